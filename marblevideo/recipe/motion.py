"""The recipe's ``motion`` object (revision 4): its settings, its JSON Schema and
what the schema cannot check (docs/recipe-format.md, "motion").

:class:`MotionSpec` lives here, in the recipe's layer, so that the loader can build
it; :mod:`marblevideo.motion` (the analysis that turns frames into strokes) imports
it from here and re-exports it as ``marblevideo.motion.MotionSpec``.
"""

from __future__ import annotations

from dataclasses import dataclass

from marblevideo.limits import NUMBER_LIMIT

#: (field, default, description) of the ``motion`` object, the contract's table.
FIELDS = (
    ("gain", 1.0, "Each motion stroke's `drag` (0..4)."),
    (
        "width",
        (24.0, 200.0),
        "Canvas units [min, max], 0 < min <= max: a stroke's width is its region's diameter "
        "(2 sqrt(area / pi)), the median over the 3 frames that made it a stroke, clamped to "
        "this range, and fixed from then on.",
    ),
    ("threshold", 60.0, "Canvas units per second: slower motion is not a stroke."),
    (
        "max_strokes",
        6,
        "At most this many regions followed at once (1..32), the largest area x speed first.",
    ),
    (
        "memory",
        6.0,
        "Seconds after a stroke's last point before it heals (>= 0.5, so a stroke has ended "
        "before its healing begins).",
    ),
    (
        "heal",
        2.0,
        "Seconds its healing takes (its `heal` is [last + memory, last + memory + heal]).",
    ),
)
#: The largest ``max_strokes``.
MAX_STROKES = 32


@dataclass(frozen=True)
class MotionSpec:
    """A recipe's ``motion`` settings, valid (the loader checked them): ``gain``
    (each stroke's drag), ``width`` (min, max) canvas units, ``threshold`` canvas
    units per second, ``max_strokes`` regions followed at once, ``memory`` and
    ``heal`` seconds."""

    gain: float = 1.0
    width: tuple[float, float] = (24.0, 200.0)
    threshold: float = 60.0
    max_strokes: int = 6
    memory: float = 6.0
    heal: float = 2.0

    @classmethod
    def from_json(cls, data: dict) -> MotionSpec:
        """The settings of a valid ``motion`` object (absent fields take their defaults)."""
        defaults = cls()
        width = data.get("width", defaults.width)
        return cls(
            gain=float(data.get("gain", defaults.gain)),
            width=(float(width[0]), float(width[1])),
            threshold=float(data.get("threshold", defaults.threshold)),
            max_strokes=int(data.get("max_strokes", defaults.max_strokes)),
            memory=float(data.get("memory", defaults.memory)),
            heal=float(data.get("heal", defaults.heal)),
        )

    def to_json(self) -> dict:
        """The ``motion`` object of these settings (every field written)."""
        return {
            "gain": self.gain,
            "width": list(self.width),
            "threshold": self.threshold,
            "max_strokes": self.max_strokes,
            "memory": self.memory,
            "heal": self.heal,
        }


def motion_schema() -> dict:
    """The JSON Schema of the top-level ``motion`` object."""
    bounds = {
        "gain": {"type": "number", "minimum": 0, "maximum": 4},
        "width": {
            "title": "width [min, max]",
            "type": "array",
            "items": {"type": "number", "exclusiveMinimum": 0, "maximum": NUMBER_LIMIT},
            "minItems": 2,
            "maxItems": 2,
        },
        "threshold": {"type": "number", "minimum": 0, "maximum": NUMBER_LIMIT},
        "max_strokes": {"type": "integer", "minimum": 1, "maximum": MAX_STROKES},
        "memory": {"type": "number", "minimum": 0.5, "maximum": NUMBER_LIMIT},
        "heal": {"type": "number", "minimum": 0, "maximum": NUMBER_LIMIT},
    }
    properties = {
        name: {
            **bounds[name],
            "default": list(default) if isinstance(default, tuple) else default,
            "description": text,
        }
        for name, default, text in FIELDS
    }
    return {
        "title": "motion object",
        "description": "What moves in front of the camera stirs the ink: the movement seen in "
        "the input's frames becomes strokes, added on top of the ops as the frames are rendered.",
        "type": "object",
        "properties": properties,
        "additionalProperties": False,
    }


def motion_faults(data: dict) -> list[tuple[list, str]]:
    """(path inside ``motion``, message) of what the schema cannot say: ``width``'s
    min <= max."""
    width = data.get("width")
    if width is not None and width[0] > width[1]:
        return [
            (["width"], f"must be [min, max] with min <= max, got [{width[0]:g}, {width[1]:g}]")
        ]
    return []
