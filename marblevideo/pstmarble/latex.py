"""``\\psMarble[options](w,h)`` (or ``(x0,y0)(x1,y1)``) found in a LaTeX or .pst
file: its options' texts (with their offsets in the file) and its corners."""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from marblevideo.limits import NUMBER_LIMIT
from marblevideo.pstmarble.postscript import PsFault

_COMMAND = re.compile(r"\\psMarble\b")
_PSSET = re.compile(r"\\psset\s*\[\s*pst-marble\s*\]\s*\{")
_CORNER = re.compile(r"\s*\(\s*([^,()]+?)\s*,\s*([^,()]+?)\s*\)")


@dataclass
class Marble:
    """The corners (x0, y0, x1, y1) and the options: key -> (text, offset)."""

    corners: tuple[float, float, float, float]
    options: dict[str, tuple[str, int]] = field(default_factory=dict)


def _strip_comments(text: str) -> str:
    """TeX comments (an unescaped % to the line's end) blanked, offsets kept."""
    return re.sub(r"(?<!\\)%[^\n]*", lambda m: " " * len(m.group()), text)


def _balanced(text: str, at: int, open_: str, close: str) -> int:
    """The offset just past the ``close`` matching ``text[at] == open_``."""
    depth = 0
    for k in range(at, len(text)):
        if text[k] == open_:
            depth += 1
        elif text[k] == close:
            depth -= 1
            if depth == 0:
                return k + 1
    raise PsFault(f"\\psMarble: a {open_} is never closed", at)


def _split_options(text: str, base: int) -> dict[str, tuple[str, int]]:
    """key=value pairs split at commas outside braces; a braced value unwrapped."""
    out, depth, start = {}, 0, 0
    for k, ch in enumerate(text + ","):
        depth += {"{": 1, "}": -1}.get(ch, 0)
        if depth < 0:
            raise PsFault("\\psMarble: a } without its {", base + k)
        if ch == "," and depth == 0:
            part = text[start:k]
            if part.strip():
                key, eq, value = part.partition("=")
                offset = base + start + len(key) + len(eq)
                value_start = len(value) - len(value.lstrip())
                value = value.strip()
                if value.startswith("{") and value.endswith("}"):
                    value, value_start = value[1:-1], value_start + 1
                out[key.strip()] = (value, offset + value_start)
            start = k + 1
    if depth:
        raise PsFault("\\psMarble: a { in this option is never closed", base + start)
    return out


def _number(text: str, at: int) -> float:
    try:
        return float(text)
    except ValueError:
        raise PsFault(f"\\psMarble: expected a number, got {text!r}", at) from None


def _defaults(text: str, before: int) -> dict[str, tuple[str, int]]:
    """The options ``\\psset[pst-marble]{...}`` sets before offset ``before``."""
    options: dict[str, tuple[str, int]] = {}
    for m in _PSSET.finditer(text, 0, before):
        end = _balanced(text, m.end() - 1, "{", "}")
        options.update(_split_options(text[m.end() : end - 1], m.end()))
    return options


def find_marble(text: str) -> Marble | None:
    """The first ``\\psMarble`` of ``text``; None when there is none."""
    clean = _strip_comments(text)
    m = _COMMAND.search(clean)
    if m is None:
        return None
    options = _defaults(clean, m.start())
    pos = m.end()
    while pos < len(clean) and clean[pos].isspace():
        pos += 1
    if pos < len(clean) and clean[pos] == "[":
        end = _balanced(clean, pos, "[", "]")
        options.update(_split_options(clean[pos + 1 : end - 1], pos + 1))
        pos = end
    corners = []
    for _ in range(2):
        c = _CORNER.match(clean, pos)
        if c is None:
            break
        corners.append((_number(c.group(1), c.start(1)), _number(c.group(2), c.start(2))))
        pos = c.end()
    if not corners:
        raise PsFault("\\psMarble needs its size (w,h)", m.start())
    if len(corners) == 1:
        w, h = corners[0]
        x0, y0, x1, y1 = -w / 2, -h / 2, w / 2, h / 2
    else:
        (x0, y0), (x1, y1) = corners
    if not (x1 - x0 > 0 and y1 - y0 > 0 and max(map(abs, (x0, y0, x1, y1))) < NUMBER_LIMIT):
        raise PsFault(f"\\psMarble: expected a size > 0 (and under {NUMBER_LIMIT:g})", m.end())
    return Marble((x0, y0, x1, y1), options)
