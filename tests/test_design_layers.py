"""The designer's renders at any size and view, and the layers of a gesture
(``POST /api/layers``), through its real HTTP server: the view's frame against
an in-process render of the same view, the base against the frame of the ops
below, the map of the ops above against the float64 reference's inverse walk
(marblevideo.reference), and refusals in one line."""

from __future__ import annotations

import json
import struct
import urllib.error
import urllib.request

import numpy as np
import pytest
from live_helpers import LiveProcess

from marblevideo.marbler import Marbler
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference.walk import inverse_walk

pytestmark = pytest.mark.tier("integration")

RECIPE = {
    "marblevideo": 1,
    "canvas": [320, 240],
    "background": "#f4f1de",
    "ops": [
        {"type": "drop", "center": [160, 120], "radius": 60, "color": "#1d3557"},
        {"type": "comb", "point": [0, 0], "angle": 90, "spacing": 40, "alpha": 30, "lambda": 8},
        {"type": "drop", "center": [100, 90], "radius": 30, "color": "#e63946"},
        {"type": "vortex", "center": [170, 130], "alpha": 90, "lambda": 50},
    ],
}
W, H, VIEW, T = 300, 200, (40.0, 30.0, 210.0, 140.0), 1.0


@pytest.fixture(scope="module")
def app(tmp_path_factory):
    folder = tmp_path_factory.mktemp("layers")
    (folder / "r.json").write_text(json.dumps(RECIPE))
    proc = LiveProcess(
        "--ops", folder / "r.json", "--no-browser", "--port", "0", "--duration", "120",
        cwd=folder, command="design",
    )  # fmt: skip
    yield proc
    assert proc.stop() == 0


def post(app, path: str, doc) -> bytes:
    request = urllib.request.Request(
        app.url.rstrip("/") + path,
        data=json.dumps(doc).encode(),
        headers={"Content-Type": "application/json"},
    )
    return urllib.request.urlopen(request, timeout=60).read()


def query(**more) -> str:
    view = ",".join(map(str, VIEW))
    return "&".join(
        [f"t={T}", f"w={W}", f"h={H}", f"view={view}"] + [f"{k}={v}" for k, v in more.items()]
    )


def test_a_frame_of_any_size_and_view_is_the_renderers(app, renderer):
    raw = post(app, f"/api/frame.rgba?{query()}", RECIPE)
    assert struct.unpack("<II", raw[:8]) == (W, H)
    got = np.frombuffer(raw[8:], np.uint8).reshape(H, W, 4)
    want = Marbler(RECIPE, renderer).render(None, T, (W, H), VIEW)
    assert np.abs(got.astype(int) - want).max() <= 1


def test_layers_are_the_ops_below_and_the_map_of_the_ops_above(app):
    k = 1
    raw = post(app, f"/api/layers?{query(k=k)}", RECIPE)
    w, h, kk, has_above = struct.unpack("<IIII", raw[:16])
    assert (w, h, kk, has_above) == (W, H, k, 1)
    n = w * h * 4
    base = np.frombuffer(raw[16 : 16 + n], np.uint8).reshape(h, w, 4)
    above = np.frombuffer(raw[16 + n :], np.float32).reshape(h, w, 4)
    below = {**RECIPE, "ops": RECIPE["ops"][:k]}
    frame = post(app, f"/api/frame.rgba?{query()}", below)
    assert np.array_equal(base, np.frombuffer(frame[8:], np.uint8).reshape(h, w, 4))
    # the map: the reference's inverse walk of the ops above k from each pixel centre
    spec = parse_recipe({**RECIPE, "ops": RECIPE["ops"][k + 1 :]}).at(T, (320, 240))
    sx, sy, ox, oy = geometry((320, 240), (W, H), None, VIEW).to_canvas
    ys, xs = np.mgrid[0:H, 0:W] + 0.5
    px, py, ink = inverse_walk(spec, xs * sx + ox, ys * sy + oy)
    on_ink = above[..., 3] < 0
    assert np.mean(on_ink == (ink >= 0)) > 0.999
    assert 0.05 < np.mean(on_ink) < 0.5  # the red drop and what the vortex made of it
    both = ~on_ink & (ink < 0)
    assert np.abs(above[both, 0] - px[both]).max() < 0.01
    assert np.abs(above[both, 1] - py[both]).max() < 0.01
    red = on_ink & (ink >= 0)
    assert np.allclose(above[red, :3], np.array([230, 57, 70]) / 255)
    # the top op has nothing above it: the base only
    raw = post(app, f"/api/layers?{query(k=3)}", RECIPE)
    assert struct.unpack("<IIII", raw[:16])[3] == 0 and len(raw) == 16 + n


@pytest.mark.parametrize(
    ("path", "fault"),
    [
        (f"/api/layers?{query(k=9)}", "k: expected an op index 0..4"),
        (f"/api/layers?{query()}", "k: expected an op index 0..4"),
        ("/api/frame.rgba?view=1,2,0,4", "view: expected x,y,w,h (finite, w and h > 0)"),
        ("/api/frame.rgba?view=a,b", "view: expected x,y,w,h in canvas units"),
        ("/api/frame.rgba?w=100&h=0", "w, h: expected 1.."),
    ],
)
def test_bad_requests_are_refused_in_one_line(app, path, fault):
    with pytest.raises(urllib.error.HTTPError) as exc:
        post(app, path, RECIPE)
    assert exc.value.code == 400
    error = json.loads(exc.value.read())["error"]
    assert error.startswith(fault) and "\n" not in error, error
