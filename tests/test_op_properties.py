"""Mathematical properties of the reference's op maps (float64).

Round trips (forward then inverse and back) and incompressibility (Jacobian
determinant 1) of every registered op type, the drop's area and annulus laws,
directions and hand-computed values of the contract's formulas. Randomness is
seeded.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from recipes import valid_registry_op

from marblevideo.ops import REGISTRY
from marblevideo.ops.shear import rake_offsets
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import OpState
from marblevideo.reference import forward, inverse, jacobian

pytestmark = pytest.mark.tier("fast")

SEEDS = range(8)
ALPHAS = (-400.0, -25.0, -0.5, 3.0, 60.0, 2500.0)  # negative, small, large
#: Every registered op type: a new op is covered by adding its definition.
TYPES = tuple(REGISTRY)
#: Op types without det J = 1, with the reason.
NOT_AREA_PRESERVING = {
    "jiggle": "a transfer effect, not area preserving (docs/recipe-format.md)",
}


def paper_op(kind: str, rng: np.random.Generator) -> OpState:
    """An op of the paper's ``kind`` with random parameters spanning the interesting ranges."""
    point = tuple(rng.uniform(-50.0, 150.0, 2))
    alpha = float(rng.choice(ALPHAS) * rng.uniform(0.5, 1.5))
    lam = float(rng.choice([0.3, 5.0, 60.0]) * rng.uniform(0.5, 1.5))
    angle = float(rng.uniform(-400.0, 400.0))
    if kind == "tine":
        return OpState(kind, {"point": point, "angle": angle, "alpha": alpha, "lambda": lam})
    if kind == "comb":
        spacing = float(rng.choice([0.7, 8.0, 45.0]) * rng.uniform(0.5, 1.5))
        values = {"point": point, "angle": angle, "spacing": spacing}
        return OpState(kind, {**values, "alpha": alpha, "lambda": lam})
    if kind == "wave":
        values = {"amplitude": alpha / 10.0, "wavelength": float(rng.uniform(3.0, 120.0))}
        return OpState(kind, {**values, "phase": float(rng.uniform(-720, 720)), "angle": angle})
    if kind == "circle":
        radius = 0.0 if rng.random() < 0.3 else float(rng.uniform(0.5, 80.0))
        values = {"center": point, "radius": radius}
        return OpState(kind, {**values, "alpha": alpha, "lambda": lam})
    if kind == "vortex":
        return OpState(kind, {"center": point, "alpha": alpha, "lambda": lam})
    radius = float(rng.choice([0.2, 10.0, 90.0]) * rng.uniform(0.5, 1.5))
    return OpState(kind, {"center": point, "radius": radius, "color": (1.0, 2.0, 3.0)})


PAPER = ("tine", "comb", "wave", "circle", "vortex", "drop")


def random_op(kind: str, rng: np.random.Generator) -> OpState:
    """A random op of any registered ``kind``: the paper's ops by their hand-made
    wide ranges, the others by the registry's parameter kinds (tests/support/recipes.py)."""
    if kind in PAPER:
        return paper_op(kind, rng)
    values = {"type": kind, **valid_registry_op(rng, kind, 160.0, 120.0)}
    recipe = parse_recipe({"canvas": [160, 120], "ops": [values]}, "op.json")
    return recipe.at(recipe.end_time()).ops[0]


def anchor(op: OpState) -> np.ndarray:
    values = op.values
    return np.array(values.get("center", values.get("point", (0.0, 0.0))), dtype=np.float64)


def random_points(op: OpState, rng: np.random.Generator, n: int = 2000) -> tuple:
    """Points near the op's anchor (within a few lambdas / radii) and far away."""
    a = anchor(op)
    near = a + rng.normal(0.0, 1.0, (n, 2)) * rng.choice([0.05, 1.0, 20.0], (n, 1))
    mid = rng.uniform(-300.0, 400.0, (n, 2))
    far = rng.uniform(-2e4, 2e4, (n, 2))
    p = np.concatenate([near, mid, far])
    return p[:, 0], p[:, 1]


def kink_distance(op: OpState, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Distance from each point to where the op's map is not smooth (inf if nowhere)."""
    v = op.values
    if op.type in ("tine", "comb"):
        a = math.radians(v["angle"])
        d = np.abs((x - v["point"][0]) * -math.sin(a) + (y - v["point"][1]) * math.cos(a))
        if op.type == "tine":
            return d
        half = v["spacing"] / 2
        m = np.mod(d, half)
        return np.minimum(m, half - m)
    if op.type == "rake":
        a = math.radians(v["angle"])
        d = (x - v["point"][0]) * -math.sin(a) + (y - v["point"][1]) * math.cos(a)
        return np.min([np.abs(d - o) for o in rake_offsets(v)], axis=0)
    if op.type in ("circle", "vortex", "drop", "stir"):
        big_r = np.hypot(x - v["center"][0], y - v["center"][1])
        if op.type == "circle":
            return np.minimum(big_r, np.abs(big_r - v["radius"]))
        if op.type == "stir":
            return np.min([big_r, *(np.abs(big_r - abs(r)) for r in v["radii"])], axis=0)
        return big_r
    return np.full(x.shape, np.inf)


def scale(x: np.ndarray, y: np.ndarray, op: OpState) -> np.ndarray:
    """Coordinate scale for relative tolerances: max(1, |P|, |anchor|)."""
    return np.maximum(np.maximum(1.0, np.hypot(x, y)), np.hypot(*anchor(op)))


@pytest.mark.parametrize("kind", TYPES)
@pytest.mark.parametrize("seed", SEEDS)
def test_forward_then_inverse_is_identity(kind: str, seed: int) -> None:
    rng = np.random.default_rng(seed)
    op = random_op(kind, rng)
    x, y = random_points(op, rng)
    if kind == "drop":  # forward is defined for every P != C
        keep = kink_distance(op, x, y) > 0
        x, y = x[keep], y[keep]
    bx, by = inverse(op, *forward(op, x, y))
    err = np.hypot(bx - x, by - y) / scale(x, y, op)
    assert err.max() < 1e-9, (op, err.max())


@pytest.mark.parametrize("kind", TYPES)
@pytest.mark.parametrize("seed", SEEDS)
def test_inverse_then_forward_is_identity(kind: str, seed: int) -> None:
    rng = np.random.default_rng(100 + seed)
    op = random_op(kind, rng)
    x, y = random_points(op, rng)
    if kind == "drop":  # the inverse is meant for points outside the drop
        keep = kink_distance(op, x, y) > op["radius"] * (1 + 1e-9)
        x, y = x[keep], y[keep]
    fx, fy = forward(op, *inverse(op, x, y))
    err = np.hypot(fx - x, fy - y) / scale(x, y, op)
    assert err.max() < 1e-9, (op, err.max())


@pytest.mark.parametrize("kind", [t for t in TYPES if t not in NOT_AREA_PRESERVING])
@pytest.mark.parametrize("seed", SEEDS)
def test_jacobian_determinant_is_one(kind: str, seed: int) -> None:
    """Every op is incompressible: det J = 1 wherever the map is smooth."""
    rng = np.random.default_rng(200 + seed)
    op = random_op(kind, rng)
    x, y = random_points(op, rng, n=300)
    # Away from kinks (a comb's are s/2 apart) and at moderate |P| (the step is relative).
    margin = min(0.5, op["spacing"] / 8) if kind == "comb" else 0.5
    keep = (np.hypot(x, y) < 500.0) & (kink_distance(op, x, y) > margin)
    x, y = x[keep], y[keep]
    assert x.size > 100
    # Where the map varies fast (a vortex winds ~alpha/R^2 per unit R) the step must shrink.
    rough = np.abs(jacobian(op, x, y, h=1e-6)).max(axis=(1, 2))
    j = jacobian(op, x, y, h=1e-6 / np.maximum(1.0, rough))
    det = np.linalg.det(j)
    # ad - bc of entries known to relative precision e is known to |J|^2 e.
    tol = 1e-6 * np.maximum(1.0, np.abs(j).max(axis=(1, 2)) ** 2)
    bad = np.abs(det - 1.0) > tol
    assert not bad.any(), (op, x[bad][:3], y[bad][:3], det[bad][:3])


def test_jacobian_tolerance_is_not_vacuous() -> None:
    """The determinant test can fail: a compressing map has det != 1 by far more than tol."""
    op = OpState("drop", {"center": (0.0, 0.0), "radius": 10.0, "color": (0, 0, 0)})
    j = jacobian(op, np.array([12.0]), np.array([5.0]))
    assert abs(np.linalg.det(j)[0] - 1.0) < 1e-6
    j[..., 0, 0] *= 1.001
    assert abs(np.linalg.det(j)[0] - 1.0) > 1e-4


def shoelace(x: np.ndarray, y: np.ndarray) -> float:
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def square(cx: float, cy: float, half: float, per_side: int) -> tuple:
    t = np.linspace(-half, half, per_side, endpoint=False)
    xs = np.concatenate([cx + t, np.full_like(t, cx + half), cx - t, np.full_like(t, cx - half)])
    ys = np.concatenate([np.full_like(t, cy - half), cy + t, np.full_like(t, cy + half), cy - t])
    return xs, ys


def circle_polygon(cx: float, cy: float, radius: float, n: int) -> tuple:
    t = np.linspace(0.0, 2 * math.pi, n, endpoint=False)
    return cx + radius * np.cos(t), cy + radius * np.sin(t)


DROP = OpState("drop", {"center": (40.0, -20.0), "radius": 15.0, "color": (0.0, 0.0, 0.0)})


@pytest.mark.parametrize(
    "polygon",
    [square(70.0, -10.0, 12.0, 5000), circle_polygon(10.0, 5.0, 9.0, 20000)],
    ids=["square", "circle"],
)
def test_drop_preserves_area_outside(polygon: tuple) -> None:
    x, y = polygon
    assert np.hypot(x - 40.0, y + 20.0).min() > 15.0  # wholly outside the drop
    before = shoelace(x, y)
    after = shoelace(*forward(DROP, x, y))
    assert after == pytest.approx(before, rel=1e-6)


def test_drop_adds_its_area_inside_an_enclosing_polygon() -> None:
    """A square around C grows by exactly the drop's area pi r^2 (the ink)."""
    x, y = square(45.0, -18.0, 30.0, 5000)
    after = shoelace(*forward(DROP, x, y))
    assert after == pytest.approx(shoelace(x, y) + math.pi * 15.0**2, rel=1e-6)


@pytest.mark.parametrize("big_r", [1e-3, 0.5, 15.0, 40.0, 1e4])
def test_drop_maps_circles_to_circles(big_r: float) -> None:
    """The annulus law: |P - C| = R goes to |P' - C| = sqrt(R^2 + r^2), same direction."""
    x, y = circle_polygon(40.0, -20.0, big_r, 64)
    fx, fy = forward(DROP, x, y)
    qx, qy = fx - 40.0, fy + 20.0
    np.testing.assert_allclose(np.hypot(qx, qy), math.hypot(big_r, 15.0), rtol=1e-12)
    np.testing.assert_allclose(np.arctan2(qy, qx), np.arctan2(y + 20.0, x - 40.0), atol=1e-12)


def test_drop_centre_and_inside_conventions() -> None:
    """Forward of C is C + (r, 0); inverse of a point inside the drop is C."""
    fx, fy = forward(DROP, 40.0, -20.0)
    assert (fx, fy) == (55.0, -20.0)
    ix, iy = inverse(DROP, [41.0, 40.0], [-19.0, -20.0])
    np.testing.assert_array_equal(ix, [40.0, 40.0])
    np.testing.assert_array_equal(iy, [-20.0, -20.0])


def test_zero_radius_drop_is_identity() -> None:
    op = OpState("drop", {"center": (1.0, 2.0), "radius": 0.0, "color": (0, 0, 0)})
    x, y = np.array([1.0, 5.0, -3.0]), np.array([2.0, 2.0, 9.0])
    for fn in (forward, inverse):
        np.testing.assert_array_equal(fn(op, x, y)[0], x)
        np.testing.assert_array_equal(fn(op, x, y)[1], y)


def test_spray_is_identity() -> None:
    op = OpState("spray", {"center": (1.0, 2.0), "radius": 5.0, "color": (0, 0, 0)})
    x, y = np.array([1.0, 5.0, -3.0]), np.array([2.0, 2.0, 9.0])
    for fn in (forward, inverse):
        np.testing.assert_array_equal(fn(op, x, y)[0], x)
        np.testing.assert_array_equal(fn(op, x, y)[1], y)


def test_tine_values_by_hand() -> None:
    """Angle 90 moves along +y (down); the shift is alpha*lambda/(d + lambda)."""
    op = OpState("tine", {"point": (10.0, 0.0), "angle": 90.0, "alpha": 6.0, "lambda": 2.0})
    x = np.array([10.0, 12.0, 8.0, 16.0])
    fx, fy = forward(op, x, np.zeros(4))
    np.testing.assert_allclose(fy, [6.0, 3.0, 3.0, 1.5], atol=1e-14)
    np.testing.assert_allclose(fx, x, atol=1e-14)


def test_comb_distance_to_nearest_tine() -> None:
    """d' = s/2 - |mod(d, s) - s/2| on both sides of the anchor tine."""
    op = OpState(
        "comb",
        {"point": (0.0, 0.0), "angle": 0.0, "spacing": 10.0, "alpha": 4.0, "lambda": 1.0},
    )
    y = np.array([0.0, 3.0, 7.0, 10.0, -3.0, 5.0, -13.0, 22.5])
    d_nearest = np.array([0.0, 3.0, 3.0, 0.0, 3.0, 5.0, 3.0, 2.5])
    fx, fy = forward(op, np.zeros_like(y), y)
    np.testing.assert_allclose(fx, 4.0 / (d_nearest + 1.0), rtol=1e-14)
    np.testing.assert_array_equal(fy, y)


def test_wave_values_by_hand() -> None:
    """v = P.(sin t, -cos t); shift = A sin(2 pi v / wavelength + phase) along (cos t, sin t)."""
    op = OpState("wave", {"amplitude": 3.0, "wavelength": 8.0, "phase": 0.0, "angle": 0.0})
    fx, fy = forward(op, [5.0, 5.0, 5.0], [-2.0, 2.0, 0.0])  # v = -y
    np.testing.assert_allclose(fx, [8.0, 2.0, 5.0], atol=1e-14)
    np.testing.assert_array_equal(fy, [-2.0, 2.0, 0.0])
    op = OpState("wave", {"amplitude": 3.0, "wavelength": 8.0, "phase": 90.0, "angle": 90.0})
    fx, fy = forward(op, [0.0, 4.0], [1.0, 1.0])  # v = x, moves along +y
    np.testing.assert_allclose(fy, [4.0, -2.0], atol=1e-14)
    np.testing.assert_allclose(fx, [0.0, 4.0], atol=1e-14)


@pytest.mark.parametrize("kind", ["circle", "vortex"])
def test_positive_alpha_turns_clockwise_on_screen(kind: str) -> None:
    """With y down, a point right of C moves down (+y) and one below C moves left."""
    values = {"center": (5.0, 5.0), "alpha": 2.0, "lambda": 3.0}
    if kind == "circle":
        values["radius"] = 4.0
    op = OpState(kind, values)
    fx, fy = forward(op, [9.0, 5.0], [5.0, 9.0])
    assert fy[0] > 5.0 and fx[1] < 5.0


def test_circle_values_by_hand() -> None:
    """On the tine circle (d = 0) the arc is alpha: theta = alpha / R."""
    op = OpState("circle", {"center": (0.0, 0.0), "radius": 4.0, "alpha": math.pi, "lambda": 1.0})
    fx, fy = forward(op, 4.0, 0.0)  # theta = pi / 4
    np.testing.assert_allclose([fx, fy], [2 * math.sqrt(2), 2 * math.sqrt(2)], atol=1e-14)
    fx, fy = forward(op, 0.0, 0.0)  # theta = 0 at R = 0
    assert (fx, fy) == (0.0, 0.0)
    vortex = OpState("vortex", {"center": (0.0, 0.0), "alpha": math.pi, "lambda": 1.0})
    fx, fy = forward(vortex, 1.0, 0.0)  # d = R = 1: l = pi / 2, theta = pi / 2
    np.testing.assert_allclose([fx, fy], [0.0, 1.0], atol=1e-14)


def test_unknown_op_type_is_refused() -> None:
    with pytest.raises(ValueError, match="unknown op type"):
        forward(OpState("smudge", {}), 0.0, 0.0)
