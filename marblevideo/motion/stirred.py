"""A recipe with ``motion`` over its input's frames: the recipe to render at each
frame's time, its own ops followed by the motion strokes seen so far
(docs/recipe-format.md, "motion"), and the take that replays them.

The frame -> canvas map is the inverse of the render's canvas -> input map
(:func:`marblevideo.recipe.frame.geometry`'s ``to_input``, for an output of
``out_size``, by default the input's own size, and ``fit``), so a stroke's points
lie under what moved in the rendered frame.
"""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from marblevideo.motion.tracker import MotionTracker
from marblevideo.recipe.frame import geometry
from marblevideo.recipe.load import Op, Recipe, build_op, parse_recipe


def frame_to_canvas(
    canvas: tuple[float, float],
    input_size: tuple[int, int],
    fit: str | None = None,
    out_size: tuple[int, int] | None = None,
) -> tuple[float, float, float, float]:
    """(a, b, c, d): a point (px, py) of the input's frame coordinates is canvas
    point (px a + c, py b + d) in a render of ``out_size`` (default the input's)."""
    geom = geometry(canvas, out_size or input_size, input_size, None, fit)
    sx, sy, ox, oy = geom.to_input
    return (1.0 / sx, 1.0 / sy, -ox / sx, -oy / sy)


class StirredRecipe:
    """``recipe`` (which has ``motion``) over an input of ``input_size`` (w, h)
    rendered at ``out_size`` (default the input's size) with ``fit``. An input
    whose size changes needs a new StirredRecipe (the frame -> canvas map is
    fixed); its ``tracker`` gives the regions and level of the last frame."""

    def __init__(
        self,
        recipe: Recipe,
        input_size: tuple[int, int],
        fit: str | None = None,
        out_size: tuple[int, int] | None = None,
    ) -> None:
        if recipe.motion is None:
            raise ValueError(f"{recipe.source}: the recipe has no `motion`")
        self.recipe = recipe
        canvas = recipe.canvas or (float(input_size[0]), float(input_size[1]))
        self.tracker = MotionTracker(
            recipe.motion, frame_to_canvas(canvas, input_size, fit, out_size)
        )
        self._plain = dataclasses.replace(recipe, motion=None)
        self._ops: dict[str, tuple[dict, Op]] = {}  # by a stroke's start: (its dict, its Op)
        self._current: tuple[list[dict], Recipe] = ([], self._plain)

    def see(self, frame: np.ndarray, t: float) -> Recipe:
        """Take the input's frame shown at ``t`` (times increasing) and return the
        recipe to render at ``t``: its ops, then the motion strokes not yet healed,
        as ordinary stroke ops, and no ``motion``. The same Recipe object is
        returned while the strokes do not change."""
        self.tracker.see(frame, t)
        strokes = self.tracker.strokes()
        if strokes == self._current[0]:
            return self._current[1]
        made: dict[str, tuple[dict, Op]] = {}
        ops = [self._op(stroke, made) for stroke in strokes]
        self._ops = made  # the healed ones forgotten
        base = len(self._plain.ops)
        entries = self._plain.entries
        ops = [
            dataclasses.replace(op, index=base + n, entry=entries + n) for n, op in enumerate(ops)
        ]
        recipe = dataclasses.replace(
            self._plain, ops=self._plain.ops + tuple(ops), entries=entries + len(ops)
        )
        self._current = (strokes, recipe)
        return recipe

    def _op(self, stroke: dict, ops: dict) -> Op:
        """The stroke as an Op: parsed as any recipe's stroke when it begins (so
        validated like one); once it grows, built from its dict without the
        schema's walk over every point (the tracker appends points within the
        stroke op's limits), so that a long stroke costs little a frame. ``ops``
        collects this frame's (dict, Op) by the stroke's start."""
        key = repr((stroke["points"][0], stroke["times"][0]))
        cached = self._ops.get(key)
        if cached is None:
            op = parse_recipe({"ops": [stroke]}, self.recipe.source).ops[0]
        elif cached[0] == stroke:
            op = cached[1]
        else:
            op = build_op(stroke, 0)
        ops[key] = (stroke, op)
        return op

    def take_document(self, document: dict) -> dict:
        """The recipe JSON ``document`` with every motion stroke made so far (healed
        ones too) appended to its ops and without ``motion``: it renders the same
        frames over the same input anywhere."""
        take = {k: copy.deepcopy(v) for k, v in document.items() if k != "motion"}
        take["ops"] = [*take.get("ops", []), *copy.deepcopy(self.tracker.take())]
        return take
