"""A recipe's frames as data for an exported program: the packed values
(:func:`marblevideo.opencl.program.pack_params`, the renderer's own) of every
frame at ``fps``, from t = 0 until the recipe settles, each op's stored only
while they change.

Frame k shows the recipe at k / fps. Op i's rows (PSTRIDE floats each, the last
its type code) are those of frames ``first[i]`` .. ``first[i] + count[i] - 1``,
from row ``row_at[i]`` of ``rows``: frame k reads row ``row_at[i] + clamp(k -
first[i], 0, count[i] - 1)``, so an op that has not begun, or has ended, reads
its first or last row at any frame. A row's list offsets (its ``*_at`` slots)
point into ``lists``, whose first float is the number of ops (the loop walk's
count); identical list data are stored once. The background is kept the same
way (``background``, three floats a row, ``background_first``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from marblevideo.errors import RecipeError, UsageError
from marblevideo.limits import EXPORT_CONSTANT_BYTES, EXPORT_MAX_FPS, EXPORT_MAX_FRAMES
from marblevideo.opencl.program import pack_params
from marblevideo.ops import PSTRIDE, op_def
from marblevideo.recipe.antialias import pattern

#: Bytes per float and per int of the program's tables.
_WORD = 4


@dataclass(frozen=True)
class FrameTable:
    """The tables of an exported program (see the module); float32 and int32 arrays."""

    rows: np.ndarray  # (n, PSTRIDE)
    row_at: np.ndarray
    first: np.ndarray
    count: np.ndarray
    lists: np.ndarray
    background: np.ndarray  # (m, 3)
    background_first: int
    samples: np.ndarray  # (NSAMPLES, 3)
    frames: int

    @property
    def nbytes(self) -> int:
        """The constant memory the tables take in the program."""
        arrays = (self.rows, self.row_at, self.first, self.count, self.lists, self.background)
        return _WORD * (sum(a.size for a in arrays) + self.samples.size)


def check_exportable(recipe, what: str) -> None:
    """Refuse what an exported file cannot carry (``what`` names the format), in one
    line naming the JSON path: camera motion (it needs the optical flow of the
    input) and parameters that follow a signal (no audio or controllers there)."""
    if recipe.motion is not None:
        raise RecipeError(
            recipe.source,
            "motion",
            f"camera motion needs the input's optical flow: {what} cannot carry it "
            "(render it with marblevideo)",
        )
    uses = recipe.signal_uses()
    if uses:
        raise RecipeError(
            recipe.source, uses[0][0], f"follows a signal: {what} has no audio or controllers"
        )


def frame_count(recipe, fps: float) -> int:
    """Frames from t = 0 until the recipe settles, at ``fps`` (1 for a still)."""
    if not (math.isfinite(fps) and 0 < fps <= EXPORT_MAX_FPS):
        raise UsageError(f"--fps: expected a frame rate > 0 and <= {EXPORT_MAX_FPS:g}, got {fps:g}")
    if not recipe.is_animated:
        return 1
    span = recipe.settled_time() * fps
    if span >= EXPORT_MAX_FRAMES:
        raise UsageError(
            f"{recipe.source}: it settles at {recipe.settled_time():g} s, {span:.0f} frames at "
            f"{fps:g} fps; an export holds at most {EXPORT_MAX_FRAMES} frames"
        )
    return math.ceil(span - 1e-9) + 1


def _list_slots(type_: str) -> list[int]:
    """The slots of op ``type_`` that hold where its data start in ``lists``."""
    return [k for k, name in enumerate(op_def(type_).slots) if name.endswith("_at")]


def _op_states(spec, packed) -> list[tuple[np.ndarray, np.ndarray]]:
    """Each op's (row, its own list data) of one frame, the row's list offsets
    relative to its data (0)."""
    rows = packed.params.reshape(-1, PSTRIDE)
    starts = []
    for i, op in enumerate(spec.ops):
        slots = _list_slots(op.type)
        starts.append(int(rows[i, slots[0]]) if slots else None)
    ends = sorted({s for s in starts if s is not None} | {packed.lists.size})
    states = []
    for i, op in enumerate(spec.ops):
        row = rows[i].copy()
        at = starts[i]
        if at is None:
            states.append((row, packed.lists[:0]))
            continue
        end = next(e for e in ends if e > at) if at < packed.lists.size else at
        for k in _list_slots(op.type):
            row[k] -= at
        states.append((row, packed.lists[at:end]))
    return states


def _window(items: list[bytes]) -> tuple[int, int]:
    """(first, count): the frames from the last before the first change to the
    last change (one frame when nothing changes)."""
    changed = [k for k in range(1, len(items)) if items[k] != items[k - 1]]
    if not changed:
        return 0, 1
    return changed[0] - 1, changed[-1] - changed[0] + 2


class _Budget:
    """The tables' size so far, refused past ``limit`` bytes."""

    def __init__(self, recipe, fps: float, limit: int, raise_limit: bool):
        self.recipe, self.fps, self.limit, self.words = recipe, fps, limit, 0
        self.raise_limit = raise_limit

    def add(self, words: int) -> None:
        self.words += words
        if _WORD * self.words <= self.limit:
            return
        every = ""
        if self.raise_limit and self.limit <= EXPORT_CONSTANT_BYTES:
            every = " (every OpenCL device gives that much)"
        more = (
            ", or give --constant-memory BYTES for a device with more (clinfo: max constant "
            "buffer size)"
            if self.raise_limit
            else ""
        )
        raise UsageError(
            f"{self.recipe.source}: its frames at {self.fps:g} fps need over "
            f"{_WORD * self.words} bytes, more than the {self.limit} bytes of constant memory "
            f"the program may use{every}: export at a lower --fps{more}"
        )


def frame_table(
    recipe,
    fps: float,
    canvas: tuple[float, float],
    limit: int = EXPORT_CONSTANT_BYTES,
    raise_limit: bool = True,
) -> FrameTable:
    """The tables of ``recipe`` at ``fps`` on ``canvas`` (see the module). Raises
    UsageError, before storing past it, when they would take more than ``limit``
    bytes (its message offers ``--constant-memory`` where ``raise_limit``: the .cl
    export's option; a shader's limit is fixed)."""
    samples = pattern(recipe.antialias).astype(np.float32)
    frames = frame_count(recipe, fps)
    nops = len(recipe.ops)
    budget = _Budget(recipe, fps, limit, raise_limit)
    budget.add(samples.size + 3 * max(nops, 1) + 1)
    per_op: list[list[tuple[np.ndarray, np.ndarray]]] = [[] for _ in range(nops)]
    backgrounds = []
    for k in range(frames):
        spec = recipe.at(k / fps, canvas)
        backgrounds.append(np.asarray(spec.background, np.float32))
        for i, state in enumerate(_op_states(spec, pack_params(spec))):
            per_op[i].append(state)
    lists: list[np.ndarray] = [np.array([float(nops)], np.float32)]
    stored: dict[bytes, int] = {}
    size = 1
    rows, row_at, first, count = [], [], [], []
    for op, states in zip(recipe.ops, per_op, strict=True):
        slots = _list_slots(op.type)
        keys = [row.tobytes() + data.tobytes() for row, data in states]
        f0, n = _window(keys)
        budget.add(n * PSTRIDE)
        first.append(f0)
        count.append(n)
        row_at.append(len(rows))
        for row, data in states[f0 : f0 + n]:
            row = row.copy()
            if data.size:
                key = data.tobytes()
                if key not in stored:
                    budget.add(data.size)
                    stored[key] = size
                    lists.append(data)
                    size += data.size
                row[slots] += stored[key]
            rows.append(row)
    bg_keys = [b.tobytes() for b in backgrounds]
    b0, bn = _window(bg_keys)
    budget.add(3 * bn)
    return FrameTable(
        rows=np.array(rows or np.zeros((1, PSTRIDE)), np.float32).reshape(-1, PSTRIDE),
        row_at=np.array(row_at or [0], np.int32),
        first=np.array(first or [0], np.int32),
        count=np.array(count or [1], np.int32),
        lists=np.concatenate(lists).astype(np.float32),
        background=np.array(backgrounds[b0 : b0 + bn], np.float32),
        background_first=b0,
        samples=samples,
        frames=frames,
    )
