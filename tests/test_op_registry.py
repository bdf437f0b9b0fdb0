"""Every op is complete: a definition, a kernel section, a reference, forward and
inverse maps that undo each other, a docs paragraph and an example that renders
on the device as the reference does. Adding an op without one of them fails here."""

from __future__ import annotations

import re

import numpy as np
import pytest
from helpers import ROOT
from tolerances import KERNEL_LEVELS, KERNEL_SHARE, ROUND_TRIP, SVG_SHARE

from marblevideo.opencl.program import UNROLL_LIMIT, kernel_source, pack_params, walk_source
from marblevideo.opencl.selfcheck import agreement
from marblevideo.ops import COLOR_SLOTS, PSTRIDE, REGISTRY, identity, op_def
from marblevideo.ops.base import PROGRESS_LAWS, slider_range
from marblevideo.recipe import parse_recipe
from marblevideo.recipe.frame import geometry
from marblevideo.reference import render as reference_render

pytestmark = pytest.mark.tier("fast")

OPS = list(REGISTRY.values())
IDS = [d.type for d in OPS]
SECTION = re.compile(r"^inline void (op_\w+)\(OP_ARGS\)", re.M)


def test_type_codes_follow_the_registry():
    assert [d.code for d in OPS] == list(range(len(OPS)))
    with pytest.raises(ValueError, match="unknown op type 'nope'"):
        op_def("nope")


def test_every_kernel_section_belongs_to_a_registered_op():
    families = {d.family for d in OPS}
    sections = {
        name for family in families for name in SECTION.findall(kernel_source(f"ops/{family}.cl"))
    }
    assert sections == {d.kernel_function for d in OPS}
    assert sorted(p.stem for p in (ROOT / "kernels" / "ops").glob("*.cl")) == sorted(families)


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_the_op_has_its_kernel_section(definition):
    source = kernel_source(f"ops/{definition.family}.cl")
    assert definition.kernel_function in SECTION.findall(source)


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_the_op_has_its_docs_paragraph(definition):
    docs = (ROOT / "docs" / "recipe-format.md").read_text()
    assert re.search(rf"^### `{definition.type}`", docs, re.M), definition.type
    assert definition.help and all(p.help for p in definition.params)


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_the_example_is_a_valid_op_of_its_type(definition):
    recipe = parse_recipe({"canvas": [80, 60], "ops": [dict(definition.example)]}, "ex.json")
    assert recipe.ops[0].type == definition.type
    required = {p.name for p in definition.params if not p.optional}
    assert required <= set(recipe.ops[0].params) <= set(definition.kinds)


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_progress_laws_and_sliders_are_well_formed(definition):
    for name, law in definition.progress:
        assert name in definition.kinds and law in PROGRESS_LAWS
    for param in definition.params:
        if param.slider is not None:
            lo, hi, step = slider_range(param, 1.0, 500.0)
            assert lo < hi and step > 0


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_packing_fits_and_ink_colours_sit_where_the_kernel_reads_them(definition):
    recipe = parse_recipe({"canvas": [80, 60], "ops": [dict(definition.example)]}, "ex.json")
    spec = recipe.at(recipe.end_time())
    row = pack_params(spec).params
    assert row.shape == (PSTRIDE,) and row[-1] == definition.code
    if definition.ink:
        assert tuple(row[list(COLOR_SLOTS)]) == spec.ops[0]["color"]


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_an_op_before_its_start_is_still_and_skipped(definition):
    """At progress 0 every op moves nothing and holds no ink (the float64 inverse
    is the identity to its rounding, no point is ink): it is still, and packed with the code
    the walk skips; at its end it is not."""
    import numpy as np

    from marblevideo.opencl.program import STILL_CODE

    op = {**definition.example, "start": 1.0, "end": 2.0}
    recipe = parse_recipe({"canvas": [80, 60], "ops": [op]}, "ex.json")
    before, after = recipe.at(0.5).ops[0], recipe.at(2.0).ops[0]
    assert definition.still(before.values) and not definition.still(after.values)
    rng = np.random.default_rng(definition.code)
    x, y = rng.uniform(-20, 100, 500), rng.uniform(-20, 80, 500)
    ix, iy = definition.inverse(before.values, x, y)  # the identity, to float64's rounding
    assert np.abs(ix - x).max() <= 1e-12 and np.abs(iy - y).max() <= 1e-12
    if definition.ink:
        assert not definition.contains(before.values, x, y).any()
    assert pack_params(recipe.at(0.5)).params[-1] == STILL_CODE
    assert pack_params(recipe.at(2.0)).params[-1] == definition.code


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_forward_then_inverse_is_the_identity(definition):
    """On points where the op is not ink, in float64: the contract's exact inverses."""
    recipe = parse_recipe({"canvas": [80, 60], "ops": [dict(definition.example)]}, "ex.json")
    values = recipe.at(recipe.end_time()).ops[0].values
    rng = np.random.default_rng(definition.code)
    x, y = rng.uniform(-40, 120, 4000), rng.uniform(-40, 100, 4000)
    fx, fy = definition.forward(values, x, y)
    if definition.ink and definition.forward is not identity:  # a drop pushes paint out
        assert not definition.contains(values, fx, fy).any()
    bx, by = definition.inverse(values, fx, fy)
    assert np.allclose(bx, x, atol=ROUND_TRIP) and np.allclose(by, y, atol=ROUND_TRIP)


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_the_example_renders_on_the_device_as_the_reference_does(renderer, definition):
    """Over a picture and on a blank sheet, unrolled and in the loop walk."""
    picture = np.random.default_rng(3).integers(0, 256, (60, 80, 4), dtype=np.uint8)
    picture[..., 3] = 255
    base = {"canvas": [80, 60], "antialias": "rgss", "ops": [dict(definition.example)]}
    looped = {**base, "ops": [dict(definition.example)] * (UNROLL_LIMIT + 1)}
    for doc, image in ((base, picture), (base, None), (looped, None)):
        recipe = parse_recipe(doc, "ex.json")
        spec = recipe.at(recipe.end_time())
        geom = geometry(recipe.canvas, (80, 60), None if image is None else (80, 60))
        ours = renderer.render(spec, geom, image)
        share = agreement(ours, reference_render(spec, geom, image))
        assert share >= KERNEL_SHARE, (definition.type, share, KERNEL_LEVELS)


def test_the_loop_walk_has_one_case_per_op_type_and_no_default():
    header = walk_source(None)  # the loop walk (Programs.program_key: types None)
    cases = re.findall(r"case CODE_(\w+): OP(?:_CHAINS)?\(i, (\w+)\)", header)
    assert cases == [(d.type.upper(), d.kernel_function) for d in OPS]
    assert "default" not in header
    inks = re.findall(r"code_ == CODE_(\w+)", header)
    assert inks == [d.type.upper() for d in OPS if d.ink]


@pytest.mark.parametrize("definition", OPS, ids=IDS)
def test_the_example_over_drops_is_the_same_in_svg(renderer, definition):
    """Ink carried through the op's forward map (SVG, rasterized by cairosvg) shows
    what the kernel's inverse walk shows."""
    from svg_raster import agreement, rasterize

    from marblevideo.outputs.svg import design_svg

    drops = [
        {"type": "drop", "center": [20 + 20 * k, 15 + 15 * (k % 3)], "radius": 12, "color": c}
        for k, c in enumerate(["#1d3557", "#e63946", "#2a9d8f", "#e9c46a"])
    ]
    doc = {"canvas": [80, 60], "background": "#f1faee", "ops": [*drops, dict(definition.example)]}
    recipe = parse_recipe(doc, "ex.json")
    spec = recipe.at(recipe.end_time())
    size = (320, 240)
    svg, _ = design_svg(spec, size)
    raster = renderer.render(spec, geometry(recipe.canvas, size))
    assert agreement(rasterize(svg, size), raster) >= SVG_SHARE, definition.type
