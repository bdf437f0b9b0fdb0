"""How much a recipe has marbled the sheet at a time, and whether a still taken
at its end (the default) shows a recipe that has come back to rest.

Motion at ``t`` is the mean, over a grid of canvas points, of how far the
inverse walk carries each point (canvas units); a point that lands in ink
counts :data:`INKED` of the canvas diagonal (the sheet there is covered).
Key times of a recipe are where its values turn (keyframes, op
``start``/``end``), so the motion is measured there and halfway between them,
and only for recipes with a strength that eases off.
"""

from __future__ import annotations

import numpy as np

from marblevideo.recipe import Recipe
from marblevideo.recipe.frame import FrameSpec
from marblevideo.reference.walk import inverse_walk

#: Grid points per side of the canvas.
GRID = 24
#: What a point in ink counts, as a fraction of the canvas diagonal.
INKED = 0.1
#: Most times measured (a recipe of many key times: evenly chosen among them).
MAX_SAMPLES = 64
#: The end counts as back at rest below this fraction of the strongest motion.
AT_REST = 0.25


def motion(spec: FrameSpec) -> float:
    """Mean distance (canvas units) the walk carries the grid's points."""
    cw, ch = spec.canvas
    x, y = np.meshgrid((np.arange(GRID) + 0.5) * cw / GRID, (np.arange(GRID) + 0.5) * ch / GRID)
    x0, y0, ink = inverse_walk(spec, x, y)
    inked = INKED * float(np.hypot(cw, ch))
    return float(np.where(ink >= 0, inked, np.hypot(x0 - x, y0 - y)).mean())


def sample_times(recipe: Recipe) -> list[float]:
    """The recipe's key times from 0 to its end and the midpoints between them (at
    most :data:`MAX_SAMPLES`, the end last)."""
    end = recipe.end_time()
    keys = {0.0, end}
    keys.update(t for op in recipe.ops for t in op.times if 0 <= t <= end)
    keys.update(t for op in recipe.ops for t in op.heal or () if 0 <= t <= end)
    keys.update(t for t in recipe.background.key_times if 0 <= t <= end)
    ordered = sorted(keys)
    times = sorted({*ordered, *((a + b) / 2 for a, b in zip(ordered, ordered[1:], strict=False))})
    if len(times) > MAX_SAMPLES:  # evenly chosen, the end kept
        times = [times[round(i)] for i in np.linspace(0, len(times) - 1, MAX_SAMPLES)]
    return times


def eases_off(recipe: Recipe) -> bool:
    """Whether a keyed number of an op ends smaller in magnitude than it was at a
    key before (a strength that goes back down), or an op heals before the end
    (``heal``): the ways a recipe comes back towards rest, since ``start``/``end``
    progress only grows."""
    end = recipe.end_time()
    if any(op.heal is not None and op.heal[0] < end for op in recipe.ops):
        return True
    for op in recipe.ops:
        for track in op.params.values():
            if track.keyed and track.scalar:
                sizes = [abs(key.v[0]) for key in track.keys]
                if sizes[-1] < max(sizes):
                    return True
    return False


def rest_note(recipe: Recipe, canvas: tuple[float, float]) -> str | None:
    """The notice for a still taken at the end of an animation that has come back
    (near) to rest there, naming the time of its strongest motion; else None.
    Measured only where a strength eases off (:func:`eases_off`)."""
    if not eases_off(recipe):
        return None
    times = sample_times(recipe)
    amounts = [motion(recipe.at(t, canvas)) for t in times]
    peak = int(np.argmax(amounts))
    if amounts[-1] >= AT_REST * amounts[peak]:
        return None
    at = f"{times[peak]:.3g}"
    return (
        f"{recipe.source}: the still is taken at the animation's end ({times[-1]:.3g} s), "
        f"where it has come back near rest; its motion is strongest at {at} s (--time {at})"
    )
