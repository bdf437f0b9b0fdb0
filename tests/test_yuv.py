"""YUV 4:2:0 frames: the matrices, the NumPy reference against swscale, the device
conversions against the reference, and the video pipeline's I420 path."""

from __future__ import annotations

import av
import numpy as np
import pytest
from clips import picture, probe, write_clip
from helpers import fresh_renderer
from tolerances import (
    LOSSY_MEAN,
    PLANAR_DIFFERING,
    PLANAR_MAX,
    SWSCALE_CHROMA_MAX,
    SWSCALE_MAX,
    SWSCALE_MEAN,
)

from marblevideo.jobs.pipeline import render_sheet, transcode
from marblevideo.jobs.route import SHEET_MATRIX, sheet_route, video_route
from marblevideo.jobs.transforms import PipelinedSource, PipelinedTransform, pipelined
from marblevideo.marbler import Marbler
from marblevideo.media.encode import plan_output
from marblevideo.media.video import VideoOptions
from marblevideo.media.yuv import YuvMatrix, packed_i420, split_i420
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.recipe.geometry import chroma_geometry, coded_spec
from marblevideo.reference import render as reference_render
from marblevideo.reference.yuv import i420_to_rgba, render_planes, rgba_to_i420

pytestmark = pytest.mark.tier("fast")

MATRICES = [
    YuvMatrix.of(2, 0),  # unspecified: BT.601, limited
    YuvMatrix.of(1, 1),  # BT.709, limited
    YuvMatrix.of(9, 2),  # BT.2020, full
    YuvMatrix.of(5, 2, "yuvj420p"),
]


def photo_like(w: int, h: int, seed: int = 0) -> np.ndarray:
    """Smooth gradients, a hard-edged disc and some noise: RGBA."""
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    img = np.empty((h, w, 4), np.uint8)
    img[..., 0] = 255 * xx / max(w - 1, 1)
    img[..., 1] = 255 * yy / max(h - 1, 1)
    img[..., 2] = 128 + 100 * np.sin(xx / 7.0) * np.cos(yy / 5.0)
    disc = (xx - w / 3) ** 2 + (yy - h / 2) ** 2 < (min(w, h) / 4) ** 2
    img[disc, :3] = (230, 40, 60)
    noisy = rng.integers(-20, 21, (h, w, 3))
    img[..., :3] = np.clip(img[..., :3].astype(int) + noisy * (xx[..., None] > w / 2), 0, 255)
    img[..., 3] = 255
    return img


def frame_of(rgba: np.ndarray, matrix: YuvMatrix) -> np.ndarray:
    """An I420 frame made by the reference (so every value is a real video value)."""
    return rgba_to_i420(rgba, matrix)


# ---------------------------------------------------------------------------- matrices


def test_matrix_choice_follows_the_tags():
    assert YuvMatrix.of(None, None) == YuvMatrix("bt601", 0.299, 0.114, False)
    assert YuvMatrix.of(1, 1).name == "bt709" and not YuvMatrix.of(1, 1).full
    assert YuvMatrix.of(1, 2).full and YuvMatrix.of(6, 0, "yuvj420p").full
    assert YuvMatrix.of(9, 0).name == "bt2020nc"
    for unsupported in (0, 8, 10, 14):  # RGB, YCgCo, BT.2020 CL, ICtCp
        assert YuvMatrix.of(unsupported, 1) is None


@pytest.mark.parametrize("matrix", MATRICES, ids=lambda m: f"{m.name}-{m.full}")
def test_matrices_are_inverse_and_keep_the_ranges(matrix):
    rgb = np.stack(np.meshgrid(*[np.arange(0, 256, 15)] * 3), -1).reshape(-1, 3).T
    yuv = matrix.to_yuv()[:, :3] @ rgb + matrix.to_yuv()[:, 3:]
    back = matrix.to_rgb()[:, :3] @ yuv + matrix.to_rgb()[:, 3:]
    assert np.abs(back - rgb).max() < 1e-3
    lo, hi = (0, 255) if matrix.full else (16, 235)
    assert yuv[0].min() == pytest.approx(lo, abs=1e-3)
    assert yuv[0].max() == pytest.approx(hi, abs=1e-3)
    assert yuv[1:].min() >= (0 if matrix.full else 16) - 1e-3
    assert yuv[1:].max() <= (255.5 if matrix.full else 240) + 1e-3  # JFIF: 255.5, clamped
    grey = matrix.to_yuv() @ np.array([100.0, 100.0, 100.0, 1.0])
    assert grey[1:] == pytest.approx([128, 128], abs=1e-3)


def test_round_trip_through_i420_keeps_flat_colours():
    rgba = np.zeros((8, 8, 4), np.uint8)
    rgba[..., :3] = (200, 120, 40)
    rgba[..., 3] = 255
    for matrix in MATRICES:
        back = i420_to_rgba(rgba_to_i420(rgba, matrix), matrix)
        assert np.abs(back.astype(int) - rgba).max() <= 2


def test_odd_sizes_are_refused():
    with pytest.raises(ValueError, match="even"):
        rgba_to_i420(np.zeros((5, 4, 4), np.uint8), MATRICES[0])


# ---------------------------------------------------------------------------- against swscale


@pytest.mark.parametrize("tags", [(2, 0), (1, 1), (1, 2)], ids=["601", "709", "709-full"])
def test_reference_decode_matches_swscale(tags):
    matrix = YuvMatrix.of(*tags)
    planes = frame_of(photo_like(96, 64), matrix)
    frame = av.VideoFrame.from_ndarray(planes, format="yuv420p")
    theirs = frame.to_ndarray(format="rgba", src_colorspace=tags[0], src_color_range=tags[1])
    ours = i420_to_rgba(planes, matrix)
    diff = np.abs(ours.astype(int) - theirs)[..., :3]
    # swscale's fast path rounds with less precision (a bias of about one level)
    assert diff.max() <= SWSCALE_MAX and diff.mean() < SWSCALE_MEAN


@pytest.mark.parametrize("tags", [(2, 0), (1, 1), (1, 2)], ids=["601", "709", "709-full"])
def test_reference_encode_matches_swscale(tags):
    matrix = YuvMatrix.of(*tags)
    yy, xx = np.mgrid[0:64, 0:96]
    smooth = np.stack([xx * 2.5, yy * 3.5, 200 - xx - yy, np.full_like(xx, 255)], -1)
    smooth = smooth.astype(np.uint8)
    theirs = (
        av.VideoFrame.from_ndarray(smooth, format="rgba")
        .reformat(format="yuv420p", dst_colorspace=tags[0], dst_color_range=tags[1])
        .to_ndarray()
    )
    ours = rgba_to_i420(smooth, matrix)
    diff = np.abs(ours.astype(int) - theirs)
    assert diff[:64].max() <= 1  # luma
    assert diff[64:].max() <= SWSCALE_CHROMA_MAX  # chroma filters differ on gradients


# ---------------------------------------------------------------------------- the device


RECIPE = {
    "marblevideo": 1,
    "ops": [
        {"type": "drop", "center": [40, 30], "radius": 12, "color": "#2a9d8f"},
        {"type": "wave", "amplitude": 6, "wavelength": 40, "phase": 10, "angle": 20},
        {"type": "vortex", "center": [50, 32], "alpha": 60, "lambda": 20},
    ],
}


@pytest.mark.parametrize("size", [(96, 64), (138, 46)], ids=["whole-runs", "row-tails"])
@pytest.mark.parametrize("pair", [(0, 1), (1, 2)], ids=["601-to-709", "709-to-2020full"])
def test_device_conversions_match_the_reference(renderer, size, pair):
    """Between two matrices, render_i420 == encode(render(decode(frame))) on the
    reference's conversions, on a fresh walk and then from the table of reused maps."""
    src, dst = MATRICES[pair[0]], MATRICES[pair[1]]
    w, h = size
    planes = frame_of(photo_like(w, h), src)
    recipe = parse_recipe(RECIPE, "t.json")
    spec, geom = recipe.at(0, (w, h)), geometry((w, h), (w, h), (w, h))
    expected = rgba_to_i420(renderer.render(spec, geom, i420_to_rgba(planes, src)), dst)
    for _ in range(3):
        ours = renderer.render_i420(spec, geom, planes, src, dst)
        assert ours.shape == (h * 3 // 2, w) and ours.dtype == np.uint8
        diff = np.abs(ours.astype(int) - expected)
        assert diff.max() <= PLANAR_MAX and (diff > 0).mean() < PLANAR_DIFFERING
    assert renderer.last_reused


def test_device_conversion_of_an_empty_recipe_is_the_input(renderer):
    planes = frame_of(photo_like(64, 32), MATRICES[1])
    recipe = parse_recipe({"marblevideo": 1, "antialias": "none", "ops": []}, "t.json")
    geom = geometry((64, 32), (64, 32), (64, 32))
    out = renderer.render_i420(recipe.at(0, (64, 32)), geom, planes, MATRICES[1], MATRICES[1])
    assert np.array_equal(out, planes)  # planar: no conversion at all
    out = renderer.render_i420(recipe.at(0, (64, 32)), geom, planes, MATRICES[1], MATRICES[0])
    back = rgba_to_i420(i420_to_rgba(planes, MATRICES[1]), MATRICES[0])
    assert np.abs(out.astype(int) - back).max() <= 1  # one decode and encode


# ---------------------------------------------------------------------------- planar frames


def test_coded_spec_holds_the_codes_of_the_colours():
    recipe = parse_recipe(
        {**RECIPE, "background": "#ffffff", "ops": [{**RECIPE["ops"][0], "color": "#000000"}]},
        "t.json",
    )
    spec = recipe.at(0, (96, 64))
    limited, full = coded_spec(spec, MATRICES[1]), coded_spec(spec, MATRICES[2])
    assert limited.background == (235.0, 128.0, 128.0) and full.background == (255.0, 128.0, 128.0)
    assert limited.ops[0]["color"] == (16.0, 128.0, 128.0) and full.ops[0]["color"][0] == 0.0
    red = parse_recipe({**RECIPE, "background": "#ff0000"}, "t.json").at(0, (96, 64))
    red = coded_spec(red, MATRICES[1])
    assert red.background == (63.0, 102.0, 240.0)  # BT.709 limited: Y 63, Cb 102, Cr 240
    assert spec.ops[1:] == coded_spec(spec, MATRICES[1]).ops[1:]  # no colour, unchanged


def test_reference_planar_luma_is_the_rgba_paths_luma():
    """Warping the planes is warping the picture: the luma of render_planes is the
    luma of decode -> render -> encode, up to that path's rounding of the RGB to 8
    bits and its clamping where decoded chroma leaves the RGB cube."""
    planes = frame_of(photo_like(96, 64), MATRICES[1])
    spec = parse_recipe(RECIPE, "t.json").at(0, (96, 64))
    geom = geometry((96, 64), (96, 64), (96, 64))
    planar = render_planes(spec, geom, planes, MATRICES[1])
    rgba = reference_render(spec, geom, i420_to_rgba(planes, MATRICES[1]))
    via_rgb = rgba_to_i420(rgba, MATRICES[1])
    diff = np.abs(planar.astype(int) - via_rgb)
    assert diff[:64].max() <= 3 and np.percentile(diff[:64], 99) <= 1
    # chroma: sampled at chroma resolution rather than averaged from RGBA pixels
    assert np.median(diff[64:]) <= 1 and diff[64:].max() > 0


def test_chroma_geometry_centres_chroma_samples_on_2x2_luma_pixels():
    geom = geometry((200, 100), (96, 64), (80, 40))
    half = chroma_geometry(geom)
    assert (half.out_w, half.out_h) == (48, 32)
    kx, _, tx, _ = geom.to_canvas
    hx, _, htx, _ = half.to_canvas
    assert (0.5 * hx + htx) == pytest.approx(1.0 * kx + tx)  # chroma 0 centre = luma x 1
    sx, _, ox, _ = geom.to_input
    hsx, _, hox, _ = half.to_input
    assert 50 * hsx + hox == pytest.approx((50 * sx + ox) / 2)


PLANAR_CASES = [
    ("rgss", "clamp", (96, 64), (96, 64)),
    ("rgss", "repeat", (90, 62), (70, 50)),
    ("rgss", "mirror", (138, 46), (138, 46)),
    ("grid4", "background", (90, 62), (96, 64)),
    ("none", "clamp", (90, 62), (70, 50)),
]


@pytest.mark.parametrize("lanes", [None, 1], ids=["cpu-vectors", "gpu-scalar"])
@pytest.mark.parametrize("case", PLANAR_CASES, ids=lambda c: "-".join(map(str, c[:2])))
def test_device_planar_frames_match_the_reference(lanes, case):
    """Same matrix in and out: the planes are warped on the device as render_planes
    does, on a fresh walk and then from the tables of reused maps."""
    antialias, edges, in_size, out_size = case
    # fresh: the first frame walks, the next reuse its maps
    renderer = fresh_renderer(lanes=lanes, chains=1 if lanes == 1 else None)
    recipe = parse_recipe({**RECIPE, "antialias": antialias, "edges": edges}, "t.json")
    spec, geom = recipe.at(0, in_size), geometry(in_size, out_size, in_size)
    planes = frame_of(photo_like(*in_size), MATRICES[2])
    expected = render_planes(spec, geom, planes, MATRICES[2])
    reused = []
    for _ in range(3):
        ours = renderer.render_i420(spec, geom, planes, MATRICES[2], MATRICES[2])
        assert ours.shape == (out_size[1] * 3 // 2, out_size[0])
        diff = np.abs(ours.astype(int) - expected)
        assert diff.max() <= PLANAR_MAX and (diff > 0).mean() < PLANAR_DIFFERING
        reused.append(renderer.last_reused)
    assert reused == [False, True, True]
    static = fresh_renderer(lanes=lanes, chains=1 if lanes == 1 else None)
    ours = static.render_i420(spec, geom, planes, MATRICES[2], MATRICES[2], static=True)
    assert static.last_reused  # the tables from the first frame on
    assert np.abs(ours.astype(int) - expected).max() <= 1


def test_planar_frames_change_with_the_maps_and_the_picture():
    """A table holds one recipe's maps: new values or a new picture are never served
    stale, and switching between planar and converted frames keeps both right."""
    renderer = fresh_renderer()  # fresh: which frames reuse maps is checked
    size = (96, 64)
    geom = geometry(size, size, size)
    a, b = (frame_of(photo_like(*size, seed=s), MATRICES[1]) for s in (1, 2))
    recipe = parse_recipe(RECIPE, "t.json")
    specs = [
        recipe.at(0, size),
        parse_recipe({**RECIPE, "ops": RECIPE["ops"][1:]}, "t.json").at(0, size),
    ]
    for spec, planes in [(specs[0], a)] * 2 + [(specs[0], b), (specs[1], b), (specs[1], b)]:
        want = render_planes(spec, geom, planes, MATRICES[1])
        got = renderer.render_i420(spec, geom, planes, MATRICES[1], MATRICES[1])
        assert np.abs(got.astype(int) - want).max() <= 1
        converted = renderer.render_i420(spec, geom, planes, MATRICES[1], MATRICES[0])
        assert not renderer.last_reused  # the other path's maps: walked afresh
        want = rgba_to_i420(
            renderer.render(spec, geom, i420_to_rgba(planes, MATRICES[1])), MATRICES[0]
        )
        assert np.abs(converted.astype(int) - want).max() <= 1


@pytest.mark.parametrize("lanes", [None, 1], ids=["cpu-vectors", "gpu-scalar"])
@pytest.mark.parametrize("static", [False, True], ids=["walked", "static"])
def test_frames_in_flight_come_out_as_rendered_one_at_a_time(lanes, static):
    """Frames queued with wait=False before any is finished share the device's
    buffers but come out exactly as frames rendered one at a time, each from its
    own picture, whichever is finished first; so do RGBA frames and the converting
    route (another matrix out). With vectors the frames are big enough that the
    device is still at work when the last one is finished (the one-pixel GPU code
    is slow on a CPU: small frames there)."""
    size = (320, 192) if lanes == 1 else (960, 544)
    chains = 1 if lanes == 1 else None
    recipe = parse_recipe(RECIPE, "t.json")
    spec, geom = recipe.at(0, size), geometry(size, size, size)
    pictures = [frame_of(photo_like(*size, seed=s), MATRICES[1]) for s in range(4)]
    one_by_one = fresh_renderer(lanes=lanes, chains=chains)
    want = [
        one_by_one.render_i420(spec, geom, p, MATRICES[1], MATRICES[1], static=static)
        for p in pictures
    ]
    assert not all(np.array_equal(want[0], w) for w in want[1:])
    renderer = fresh_renderer(lanes=lanes, chains=chains)  # fresh: its buffers are shared
    started = [
        renderer.render_i420(spec, geom, p, MATRICES[1], MATRICES[1], static=static, wait=False)
        for p in pictures
    ]
    for finish, expected in reversed(list(zip(started, want, strict=True))):
        assert np.array_equal(finish(), expected)
    converted = renderer.render_i420(spec, geom, pictures[0], MATRICES[1], MATRICES[0], wait=False)
    want_converted = one_by_one.render_i420(spec, geom, pictures[0], MATRICES[1], MATRICES[0])
    rgba = [photo_like(*size, seed=s) for s in range(3)]
    want = [one_by_one.render(spec, geom, p, static=static) for p in rgba]
    started = [renderer.render(spec, geom, p, static=static, wait=False) for p in rgba]
    for finish, expected in reversed(list(zip(started, want, strict=True))):
        assert np.array_equal(finish(), expected)
    assert np.array_equal(converted(), want_converted)


@pytest.mark.parametrize(
    "out_size, planes_shape",
    [((95, 64), (96, 96)), ((96, 64), (95, 96)), ((96, 64), (96, 95))],
    ids=["odd-output", "rows-not-3h/2", "odd-width"],
)
def test_render_i420_refuses_odd_sizes(renderer, out_size, planes_shape):
    spec = parse_recipe(RECIPE, "t.json").at(0, (96, 64))
    geom = geometry((96, 64), out_size, (96, 64))
    with pytest.raises(ValueError, match="even"):
        renderer.render_i420(spec, geom, np.zeros(planes_shape, np.uint8), *MATRICES[:2])


# ---------------------------------------------------------------------------- the pipeline


class RgbaOnly:
    """The same marbling as a plain function: the pipeline's swscale path."""

    def __init__(self, transform):
        self.transform = transform

    def __call__(self, rgba, t):
        return self.transform(rgba, t)


_LOSSLESS = {"crf": 0, "preset": "ultrafast", "quiet": True}  # x264 crf 0: lossless


def _lossless(**extra) -> VideoOptions:
    return VideoOptions(**_LOSSLESS, **extra)


def _planes(path) -> list[np.ndarray]:
    with av.open(str(path)) as container:
        return [frame.to_ndarray() for frame in container.decode(video=0)]


def test_pipeline_marbles_i420_frames_plane_by_plane(tmp_path, renderer):
    """A yuv420p clip is warped plane by plane (render_planes on each decoded frame,
    exactly through lossless x264), with the RGBA path's luma and timing."""
    clip = write_clip(tmp_path / "in.mp4", size=(96, 64), frames=6, audio=True)
    transform = Marbler(RECIPE, renderer).transform()
    fast = transcode(clip, tmp_path / "fast.mp4", transform, _lossless())
    slow = transcode(clip, tmp_path / "slow.mp4", RgbaOnly(transform), _lossless())
    assert fast.i420_frames == fast.frames == 6 and slow.i420_frames == 0
    a, b = probe(tmp_path / "fast.mp4"), probe(tmp_path / "slow.mp4")
    assert a.pts == b.pts and a.audio_packets == b.audio_packets
    spec = parse_recipe(RECIPE, "t.json").at(0, (96, 64))
    geom = geometry((96, 64), (96, 64), (96, 64))
    inputs, planar, converted = (
        _planes(p) for p in (clip, tmp_path / "fast.mp4", tmp_path / "slow.mp4")
    )
    for frame, ours, theirs in zip(inputs, planar, converted, strict=True):
        want = render_planes(spec, geom, frame, YuvMatrix.of(None, None))
        assert np.abs(ours.astype(int) - want).max() <= 1
        luma = np.abs(ours[:64].astype(int) - theirs[:64])
        # swscale decodes a level or two darker and rounds the RGB to 8 bits
        assert luma.mean() < 2.0 and np.percentile(luma, 99) <= 4


def test_i420_planes_are_views_of_a_packed_frame_and_pack_back():
    packed = np.random.default_rng(3).integers(0, 256, (24, 8), np.uint8)
    y, u, v = split_i420(packed)
    assert y.shape == (16, 8) and u.shape == v.shape == (8, 4)
    assert all(np.shares_memory(plane, packed) for plane in (y, u, v))
    assert np.array_equal(v, packed[20:].reshape(8, 4))
    wide = np.zeros((16, 32), np.uint8)
    wide[:, :8] = y  # a plane whose rows are padded, as a decoder's are
    assert np.array_equal(packed_i420((wide[:, :8], u, v)), packed)


@pytest.mark.parametrize(
    "planes",
    [
        (np.zeros((16, 8), np.uint8), np.zeros((8, 4), np.uint8)),
        (np.zeros((16, 8), np.uint8), np.zeros((8, 5), np.uint8), np.zeros((8, 4), np.uint8)),
        (np.zeros((16, 8), np.float32), np.zeros((8, 4)), np.zeros((8, 4))),
        (np.zeros((15, 8), np.uint8), np.zeros((7, 4), np.uint8), np.zeros((7, 4), np.uint8)),
        tuple(np.zeros((n, 8 if n == 16 else 4), np.uint8)[:, ::-1] for n in (16, 8, 8)),
        None,
    ],
    ids=["two-planes", "chroma-size", "dtype", "odd-height", "reversed-rows", "none"],
)
def test_i420_planes_that_are_not_a_frame_are_refused(planes):
    with pytest.raises(ValueError, match="I420"):
        split_i420(planes)


class PlanesBack(PipelinedTransform):
    """A planar transform that returns the decoded planes as planes, in arrays of its own."""

    planar = True

    def start_rgba(self, rgba, t, route):
        return lambda: rgba

    def i420(self, planes):
        return tuple(plane.copy() for plane in planes)

    def start_i420(self, planes, t, src, route):
        result = self.i420(planes)
        return lambda: result


@pytest.mark.parametrize("size", [(128, 64), (90, 34)], ids=["packed-rows", "padded-rows"])
def test_i420_frames_cross_the_pipeline_exactly(tmp_path, size, renderer):
    """Decoded planes go to the device as they are (rows padded to the decoder's
    line size at 90 wide) and a frame is encoded on the result's own memory (PyAV
    misreads a yuv420p height that is not a multiple of 4, 34 here, so that one is
    copied): an identity recipe and a transform returning planes come out exact."""
    clip = write_clip(tmp_path / "in.mkv", size=size, frames=3, audio=False)
    with av.open(str(clip)) as container:
        first = next(container.decode(video=0))
        padded = any(plane.line_size > plane.width for plane in first.planes)
        assert padded == (size[0] == 90)
    identity = parse_recipe({"marblevideo": 1, "antialias": "none", "ops": []}, "t.json")
    marbled = Marbler(identity, renderer).transform()
    for name, transform in (("marbled", marbled), ("planes", PlanesBack())):
        stats = transcode(clip, tmp_path / f"{name}.mkv", transform, _lossless())
        assert stats.i420_frames == 3
        for a, b in zip(_planes(clip), _planes(tmp_path / f"{name}.mkv"), strict=True):
            assert np.array_equal(a, b)


class Logged:
    """Logs when each frame starts and finishes, frames numbered by start."""

    def __init__(self):
        self.log: list[tuple[str, int]] = []  # (what, frame number)
        self.times: list[float] = []

    def started(self, t: float, result):
        self.times.append(t)
        frame = len(self.times) - 1
        self.log.append(("start", frame))

        def finish():
            self.log.append(("finish", frame))
            return result

        return finish


class InFlight(Logged, PlanesBack):
    """PlanesBack, logged."""

    def start_i420(self, planes, t, src, route):
        return self.started(t, self.i420(planes))


class RgbaInFlight(Logged, PipelinedTransform):
    """An RGBA transform (not planar), logged."""

    def start_rgba(self, rgba, t, route):
        return self.started(t, 255 - rgba)


class BlankInFlight(Logged, PipelinedSource):
    """Blank frames, as render_sheet's render_at, planar, logged."""

    planar = True

    def __init__(self):
        super().__init__()
        self.planes = frame_of(photo_like(96, 64), MATRICES[0])

    def __call__(self, t):
        return i420_to_rgba(self.planes, MATRICES[0])

    def i420(self, t):
        return self.planes + int(t * 10)

    def start_i420(self, t, matrix):
        return self.started(t, self.i420(t))


#: frames n + 1 and n: started, then finished, one frame in flight
IN_FLIGHT_LOG = [("start", 0), ("start", 1), ("finish", 0), ("start", 2), ("finish", 1)]
IN_FLIGHT_LOG += [("start", 3), ("finish", 2), ("finish", 3)]


@pytest.mark.parametrize(
    "flight, alone, i420_frames",
    [(InFlight, PlanesBack, 4), (RgbaInFlight, lambda: lambda rgba, t: 255 - rgba, 0)],
    ids=["i420", "rgba"],
)
def test_pipeline_keeps_one_frame_in_flight(tmp_path, flight, alone, i420_frames):
    """A pipelined transform (planar or RGBA) has frame n + 1 started before frame
    n is finished, and the file is the one the plain call writes: frames,
    timing and audio alike."""
    clip = write_clip(tmp_path / "in.mp4", size=(96, 64), frames=4, audio=True)
    transform = flight()
    stats = transcode(clip, tmp_path / "flight.mp4", transform, _lossless())
    assert stats.i420_frames == i420_frames and transform.times == sorted(transform.times)
    assert transform.log == IN_FLIGHT_LOG
    transcode(clip, tmp_path / "one.mp4", alone(), _lossless())
    a, b = probe(tmp_path / "flight.mp4"), probe(tmp_path / "one.mp4")
    assert a.pts == b.pts and a.audio_packets == b.audio_packets
    for x, y in zip(*map(_planes, (tmp_path / "flight.mp4", tmp_path / "one.mp4")), strict=True):
        assert np.array_equal(x, y)


def test_blank_video_keeps_one_frame_in_flight(tmp_path):
    render_at = BlankInFlight()
    stats = render_sheet(tmp_path / "blank.mkv", render_at, 0.4, 10, _lossless())
    assert stats.frames == stats.i420_frames == 4 and render_at.log == IN_FLIGHT_LOG
    for i, frame in enumerate(_planes(tmp_path / "blank.mkv")):
        assert np.array_equal(frame, render_at.i420(i / 10))


class StartsBadly(PlanesBack):
    def start_i420(self, planes, t, src, route):
        return self.i420(planes)  # the frame, not a function

    def start_rgba(self, rgba, t, route):
        return rgba


@pytest.mark.parametrize("kind", ["i420", "rgba"])
def test_a_start_that_returns_no_function_is_refused(tmp_path, kind):
    clip = write_clip(tmp_path / "in.mp4", size=(96, 64), frames=2, audio=False)
    options = _lossless(pix_fmt="yuv444p") if kind == "rgba" else _lossless()
    with pytest.raises(TypeError, match=f"start_{kind} must return a function"):
        transcode(clip, tmp_path / "out.mp4", StartsBadly(), options)
    assert not (tmp_path / "out.mp4").exists()


def test_pipeline_keeps_full_range_on_the_i420_path(tmp_path, renderer):
    clip = write_clip(tmp_path / "full.mkv", color_range=2, audio=False, frames=3)
    identity = parse_recipe({"marblevideo": 1, "antialias": "none", "ops": []}, "t.json")
    transform = Marbler(identity, renderer).transform()
    stats = transcode(clip, tmp_path / "out.mkv", transform, _lossless())
    assert stats.i420_frames == 3
    out = probe(tmp_path / "out.mkv")
    assert out.color_range == 2
    assert np.abs(out.frames[1].astype(int) - picture(1, 96, 64)).mean() < LOSSY_MEAN


@pytest.mark.parametrize(
    "case",
    ["rotated", "odd-size", "yuv444p-output", "odd-output-size"],
)
def test_pipeline_falls_back_to_rgba_where_i420_cannot_go(tmp_path, case, renderer):
    size, options, clip_args = (96, 64), {}, {}
    if case == "rotated":
        clip_args["rotation"] = 90
    elif case == "odd-size":
        size, clip_args["codec"] = (95, 63), "mjpeg"
    elif case == "yuv444p-output":
        options["pix_fmt"] = "yuv444p"
    else:
        options["size"] = (81, 60)
    clip = write_clip(tmp_path / "in.mkv", size=size, frames=3, audio=False, **clip_args)
    transform = Marbler(RECIPE, renderer).transform(options.get("size"))
    stats = transcode(clip, tmp_path / "out.mp4", transform, _lossless(**options))
    assert stats.frames == 3 and stats.i420_frames == 0


@pytest.mark.parametrize("size, planar", [((96, 64), True), ((95, 64), False)])
def test_blank_sheet_video_is_rendered_as_i420_where_it_can(tmp_path, size, planar, renderer):
    from marblevideo.api import render_video

    recipe = parse_recipe({**RECIPE, "canvas": [96, 64]}, "t.json")
    dst = tmp_path / "blank.mp4"
    stats = render_video(None, recipe, dst, duration=0.3, fps=10, size=size, **_LOSSLESS)
    assert stats.frames == 3 and stats.i420_frames == (3 if planar else 0)
    if planar:
        marbler = Marbler(recipe, renderer)
        with av.open(str(dst)) as container:
            for i, frame in enumerate(container.decode(video=0)):
                want = rgba_to_i420(marbler.render(None, i / 10, size), MATRICES[0])
                assert np.abs(frame.to_ndarray().astype(int) - want).max() <= 1


def test_a_jobs_route_is_decided_once_from_transform_input_plan_and_recipe(tmp_path, renderer):
    """I420 (in the input's tags) only for a planar transform, a yuv420p output and
    an even size; a lattice only for a recipe that moves and allows it; tables for
    one that does not; a blank sheet's I420 is BT.601 limited."""
    colors = {"colorspace": 1, "color_range": 2}  # BT.709, full range
    mp4 = plan_output(tmp_path / "o.mp4", VideoOptions())
    yuv444 = plan_output(tmp_path / "o.mkv", VideoOptions(pix_fmt="yuv444p"))
    keyed = {**RECIPE["ops"][2], "alpha": {"keys": [{"t": 0, "v": 0}, {"t": 1, "v": 60}]}}
    moves = {**RECIPE, "ops": [*RECIPE["ops"][:2], keyed]}
    moving = Marbler(moves, renderer).transform()
    route = video_route(moving, colors, mp4, None)
    assert route.i420 == YuvMatrix.of(1, 2) and route.lattice and not route.static
    assert not video_route(moving, colors, mp4, (96, 63)).planar  # odd output
    assert not video_route(moving, colors, yuv444, None).planar
    assert not video_route(pipelined(lambda rgba, t: rgba), colors, mp4, None).planar
    route = video_route(Marbler(RECIPE, renderer).transform(), colors, mp4, None)
    assert route.static and not route.lattice
    exact = Marbler(moves, renderer, lattice=False).transform()
    assert not video_route(exact, colors, mp4, None).lattice
    assert sheet_route(True, True, mp4).i420 == YuvMatrix.of(None, None) == SHEET_MATRIX
    assert not sheet_route(False, True, mp4).planar and not sheet_route(True, True, yuv444).planar
