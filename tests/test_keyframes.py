"""Keyframe tracks and eases against the contract's definitions."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

from marblevideo.recipe.keyframes import BEZIERS, EASE_NAMES, Key, Track, cubic_bezier, ease

pytestmark = pytest.mark.tier("fast")


def brute_bezier(x1: float, y1: float, x2: float, y2: float, u: float) -> float:
    """y at x = u by exact rational bisection on the monotonic x(s), 120 halvings."""
    x1, y1, x2, y2, u = map(Fraction, (x1, y1, x2, y2, float(u)))

    def bez(p1: Fraction, p2: Fraction, s: Fraction) -> Fraction:
        return 3 * (1 - s) ** 2 * s * p1 + 3 * (1 - s) * s**2 * p2 + s**3

    lo, hi = Fraction(0), Fraction(1)
    for _ in range(120):
        mid = (lo + hi) / 2
        lo, hi = (mid, hi) if bez(x1, x2, mid) < u else (lo, mid)
    return float(bez(y1, y2, (lo + hi) / 2))


def track(*keys: tuple) -> Track:
    """Scalar track from (t, v[, ease]) tuples."""
    return Track(tuple(Key(k[0], (float(k[1]),), *k[2:]) for k in keys), scalar=True)


def test_named_beziers_are_the_css_ones():
    assert BEZIERS["ease-in"] == (0.42, 0.0, 1.0, 1.0)
    assert BEZIERS["ease-out"] == (0.0, 0.0, 0.58, 1.0)
    assert BEZIERS["ease-in-out"] == (0.42, 0.0, 0.58, 1.0)
    assert EASE_NAMES == ("linear", "hold", "ease-in", "ease-out", "ease-in-out")


@pytest.mark.parametrize("name", ["ease-in", "ease-out", "ease-in-out"])
@pytest.mark.parametrize("u", [0.0, 0.01, 0.25, 0.5, 0.73, 0.999, 1.0])
def test_named_eases_match_brute_force(name, u):
    assert ease(name, u) == pytest.approx(brute_bezier(*BEZIERS[name], u), abs=1e-10)


@given(
    x1=st.floats(0, 1),
    y1=st.floats(-2, 3),
    x2=st.floats(0, 1),
    y2=st.floats(-2, 3),
    # Within ~1e-9 of u = 1 a curve flat there (x1 = x2 = 1) is ill-conditioned in float64:
    # x(s) = 1 - (1 - s)^3 cannot resolve s better than the cube root of the rounding.
    u=st.floats(0, 1 - 1e-9),
)
def test_cubic_bezier_matches_brute_force(x1, y1, x2, y2, u):
    expected = brute_bezier(x1, y1, x2, y2, u)
    assert cubic_bezier(x1, y1, x2, y2, u) == pytest.approx(expected, abs=1e-8)


def test_cubic_bezier_hard_cases_and_arrays():
    # Flat x'(s) at both ends: Newton stalls there, bisection must finish the job.
    u = np.linspace(0, 1, 101)
    for curve in [(1, 0, 0, 1), (0, 1, 1, 0), (1, -1, 1, 2), (0, 0, 0, 0), (1, 1, 1, 1)]:
        got = cubic_bezier(*curve, u)
        assert isinstance(got, np.ndarray) and got.shape == u.shape
        expected = [brute_bezier(*curve, x) for x in u]
        np.testing.assert_allclose(got, expected, atol=1e-9)
    # x = s^3 is flat at 0 while y is not: s = 1e-4, not 1e-12.
    assert cubic_bezier(0, 0, 0, 1, 1e-12) == pytest.approx(brute_bezier(0, 0, 0, 1, 1e-12))
    assert cubic_bezier(0.25, 0.1, 0.25, 1.0, 0.0) == 0.0
    assert cubic_bezier(0.25, 0.1, 0.25, 1.0, 1.0) == pytest.approx(1.0)
    assert isinstance(cubic_bezier(0.25, 0.1, 0.25, 1.0, 0.5), float)


def test_linear_and_hold_eases():
    assert ease("linear", 0.3) == 0.3
    assert ease("hold", 0.0) == 0.0 and ease("hold", 0.999) == 0.0 and ease("hold", 1.0) == 1.0
    np.testing.assert_array_equal(ease("hold", np.array([0.0, 0.5, 1.0])), [0.0, 0.0, 1.0])
    assert ease((0.0, 0.0, 1.0, 1.0), 0.3) == pytest.approx(0.3)


def test_constant_track():
    c = Track.constant(4.0)
    assert c.at(-10) == 4.0 and c.at(1e6) == 4.0 and c.key_times == ()
    p = Track.constant((1.0, 2.0))
    assert p.at(3) == (1.0, 2.0) and p.key_times == ()


def test_keyed_track_linear_before_between_at_after():
    tr = track((1.0, 10.0), (3.0, 30.0), (4.0, 0.0))
    assert tr.key_times == (1.0, 3.0, 4.0)
    assert tr.at(0.0) == 10.0  # before the first key: first value
    assert tr.at(1.0) == 10.0
    assert tr.at(2.0) == pytest.approx(20.0)
    assert tr.at(3.0) == 30.0
    assert tr.at(3.5) == pytest.approx(15.0)
    assert tr.at(4.0) == 0.0
    assert tr.at(99.0) == 0.0  # after the last: last value
    assert isinstance(tr.at(2.0), float)


def test_single_key_track():
    tr = track((2.0, 5.0))
    assert tr.at(0) == 5.0 and tr.at(2) == 5.0 and tr.at(9) == 5.0 and tr.key_times == (2.0,)


def test_hold_keeps_value_until_next_key():
    tr = track((0.0, 1.0, "hold"), (2.0, 5.0), (4.0, 9.0))
    assert tr.at(0.0) == 1.0
    assert tr.at(1.999) == 1.0
    assert tr.at(2.0) == 5.0
    assert tr.at(3.0) == pytest.approx(7.0)  # ease of key 1 (linear) shapes 2..4


@pytest.mark.parametrize("spec", ["ease-in", "ease-out", "ease-in-out", (0.1, 0.7, 0.2, 1.3)])
def test_ease_shapes_the_segment_leaving_its_key(spec):
    curve = BEZIERS[spec] if isinstance(spec, str) else spec
    tr = track((0.0, 0.0), (1.0, 10.0, spec), (3.0, 20.0))
    assert tr.at(0.5) == pytest.approx(5.0)  # key 0 is linear
    for t in (1.0, 1.3, 2.0, 2.9, 3.0):
        u = (t - 1.0) / 2.0
        assert tr.at(t) == pytest.approx(10.0 + 10.0 * brute_bezier(*curve, u), abs=1e-8)


def test_points_and_colors_interpolate_per_component():
    pts = Track((Key(0.0, (0.0, 100.0)), Key(2.0, (10.0, 0.0), "ease-in")), scalar=False)
    assert pts.at(1.0) == pytest.approx((5.0, 50.0))
    # The ease applies to each component alike.
    pts = Track((Key(0.0, (0.0, 100.0), "ease-in"), Key(2.0, (10.0, 0.0))), scalar=False)
    w = brute_bezier(*BEZIERS["ease-in"], 0.5)
    assert pts.at(1.0) == pytest.approx((10.0 * w, 100.0 - 100.0 * w))
    col = Track((Key(0.0, (0.0, 255.0, 10.0)), Key(1.0, (255.0, 0.0, 10.0))), scalar=False)
    assert col.at(0.25) == pytest.approx((63.75, 191.25, 10.0))
    assert len(col.at(0.25)) == 3


@given(st.floats(-10, 10))
def test_linear_track_stays_between_neighbouring_values(t):
    tr = track((-1.0, 3.0), (2.0, -7.0))
    assert -7.0 - 1e-12 <= tr.at(t) <= 3.0 + 1e-12
    assert math.isfinite(tr.at(t))
