"""Recipe faults: the first one in document order, as the one line
``FILE: json.path: what was expected, got what`` (:class:`Fault`), from a JSON
Schema error (:func:`schema_fault`) or a rule the loader checks itself
(:func:`make_fault`). Paths are written like ``ops[3].center.keys[1].t``."""

from __future__ import annotations

import difflib
import json
import re
from dataclasses import dataclass
from functools import lru_cache
from typing import TYPE_CHECKING, Any

from marblevideo.recipe.colors import CSS_NAMES, SHAPES
from marblevideo.recipe.schema import COLOR_TITLE, LIMIT, schema

if TYPE_CHECKING:
    from jsonschema import Draft202012Validator, ValidationError


class NonFinite:
    """Stands in for a non-finite number so validation reports it where it is."""

    def __init__(self, text: str):
        self.text = text

    def __repr__(self) -> str:
        return self.text


@dataclass(frozen=True)
class Fault:
    position: tuple[int, ...]  # document order: index of each step, then where in the node
    path: str
    message: str


@lru_cache(maxsize=1)
def validator() -> Draft202012Validator:
    """The recipe schema's validator (jsonschema, imported here: a recipe file the
    schema accepted before skips it, :mod:`marblevideo.recipe.accepted`)."""
    from jsonschema import Draft202012Validator

    return Draft202012Validator(schema())


def make_fault(doc: Any, path: list, message: str, tail: int | None = None) -> Fault:
    position = []
    node = doc
    for step in path:
        position.append(list(node).index(step) if isinstance(node, dict) else step)
        node = node[step]
    if tail is not None:
        position.append(tail)
    return Fault(tuple(position), format_path(path), message)


_PLAIN_KEY = re.compile(r"[A-Za-z_$][A-Za-z0-9_$]*")  # ASCII only: "²".isalnum() is True


def format_path(path: list) -> str:
    out = ""
    for step in path:
        if isinstance(step, int):
            out += f"[{step}]"
        elif _PLAIN_KEY.fullmatch(step):
            out += f".{step}" if out else step
        else:
            out += f"[{json.dumps(step, ensure_ascii=False)}]"
    return out


def schema_fault(error: ValidationError, doc: Any) -> Fault:
    """One schema error as a fault, descending into the anyOf branch the value meant."""
    path = list(error.absolute_path)
    kind, instance, bound = error.validator, error.instance, error.validator_value
    if kind == "anyOf" and isinstance(instance, str) and error.schema.get("title") == COLOR_TITLE:
        return make_fault(doc, path, color_message(instance))
    if isinstance(instance, dict) and "signal" in instance and _refuses_signals(error):
        return make_fault(doc, path, NO_SIGNAL)
    if kind == "anyOf":
        branches = _branches(error)
        meant = [
            errors
            for _, errors in sorted(
                enumerate(branches), key=lambda b: not _holds_key(error, b[0], instance)
            )
            if not any(_mismatch(e) for e in errors)
        ]
        if meant:
            return min((schema_fault(e, doc) for e in meant[0]), key=lambda f: f.position)
        message = f"expected {' or '.join(_expected(error.schema))}, got {describe(instance)}"
        return make_fault(doc, path, message)
    if kind == "additionalProperties":
        allowed = error.schema.get("properties", {})
        extra = next(k for k in instance if k not in allowed)
        message = f"unknown field {extra!r}" + did_you_mean(extra, set(allowed) - set(instance))
        return make_fault(doc, path, message, list(instance).index(extra))
    if kind == "required":
        missing = next(k for k in bound if k not in instance)
        return make_fault(doc, path, f"missing required field {missing!r}", len(instance))
    if kind == "dependentRequired":
        field_, needs = next((k, v) for k, v in bound.items() if k in instance)
        message = f"{field_!r} requires {needs[0]!r} (progress runs from start to end)"
        return make_fault(doc, path, message, list(instance).index(field_))
    return make_fault(doc, path, _message(kind, instance, bound, error.schema))


#: A signal where the parameter takes none (points, colours, layout fields, constants).
NO_SIGNAL = (
    "takes no signal: only keyable numbers follow signals (points, colors, layout fields "
    "and constants take none)"
)


def _refuses_signals(error: ValidationError) -> bool:
    """Whether the schema that refused a signal object has no signal branch."""
    if error.validator == "type":
        return True
    refs = [branch.get("$ref", "") for branch in error.schema.get("anyOf", ())]
    return error.validator == "anyOf" and not any(r.endswith("Signal") for r in refs)


def _holds_key(error: ValidationError, branch: int, instance: Any) -> bool:
    """Whether ``instance`` has the field that marks anyOf ``branch`` as the one it
    means: ``keys`` for a keyframe track, ``signal`` for a signal."""
    ref = error.schema["anyOf"][branch].get("$ref", "")
    field_ = "keys" if ref.endswith("Track") else "signal" if ref.endswith("Signal") else None
    return isinstance(instance, dict) and field_ in instance


def color_message(text: str) -> str:
    """Why the string ``text`` is not a colour, with the nearest CSS name if any."""
    if text.startswith("#"):
        return f'expected "#rrggbb" or "#rgb" (hex digits), got string {text!r}'
    squashed = "".join(c for c in text.lower() if c.isalpha())  # "Light Blue", "light-blue"
    if squashed in CSS_NAMES:
        hint = f" (did you mean {squashed!r}?)"
    else:
        hint = did_you_mean(squashed or text, CSS_NAMES)
    return f"unknown color {text!r}{hint}; expected {SHAPES}"


def _message(kind: str, instance: Any, bound: Any, schema_: dict) -> str:
    """The text for a leaf schema error: what was expected, got what."""
    got = describe(instance)
    title = schema_.get("title")
    if kind == "type":
        return f"expected {_expected(schema_)[0]}, got {got}"
    if kind in ("minimum", "maximum") and abs(bound) == LIMIT:
        return f"too large: must be within -1e30..1e30 (float32 range), got {got}"
    comparisons = {
        "minimum": ">=",
        "maximum": "<=",
        "exclusiveMinimum": ">",
        "exclusiveMaximum": "<",
    }
    if kind in comparisons:
        return f"must be {comparisons[kind]} {describe(bound)}, got {got}"
    if kind in ("minItems", "maxItems"):
        if title:
            return f"expected {_article(title)}, got {got}"
        return f"expected at least {bound} item{'s' * (bound != 1)}, got {got}"
    if kind == "maxLength":
        return f"too long: at most {bound} characters, got {len(instance)}"
    if kind == "enum":
        names = ", ".join(map(str, bound))
        if isinstance(instance, str):
            hint = did_you_mean(instance, bound)
            return f"unknown {title or 'value'} {instance!r}{hint}; expected one of {names}"
        return f"expected one of {names}, got {got}"
    if kind == "not" and isinstance(bound, dict) and "const" in bound:
        return f"must not be {describe(bound['const'])}, got {got}"
    if kind == "const":
        return f"unsupported {title or 'value'}: expected {describe(bound)}, got {got}"
    if kind == "pattern":
        return f"expected {_article(title) if title else 'a match of ' + bound}, got {got}"
    return f"{kind}: {got} is not valid"  # unreachable for the published schema


def _branches(error: ValidationError) -> list[list[ValidationError]]:
    grouped: dict[int, list[ValidationError]] = {}
    for sub in error.context or ():
        grouped.setdefault(sub.relative_schema_path[0], []).append(sub)
    return [grouped[i] for i in sorted(grouped)]


def _mismatch(error: ValidationError) -> bool:
    """Whether the error says the value is of another JSON type than this branch takes."""
    if error.relative_path:
        return False
    if error.validator == "type":
        return True
    if error.validator == "anyOf":
        return all(any(_mismatch(e) for e in errors) for errors in _branches(error))
    return False


_TYPE_NOUNS = {
    "number": "a number",
    "integer": "an integer",
    "string": "a string",
    "array": "a list",
    "object": "an object",
    "boolean": "true or false",
}


def _expected(schema_: dict) -> list[str]:
    """What a (sub)schema takes, as noun phrases."""
    if "$ref" in schema_:
        return _expected(validator().schema["$defs"][schema_["$ref"].rsplit("/", 1)[1]])
    if "title" in schema_:
        return [_article(schema_["title"])]
    if "anyOf" in schema_:
        return [phrase for branch in schema_["anyOf"] for phrase in _expected(branch)]
    return [_TYPE_NOUNS[schema_["type"]]]


def _article(noun: str) -> str:
    return ("an " if noun[0] in "aeiou" else "a ") + noun


def did_you_mean(word: str, choices: Any, n: int = 1) -> str:
    """`` (did you mean 'a'?)`` (or ``'a' or 'b'``) for the up to ``n`` choices
    closest to ``word``; empty when none is close."""
    close = difflib.get_close_matches(word, [str(c) for c in choices], n=n)
    return f" (did you mean {' or '.join(map(repr, close))}?)" if close else ""


def describe(value: Any) -> str:
    """A JSON value as it appears in messages: 2.5, string 'abc', a list of 3, true."""
    if isinstance(value, bool):
        return "true" if value else "false"
    if value is None:
        return "null"
    if isinstance(value, NonFinite):
        return f"{value.text} (not a finite number)"
    if isinstance(value, (int, float)):
        text = repr(value)
        return text[:-2] if text.endswith(".0") else text
    if isinstance(value, str):
        return f"string {value!r}"
    if isinstance(value, list):
        return f"a list of {len(value)}" if value else "an empty list"
    return "an object"
