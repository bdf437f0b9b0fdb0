"""The marbler's vocabulary (format 1, revision 2) and every op generically: each
op's kernel section against its NumPy inverse point by point, random recipes of
all ops against the reference and in SVG, round trips, and the new ops' rules
(rake's two forms, stir's radii, jiggle's |k A| < 1 and its Newton inverse)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from op_probe import run_op
from recipes import make_image, valid_op
from tolerances import KERNEL_SHARE, ROUND_TRIP, SVG_SHARE

from marblevideo.errors import RecipeError
from marblevideo.opencl.selfcheck import agreement
from marblevideo.ops import REGISTRY
from marblevideo.ops.shear import rake_offsets
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import OpState, geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")

OPS = list(REGISTRY.values())
IDS = [d.type for d in OPS]
#: A kernel section's point against the float64 inverse of the same float32 point.
SECTION_PX = 2e-3
#: Jiggle's float32 Newton against the float64 root (the issue's bound).
JIGGLE_PX = 1e-3


def _op_values(definition, seed: int, w: float = 80.0, h: float = 60.0) -> OpState:
    """A random valid instance of ``definition`` at the end of its animation."""
    op = valid_op(np.random.default_rng(seed), definition, w, h)
    assert op is not None, f"no valid random {definition.type}"
    recipe = parse_recipe({"canvas": [w, h], "ops": [op]}, "r.json")
    return recipe.at(recipe.end_time()).ops[0]


@pytest.mark.parametrize("lanes", [None, 1], ids=["vectors", "one-pixel"])
@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_the_kernel_section_is_the_numpy_inverse(renderer, one_pixel_renderer, definition, lanes):
    """Point by point, on random values and points: the section walks a float32
    point where the float64 inverse takes it (ink where contains says so)."""
    device = renderer if lanes is None else one_pixel_renderer
    rng = np.random.default_rng(definition.code)
    for seed in range(3):
        op = _op_values(definition, 10 * definition.code + seed)
        x = rng.uniform(-20, 100, 4096).astype(np.float32)
        y = rng.uniform(-20, 80, 4096).astype(np.float32)
        kx, ky, ink = run_op(device, op, x, y)
        rx, ry = definition.inverse(op.values, x.astype(np.float64), y.astype(np.float64))
        if definition.ink:
            inside = definition.contains(op.values, x.astype(np.float64), y.astype(np.float64))
            edge = np.abs(np.hypot(x - op["center"][0], y - op["center"][1]) - op["radius"]) < 1e-3
            assert np.array_equal((ink == 0)[~edge], inside[~edge]), definition.type
            keep = ~inside & ~edge
        else:
            assert (ink < 0).all()
            keep = np.ones(x.shape, bool)
        err = np.hypot(kx - rx, ky - ry)[keep]
        scale = np.maximum(1.0, np.hypot(rx, ry)[keep] / 100)
        scale *= np.maximum(1.0, _condition(definition, op, x, y)[keep])
        assert (err <= SECTION_PX * scale).mean() >= 0.999, (definition.type, err.max())


def _condition(definition, op, x, y, h: float = 1e-4) -> np.ndarray:
    """How much the float64 inverse stretches a small error at each point (its
    derivative's largest column, by central differences): a float32 walk's
    rounding grows by as much. About 1 for most ops; a long stroke that folds
    the fluid many times over (random paths crossing themselves, close tines)
    stretches it by up to 1e6, where float32 and float64 walks part."""
    x, y = x.astype(np.float64), y.astype(np.float64)
    most = np.zeros(x.shape)
    for dx, dy in ((h, 0.0), (0.0, h)):
        ax, ay = definition.inverse(op.values, x + dx, y + dy)
        bx, by = definition.inverse(op.values, x - dx, y - dy)
        most = np.maximum(most, np.hypot(ax - bx, ay - by) / (2 * h))
    return most


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_forward_then_inverse_on_random_values(definition):
    """float64: exact inverses to ROUND_TRIP; jiggle's Newton to 1e-6."""
    bound = 1e-6 if definition.type == "jiggle" else ROUND_TRIP
    rng = np.random.default_rng(7)
    for seed in range(5):
        op = _op_values(definition, 100 + seed)
        x, y = rng.uniform(-20, 100, 2000), rng.uniform(-20, 80, 2000)
        fx, fy = definition.forward(op.values, x, y)
        bx, by = definition.inverse(op.values, fx, fy)
        if definition.ink:  # a drop's inside is ink, not a moved point
            fine = ~definition.contains(op.values, fx, fy) | (definition.forward is not None)
            fine &= np.hypot(x - op["center"][0], y - op["center"][1]) > 1e-9
        else:
            fine = np.ones(x.shape, bool)
        assert np.allclose(bx[fine], x[fine], atol=bound) and np.allclose(
            by[fine], y[fine], atol=bound
        )


def _random_recipe(seed: int, blank: bool, w: float = 120.0, h: float = 90.0) -> dict:
    """Drops, then a random mix of every op type (the new ones among them)."""
    rng = np.random.default_rng(seed)
    ops = [
        {"type": "drop", "center": [float(rng.uniform(0, w)), float(rng.uniform(0, h))],
         "radius": float(rng.uniform(0.1, 0.3) * min(w, h)),
         "color": [int(c) for c in rng.integers(0, 256, 3)]}
        for _ in range(4)
    ]  # fmt: skip
    kinds = [OPS[int(i)] for i in rng.permutation(len(OPS))[:6]]
    for definition in kinds:
        op = valid_op(rng, definition, w, h)
        if op is not None:
            ops.append(op)
    patterns = ("rgss", "none", "quincunx", "checker4")
    edges = ("clamp", "repeat", "mirror", "background")
    return {
        "canvas": [w, h],
        "background": "#f1faee",
        "antialias": patterns[seed % 4],
        "edges": edges[seed // 4 % 4],
        "ops": ops if blank else ops[2:],
    }


@pytest.mark.parametrize("seed", range(8))
def test_random_recipes_of_every_op_match_the_reference(renderer, seed):
    for blank in (False, True):
        recipe = parse_recipe(_random_recipe(seed, blank), "random.json")
        image = None if blank else make_image(100, 76, seed)
        for t in (0.5, recipe.end_time()):
            spec = recipe.at(t)
            geom = geometry(recipe.canvas, (130, 97), None if blank else (100, 76))
            share = agreement(
                renderer.render(spec, geom, image), reference_render(spec, geom, image)
            )
            assert share >= KERNEL_SHARE, (seed, blank, t, share)


@pytest.mark.parametrize("seed", range(4))
def test_random_blank_designs_of_every_op_in_svg(renderer, seed):
    from svg_raster import agreement as svg_agreement
    from svg_raster import rasterize

    from marblevideo.outputs.svg import design_svg

    doc = _random_recipe(100 + seed, blank=True, w=240, h=180)
    doc["antialias"] = "rgss"
    recipe = parse_recipe(doc, "random.json")
    spec = recipe.at(recipe.end_time())
    size = (240, 180)
    svg, _ = design_svg(spec, size)
    raster = renderer.render(spec, geometry(recipe.canvas, size))
    assert svg_agreement(rasterize(svg, size), raster) >= SVG_SHARE


# ---------------------------------------------------------------------------- jiggle


@pytest.mark.parametrize("ka", [0.5, 0.9, 0.99])
@pytest.mark.parametrize("lanes", [None, 1], ids=["vectors", "one-pixel"])
def test_jiggle_newton_converges_to_a_thousandth_of_a_pixel(
    renderer, one_pixel_renderer, ka, lanes
):
    """Near the |k A| -> 1 edge too, over phases and a canvas of 2000 units."""
    device = renderer if lanes is None else one_pixel_renderer
    definition = REGISTRY["jiggle"]
    rng = np.random.default_rng(int(ka * 100))
    for wavelength in (17.0, 60.0, 400.0):
        major = ka * wavelength / (2 * math.pi)
        values = {"angle": 23.0, "wavelength": wavelength, "phase": 71.0, "major": major,
                  "minor": 0.3 * major}  # fmt: skip
        op = OpState("jiggle", values)
        x = rng.uniform(0, 2000, 4096).astype(np.float32)
        y = rng.uniform(0, 2000, 4096).astype(np.float32)
        kx, ky, _ = run_op(device, op, x, y)
        rx, ry = definition.inverse(values, x.astype(np.float64), y.astype(np.float64))
        err = np.hypot(kx - rx, ky - ry)
        # float32 holds a coordinate near 2000 to 1.2e-4: the solve adds less than the bound
        assert err.max() <= JIGGLE_PX, (wavelength, ka, err.max())


def test_jiggle_keys_beyond_one_solution_are_refused_with_their_path():
    base = {"type": "jiggle", "angle": 0, "wavelength": 30, "phase": 0, "minor": 1}
    with pytest.raises(RecipeError, match=r"ops\[0\]\.major: \|2 pi major / wavelength\|"):
        parse_recipe({"canvas": [80, 60], "ops": [{**base, "major": 5}]}, "r.json")
    keyed = {**base, "major": {"keys": [{"t": 0, "v": 1}, {"t": 2, "v": 6}]}}
    with pytest.raises(RecipeError, match=r"ops\[0\]\.major\.keys\[1\]\.v: .*got 1\.26 at t=2"):
        parse_recipe({"canvas": [80, 60], "ops": [keyed]}, "r.json")
    narrowing = {**base, "major": 4, "wavelength": {"keys": [{"t": 0, "v": 30}, {"t": 1, "v": 20}]}}
    with pytest.raises(RecipeError, match=r"ops\[0\]\.wavelength\.keys\[1\]\.v"):
        parse_recipe({"canvas": [80, 60], "ops": [narrowing]}, "r.json")


def test_jiggle_between_valid_keys_is_held_below_the_edge():
    """Keys valid, frames between them not (the wavelength shrinks faster than the
    shake): A is held to 0.99 / k there, and rendered."""
    op = {"type": "jiggle", "angle": 0, "phase": 0, "minor": 0,
          "major": {"keys": [{"t": 0, "v": 4.5}, {"t": 2, "v": 1}]},
          "wavelength": {"keys": [{"t": 0, "v": 30, "ease": "ease-out"},
                                  {"t": 2, "v": 8}]}}  # fmt: skip
    recipe = parse_recipe({"canvas": [80, 60], "ops": [op]}, "r.json")
    values = recipe.at(1.32).ops[0].values
    assert 2 * math.pi * values["major"] / values["wavelength"] == pytest.approx(0.99)
    assert recipe.at(0.0).ops[0]["major"] == 4.5 and recipe.at(2.0).ops[0]["major"] == 1.0


# ---------------------------------------------------------------------------- rules


@pytest.mark.parametrize(
    "op, message",
    [
        ({"tines": [0, 5], "spacing": 4, "count": 2}, r"ops\[0\]\.spacing: give the tines"),
        ({}, r"ops\[0\]: missing 'tines' \(or 'spacing' and 'count'\)"),
        ({"spacing": 4}, r"ops\[0\]\.spacing: missing 'count'"),
        ({"count": 3}, r"ops\[0\]\.count: missing 'spacing'"),
        ({"spacing": 4, "count": 300}, r"ops\[0\]\.count: must be <= 256"),
        ({"tines": []}, r"ops\[0\]\.tines: expected a list of 1\.\.256 numbers, got an empty"),
        ({"tines": [1] * 257}, r"ops\[0\]\.tines: expected a list of 1\.\.256 numbers"),
        ({"count": 2.5, "spacing": 1}, r"ops\[0\]\.count: expected a count"),
    ],
)
def test_rake_takes_tines_or_spacing_and_count(op, message):
    rake = {"type": "rake", "point": [0, 0], "angle": 0, "alpha": 5, "falloff": 2, **op}
    with pytest.raises(RecipeError, match=message):
        parse_recipe({"canvas": [80, 60], "ops": [rake]}, "r.json")


def test_rake_offsets_centre_on_the_point_and_tines_are_as_given():
    from marblevideo.ops.shear import rake_offsets

    assert rake_offsets({"spacing": 4.0, "count": 3}) == [-4.0, 0.0, 4.0]
    assert rake_offsets({"spacing": 2.0, "count": 2}) == [-1.0, 1.0]
    assert rake_offsets({"tines": (3.0, -1.0)}) == [3.0, -1.0]
    spaced = {"type": "rake", "point": [40, 30], "angle": 90, "alpha": 6, "falloff": 3,
              "spacing": 10, "count": 3}  # fmt: skip
    listed = {**{k: v for k, v in spaced.items() if k not in ("spacing", "count")},
              "tines": [-10, 0, 10]}  # fmt: skip
    a, b = (parse_recipe({"canvas": [80, 60], "ops": [op]}, "r").at(0) for op in (spaced, listed))
    geom = geometry((80, 60), (80, 60))
    assert np.array_equal(reference_render(a, geom), reference_render(b, geom))


RAKE = {"type": "rake", "point": [40, 30], "angle": 30, "alpha": 9, "falloff": 4}
STIR = {"type": "stir", "center": [40, 30], "alpha": 30, "falloff": 15}


@pytest.mark.parametrize(
    "op, closed",
    [
        ({**RAKE, "spacing": 30, "count": 19}, True),  # the samples' rakes: s/L 7.5
        ({**RAKE, "spacing": 8, "count": 43}, True),
        ({**RAKE, "spacing": 0.4, "count": 256}, True),  # s/L 0.1: close tines
        ({**RAKE, "spacing": 3, "count": 4}, True),
        ({**RAKE, "tines": [12, -6, 0, 6, -12]}, True),  # evenly spaced once sorted
        ({**RAKE, "tines": [-9, 0, 5, 14]}, False),  # uneven: term by term
        ({**RAKE, "spacing": 0.1, "count": 40}, False),  # s/L 0.025: term by term
        ({**RAKE, "spacing": 5, "count": 3}, False),  # too few to gain
        ({**STIR, "radii": [60, -120, 180, -240, 300, -360, 420, -480]}, True),  # alternating
        ({**STIR, "radii": [-480, 420, -360, 300, -240, 180, -120, 60]}, True),  # reversed
        ({**STIR, "radii": [30, 60, 90, 120, 150]}, True),
        ({**STIR, "radii": [-20, -40, -60, -80]}, True),
        ({**STIR, "radii": [10, -20, 30, 40]}, False),  # neither equal nor alternating
    ],
)
def test_evenly_spaced_tines_and_rings_sum_in_closed_form(renderer, op, closed):
    """A rake's evenly spaced tines and a stir's evenly spaced rings whose signs
    are equal or alternate are summed as two geometric series (four
    exponentials for any count): the section still walks where the float64 sum
    of every term says, on, between and far off the tines or rings."""
    state = parse_recipe({"canvas": [80, 60], "ops": [op]}, "r.json").at(0).ops[0]
    definition = REGISTRY[op["type"]]
    packed = definition.pack(state.values, [])
    assert packed["series_even"] == (1.0 if closed else 0.0)
    rng = np.random.default_rng(len(str(op)))
    if op["type"] == "rake":
        offsets = rake_offsets(state.values)
        reach = max(abs(o) for o in offsets) + 40
        t = rng.uniform(-reach, reach, 8192)  # across the tines, from the point
        t[: len(offsets)] = offsets  # on every tine
        u = rng.uniform(-50, 50, t.size)  # along them
        c, s = math.cos(math.radians(30)), math.sin(math.radians(30))  # M = (c, s), N = (-s, c)
        x, y = 40 - t * s + u * c, 30 + t * c + u * s
    else:
        radii = [abs(r) for r in op["radii"]]
        reach = max(radii) + 40
        r = rng.uniform(0, reach, 8192)
        r[: len(radii)] = radii  # on every ring
        a = rng.uniform(0, 2 * math.pi, r.size)
        x, y = 40 + r * np.cos(a), 30 + r * np.sin(a)
    x, y = x.astype(np.float32), y.astype(np.float32)
    rx, ry = definition.inverse(state.values, x.astype(np.float64), y.astype(np.float64))
    for lanes in (None, 1):  # vectors, and the scalar code of GPUs
        kx, ky, _ = run_op(renderer, state, x, y, lanes)
        err = np.hypot(kx - rx, ky - ry)
        assert err.max() <= SECTION_PX * max(1.0, reach / 100), (op, lanes, err.max())


def test_stir_radii_must_not_be_zero():
    stir = {"type": "stir", "center": [0, 0], "radii": [4, 0], "alpha": 1, "falloff": 1}
    with pytest.raises(RecipeError, match=r"ops\[0\]\.radii\[1\]: must not be 0, got 0"):
        parse_recipe({"canvas": [80, 60], "ops": [stir]}, "r.json")


def test_oseen_develops_with_its_time_and_is_still_at_time_zero():
    """Progress scales time; T = 0 is no rotation; far out a free vortex G T / (2 pi R^2)."""
    op = {"type": "oseen", "center": [0, 0], "circulation": 5000, "viscosity": 10, "time": 4,
          "start": 0, "end": 2}  # fmt: skip
    recipe = parse_recipe({"canvas": [80, 60], "ops": [op]}, "r.json")
    assert recipe.at(1.0).ops[0]["time"] == 2.0
    still = recipe.at(0.0).ops[0]
    x, y = np.array([30.0, 5.0]), np.array([0.0, 2.0])
    assert np.array_equal(REGISTRY["oseen"].forward(still.values, x, y)[0], x)
    done = recipe.at(2.0).ops[0].values
    r = 400.0
    fx, fy = REGISTRY["oseen"].forward(done, np.array([r]), np.array([0.0]))
    theta = math.atan2(fy[0], fx[0])
    assert theta == pytest.approx(5000 * 4 / (2 * math.pi * r * r), rel=3e-3)  # core: +0.2%


def test_shift_and_turn_animate_linearly():
    ops = [{"type": "shift", "offset": [10, -4], "start": 0, "end": 2},
           {"type": "turn", "center": [0, 0], "angle": 90, "start": 0, "end": 2}]  # fmt: skip
    recipe = parse_recipe({"canvas": [80, 60], "ops": ops}, "r.json")
    half = recipe.at(1.0).ops
    assert half[0]["offset"] == (5.0, -2.0) and half[1]["angle"] == 45.0
    fx, fy = REGISTRY["turn"].forward(half[1].values, np.array([1.0]), np.array([0.0]))
    assert (fx[0], fy[0]) == pytest.approx((math.sqrt(0.5), math.sqrt(0.5)))  # clockwise: +y


def test_a_jiggle_too_strong_before_its_first_key_names_its_path():
    """t = 0 before the wavelength's first key: the fault names the op's major,
    not a key of the wavelength that is not there (was a ValueError traceback)."""
    wavelength = {"keys": [{"t": 0.5, "v": 10}, {"t": 1, "v": 40}]}
    op = {
        "type": "jiggle",
        "angle": 0,
        "wavelength": wavelength,
        "phase": 0,
        "major": 5,
        "minor": 1,
    }
    with pytest.raises(RecipeError, match=r"ops\[0\]\.major"):
        parse_recipe({"canvas": [80, 60], "ops": [op]}, "r.json")


@pytest.mark.parametrize(
    "positions, falloff",
    [
        ([(k - 9) * 30.0 for k in range(19)], 4.0),  # bouquet's rake
        ([(k - 21) * 8.0 for k in range(43)], 2.5),
        ([5.0 + 3.0 * k for k in range(4)], 60.0),  # wide fall-off: every tine counts
        ([(k - 2) * 0.1 for k in range(5)], 4.0),  # closer than MIN_RATIO: term by term
        ([0.0, 1.0, 3.0, 7.0], 2.0),  # uneven: term by term
    ],
)
def test_a_rakes_closed_form_is_the_sum_of_its_tines(positions, falloff):
    """The float64 reference's closed form against the definition, term by term,
    across the tines, on them, between them and far beyond either end."""
    from marblevideo.ops.series import falloff_sum

    rng = np.random.default_rng(7)
    lo, hi = min(positions), max(positions)
    u = np.concatenate(
        [
            rng.uniform(lo - 200, hi + 200, 4000),
            np.array(positions),
            np.array(positions) + 1e-13,
            np.array([lo - 5000.0, hi + 5000.0, -1e300 if lo < 0 else 0.0]),
        ]
    )
    sum_of_terms = sum(np.exp(-np.abs(u - p) / falloff) for p in positions)
    got = falloff_sum(u, positions, falloff)
    assert np.all(np.isfinite(got))
    assert np.allclose(got, sum_of_terms, rtol=1e-12, atol=1e-300)
