"""A recipe's JSON document, read strictly before it is validated
(:mod:`marblevideo.recipe.load`): a key given twice in one object, non-finite
numbers (NaN, Infinity, 1e400) and nesting deeper than :data:`MAX_DEPTH` are
kept visible to the checks instead of lost or crashing them.
"""

from __future__ import annotations

import json
import math
import numbers
from typing import Any

from marblevideo.errors import RecipeError
from marblevideo.limits import MAX_DEPTH
from marblevideo.recipe.faults import NonFinite, format_path


def parse_json(text: str, source: str) -> Any:
    """The JSON ``text`` of the recipe file ``source`` (named in messages), its
    objects remembering keys given twice, non-finite numbers as NonFinite."""
    try:
        return json.loads(
            text, parse_constant=NonFinite, parse_float=_parse_float, object_pairs_hook=_Object
        )
    except json.JSONDecodeError as exc:
        raise RecipeError(
            source, "", f"invalid JSON at line {exc.lineno}, column {exc.colno}: {exc.msg}"
        ) from None
    except RecursionError:
        raise RecipeError(source, "", f"nested too deeply (over {MAX_DEPTH} levels)") from None


def _parse_float(text: str) -> float | NonFinite:
    value = float(text)
    return value if math.isfinite(value) else NonFinite(text)


class _Object(dict):
    """A JSON object as read from a file, with the keys it gave more than once
    (json keeps the last value of each without a word)."""

    def __init__(self, pairs: list[tuple[str, Any]]):
        super().__init__(pairs)
        seen: set[str] = set()
        self.twice = [k for k, _ in pairs if k in seen or seen.add(k)]


def check_depth(data: Any, source: str) -> None:
    """Refuse nesting deeper than MAX_DEPTH, naming the first node too deep, and a key
    given twice in one object of a file, in document order, without recursion (the
    validator and the builder recurse)."""
    stack: list[tuple[Any, list, int]] = [(data, [], 0)]
    while stack:
        node, path, depth = stack.pop()
        if isinstance(node, dict):
            if getattr(node, "twice", None):
                message = "given twice in one object (JSON would keep only the last)"
                raise RecipeError(source, format_path([*path, node.twice[0]]), message)
            children = list(node.items())
        elif isinstance(node, (list, tuple)):
            children = list(enumerate(node))
        else:
            continue
        if depth == MAX_DEPTH:
            message = f"nested too deeply: more than {MAX_DEPTH} levels of lists and objects"
            raise RecipeError(source, format_path(path), message)
        stack.extend((child, [*path, key], depth + 1) for key, child in reversed(children))


def normalize(data: Any) -> Any:
    """JSON-shaped copy: tuples become lists, NumPy-style numbers int or float,
    non-finite floats NonFinite."""
    if isinstance(data, dict):
        return {k: normalize(v) for k, v in data.items()}
    if isinstance(data, (list, tuple)):
        return [normalize(v) for v in data]
    if isinstance(data, numbers.Real) and not isinstance(data, (bool, int, float)):
        data = int(data) if isinstance(data, numbers.Integral) else float(data)
    if isinstance(data, float) and not math.isfinite(data):
        return NonFinite("NaN" if math.isnan(data) else "Infinity" if data > 0 else "-Infinity")
    return data
