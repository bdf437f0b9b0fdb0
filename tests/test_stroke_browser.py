"""The designer's stroke tools driven by the mouse in a real headless
Chromium over samples/coffee.jpg (a 400x300 canvas shown at 4/3 in the 600x400
frame): a drag along an S with the stroke tool adds one stroke whose points
follow the drag within 2 px, with the times it was drawn at, and carries the
ink along it, undo removes it, a path point is a handle, the comb stroke has
tines and a click with the curl tool draws a small loop. Skipped, with the
reason, without Playwright or Chromium."""

from __future__ import annotations

import math

import numpy as np
import pytest
from live_helpers import INK, drag, frames, settled, wait_for

pytestmark = pytest.mark.tier("integration")

#: The S drawn, in frame pixels: through the drop at (300, 200) at its middle.
S = [(220 + 160 * u, 200 - 70 * math.sin(2 * math.pi * u)) for u in np.linspace(0, 1, 41)]


def ink_near(page, points) -> int:
    """How many sheet pixels within 5 frame pixels of ``points`` (frame pixels)
    show the ink colour."""
    return page.evaluate(
        """([pts, ink]) => {
            const img = designer.sheetPixels();  // whichever canvas shows the sheet
            const sc = img.width / designer.state.info.size[0], r = Math.round(5 * sc);
            let n = 0;
            for (const [x, y] of pts) {  // the sheet has device pixels: the frame scaled by sc
                const x0 = Math.round(x * sc) - r, y0 = Math.round(y * sc) - r;
                for (let y = Math.max(0, y0); y <= Math.min(img.height - 1, y0 + 2 * r); y++)
                for (let x = Math.max(0, x0); x <= Math.min(img.width - 1, x0 + 2 * r); x++) {
                    const d = img.data, k = 4 * (y * img.width + x);
                    const hex = '#' + [d[k], d[k + 1], d[k + 2]]
                        .map((v) => v.toString(16).padStart(2, '0')).join('');
                    if (hex === ink) n++;
                }
            }
            return n;
        }""",
        [[list(p) for p in points], INK],
    )


def segment_distance(p, a, b) -> float:
    p, a, b = (np.asarray(v, float) for v in (p, a, b))
    ab = b - a
    u = np.clip(np.dot(p - a, ab) / max(np.dot(ab, ab), 1e-12), 0, 1)
    return float(np.linalg.norm(p - (a + u * ab)))


def test_stroke_comb_stroke_curl_handles_and_undo(coffee_designer):
    d = coffee_designer
    page, errors, saved, client = d.page, d.errors, d.saved, d.client
    s, dx, dy = d.s, d.dx, d.dy

    def frame(q) -> tuple[float, float]:
        return q[0] * s + dx, q[1] * s + dy

    page.mouse.click(*client(300, 200))  # a drop of ink where the S will pass
    drop = wait_for(saved, "the drop is saved")
    tail = S[28:38]  # the S after the drop, where the stylus carries its ink
    settled(page, 0, ops=drop)
    assert ink_near(page, tail) == 0

    # the stroke tool: the S, one stroke along it, the ink carried along
    page.click("#tool-stroke")
    n = frames(page)
    page.mouse.move(*client(*S[0]))
    page.mouse.down()
    for p in S[1:]:
        page.mouse.move(*client(*p))
    page.mouse.up()
    ops = wait_for(lambda: len(saved()) == 2 and saved(), "the stroke is saved")
    stroke = ops[1]
    assert stroke["type"] == "stroke" and stroke["drag"] == 1 and "tines" not in stroke
    path = [frame(q) for q in stroke["points"]]
    assert len(path) == len(S)  # each move a point (it moved a device pixel or more)
    times = stroke["times"]  # drawn in time: one per point, from the time shown at the press
    assert len(times) == len(S) and times[0] == 0 and times == sorted(times) and times[-1] > 0
    for p in S:
        assert (
            min(segment_distance(p, a, b) for a, b in zip(path[:-1], path[1:], strict=True)) <= 2.0
        ), p
    settled(page, n, ops=ops)
    assert ink_near(page, tail) > 20

    # a point of the path is a handle: dragged, that point moves
    first = frame(stroke["points"][0])
    page.keyboard.down("Alt")  # Alt-drag: a handle moves (a plain drag would draw)
    drag(page, client, first, (first[0] - 30, first[1] + 20))
    page.keyboard.up("Alt")
    wait_for(lambda: saved()[1]["points"][0] != stroke["points"][0], "the handle moved")
    moved = frame(saved()[1]["points"][0])
    assert math.dist(moved, (first[0] - 30, first[1] + 20)) <= 1.5
    assert saved()[1]["points"][1:] == stroke["points"][1:]

    # undo twice: the handle's move, then the stroke; the ink is back in its drop
    n = frames(page)
    page.click("#undo")
    wait_for(lambda: saved() == ops, "the handle's move undone")
    page.click("#undo")
    wait_for(lambda: saved() == drop, "the stroke undone")
    settled(page, n, ops=drop)
    assert ink_near(page, tail) == 0

    # the comb stroke: the same gesture with tines, 5 by default, centred
    page.click("#tool-comb-stroke")
    page.fill("#stroke-tines", "3")
    page.fill("#stroke-spacing", "12")
    drag(page, client, (200, 320), (420, 330))
    comb = wait_for(lambda: len(saved()) == 2 and saved()[1], "the comb stroke is saved")
    assert comb["type"] == "stroke" and comb["tines"] == [-12, 0, 12]
    assert len(comb["times"]) == len(comb["points"])  # drawn in time too

    # the curl: a click draws a small loop about the point clicked
    page.click("#tool-curl")
    page.mouse.click(*client(450, 120))
    curl = wait_for(lambda: len(saved()) == 3 and saved()[2], "the curl is saved")
    centre = ((450 - dx) / s, (120 - dy) / s)
    radii = [math.dist(q, centre) for q in curl["points"]]
    assert curl["type"] == "stroke" and len(curl["points"]) > 20
    assert "times" not in curl  # not drawn: it appears whole
    assert max(radii) - min(radii) < 0.2 and abs(radii[0] - 10) < 0.2  # side / 30
    assert errors == []
