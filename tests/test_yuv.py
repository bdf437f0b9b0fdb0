"""YUV 4:2:0 frames: the matrices, the NumPy reference against swscale, the device
conversions against the reference, and the video pipeline's I420 path."""

from __future__ import annotations

import av
import numpy as np
import pytest
from clips import picture, probe, write_clip

from marblevideo.api import Marbler
from marblevideo.frame import geometry
from marblevideo.recipe import parse_recipe
from marblevideo.video import VideoOptions, transcode
from marblevideo.yuv import YuvMatrix, i420_to_rgba, rgba_to_i420

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
    assert diff.max() <= 3 and diff.mean() < 1.5


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
    assert diff[64:].max() <= 2  # chroma filters differ slightly on gradients


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
@pytest.mark.parametrize("pair", [(0, 0), (1, 2)], ids=["601", "709-to-2020full"])
def test_device_conversions_match_the_reference(renderer, size, pair):
    """render_i420 == encode(render(decode(frame))) on the reference's conversions,
    on a fresh walk and then from the table of reused maps."""
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
        assert diff.max() <= 1 and (diff > 0).mean() < 1e-3
    assert renderer.last_reused


def test_device_conversion_of_an_empty_recipe_is_the_input(renderer):
    planes = frame_of(photo_like(64, 32), MATRICES[1])
    recipe = parse_recipe({"marblevideo": 1, "antialias": "none", "ops": []}, "t.json")
    geom = geometry((64, 32), (64, 32), (64, 32))
    out = renderer.render_i420(recipe.at(0, (64, 32)), geom, planes, MATRICES[1], MATRICES[1])
    diff = np.abs(out.astype(int) - planes)
    assert diff.max() <= 2 and diff.mean() < 0.5  # one decode and encode


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
    """The same marbling without an i420 method: the pipeline's swscale path."""

    def __init__(self, transform):
        self.transform = transform

    def __call__(self, rgba, t):
        return self.transform(rgba, t)


_LOSSLESS = {"crf": 0, "preset": "ultrafast", "quiet": True}  # x264 crf 0: lossless


def _lossless(**extra) -> VideoOptions:
    return VideoOptions(**_LOSSLESS, **extra)


def test_pipeline_marbles_i420_frames_like_the_rgba_path(tmp_path):
    clip = write_clip(tmp_path / "in.mp4", size=(96, 64), frames=6, audio=True)
    transform = Marbler(RECIPE).transform()
    fast = transcode(clip, tmp_path / "fast.mp4", transform, _lossless())
    slow = transcode(clip, tmp_path / "slow.mp4", RgbaOnly(transform), _lossless())
    assert fast.i420_frames == fast.frames == 6 and slow.i420_frames == 0
    a, b = probe(tmp_path / "fast.mp4"), probe(tmp_path / "slow.mp4")
    assert a.pts == b.pts and a.audio_packets == b.audio_packets
    for x, y in zip(a.frames, b.frames, strict=True):
        diff = np.abs(x.astype(int) - y)
        # swscale decodes a level or two darker and filters chroma differently
        assert diff.mean() < 2.0 and np.percentile(diff, 99) <= 8


def test_pipeline_keeps_full_range_on_the_i420_path(tmp_path):
    clip = write_clip(tmp_path / "full.mkv", color_range=2, audio=False, frames=3)
    identity = parse_recipe({"marblevideo": 1, "antialias": "none", "ops": []}, "t.json")
    stats = transcode(clip, tmp_path / "out.mkv", Marbler(identity).transform(), _lossless())
    assert stats.i420_frames == 3
    out = probe(tmp_path / "out.mkv")
    assert out.color_range == 2
    assert np.abs(out.frames[1].astype(int) - picture(1, 96, 64)).mean() < 4


@pytest.mark.parametrize(
    "case",
    ["rotated", "odd-size", "yuv444p-output", "odd-output-size"],
)
def test_pipeline_falls_back_to_rgba_where_i420_cannot_go(tmp_path, case):
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
    transform = Marbler(RECIPE).transform(options.get("size"))
    stats = transcode(clip, tmp_path / "out.mp4", transform, _lossless(**options))
    assert stats.frames == 3 and stats.i420_frames == 0


@pytest.mark.parametrize("size, planar", [((96, 64), True), ((95, 64), False)])
def test_blank_sheet_video_is_rendered_as_i420_where_it_can(tmp_path, size, planar):
    from marblevideo.api import render_video

    recipe = parse_recipe({**RECIPE, "canvas": [96, 64]}, "t.json")
    dst = tmp_path / "blank.mp4"
    stats = render_video(None, recipe, dst, duration=0.3, fps=10, size=size, **_LOSSLESS)
    assert stats.frames == 3 and stats.i420_frames == (3 if planar else 0)
    if planar:
        marbler = Marbler(recipe)
        with av.open(str(dst)) as container:
            for i, frame in enumerate(container.decode(video=0)):
                want = rgba_to_i420(marbler.render(None, i / 10, size), MATRICES[0])
                assert np.abs(frame.to_ndarray().astype(int) - want).max() <= 1
