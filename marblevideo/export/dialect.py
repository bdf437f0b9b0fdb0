"""The op sections' dialect as GLSL: kernels/math.cl, kernels/edges.cl and
kernels/ops/*.cl, written once in a small subset of OpenCL C, turned into GLSL
3.30 / GLSL ES 3.00 for the shader exports (kernels/glsl/prelude.glsl defines
the dialect's types and helpers there).

The subset, and what each part becomes:

- the lane types ``vf``, ``vi``, ``vm`` (a mask) stay (the GLSL prelude defines
  them as float, int and bool); masks combine with ``&``, ``|`` and ``|=``,
  which become ``&&``, ``||`` and ``m = m || (...)``;
- a pointer to floats in ``__constant``, ``__global`` or ``LIST_SPACE`` (an op's
  packed row ``p``, the frame's ``lists``, a list's data) becomes an int offset
  into one constant array, ``MV_DATA``: ``p[e]`` reads ``MV_DATA[p + (e)]``, and
  pointer arithmetic is offset arithmetic; ``PARAMS(i)`` (the walk's row of op
  i) likewise;
- a pointer to lanes (``vf *x``: the point, a result) becomes an ``inout``
  parameter, an array of CHAINS where the function indexes it; ``*x`` is ``x``
  and ``&a`` is ``a``;
- ``(type)e`` casts become ``type(e)``; ``const`` and ``inline`` go (GLSL's
  const wants constant initializers); ``fabs``, ``fmin``, ``fmax`` are GLSL's
  ``abs``, ``min``, ``max``.

Anything else of C is refused (:class:`DialectError`), so that a section that
leaves the subset fails when the exports are built or tested, not in a host.
"""

from __future__ import annotations

import re

#: Types a cast may name.
CAST_TYPES = {"vf", "vi", "vu", "vm", "float", "int", "uint", "bool"}
#: Qualifiers of a pointer to floats (a data pointer: an int offset in GLSL).
DATA_SPACES = {"__constant", "__global", "LIST_SPACE"}
#: Calls that return a data pointer.
DATA_CALLS = {"PARAMS"}
#: OpenCL names and their GLSL names.
RENAMES = {"fabs": "abs", "fmin": "min", "fmax": "max"}
#: Tokens dropped.
DROPPED = {"inline", "const"}

_TOKEN = re.compile(
    r"""(?P<ws>[ \t]+|\\\n)|(?P<nl>\n)|(?P<comment>/\*.*?\*/|//[^\n]*)
    |(?P<num>(?:\d+\.\d*|\.\d+|\d+)(?:[eE][+-]?\d+)?[fFuU]?)
    |(?P<id>[A-Za-z_]\w*)
    |(?P<op>\|\||&&|\|=|&=|<<|>>|<=|>=|==|!=|\+=|-=|\*=|/=|\+\+|--|\#\#|[-+*/%&|^!~<>=?:;,.(){}\[\]\#])""",
    re.X | re.S,
)
_VALUE_END = {"id", "num"}


class DialectError(ValueError):
    """A section outside the dialect (file, line and what)."""


def tokens(text: str, where: str = "<source>") -> list[tuple[str, str]]:
    """(kind, text) tokens of ``text``, whitespace and comments kept as they are."""
    out, pos = [], 0
    while pos < len(text):
        m = _TOKEN.match(text, pos)
        if m is None:
            line = text.count("\n", 0, pos) + 1
            raise DialectError(f"{where}:{line}: cannot read {text[pos : pos + 20]!r}")
        out.append((m.lastgroup, m.group()))
        pos = m.end()
    return out


def _significant(toks, k: int, step: int) -> int:
    """The index of the next token from k (step +1 or -1) that is not space."""
    while 0 <= k < len(toks) and toks[k][0] in ("ws", "nl", "comment"):
        k += step
    return k


def _closing(toks, k: int) -> int:
    """The index of the bracket closing the one at k."""
    pairs = {"(": ")", "[": "]", "{": "}"}
    opening, depth = toks[k][1], 0
    for j in range(k, len(toks)):
        if toks[j][1] == opening:
            depth += 1
        elif toks[j][1] == pairs[opening]:
            depth -= 1
            if depth == 0:
                return j
    raise DialectError(f"unbalanced {opening!r}")


class Translator:
    """Turns dialect source into GLSL. ``refs``: names of lane pointers (``inout``
    in GLSL); ``data``: names of data pointers (int offsets); both are gathered
    from every declaration of the sources given to :meth:`learn`."""

    def __init__(self):
        self.refs: set[str] = set()
        self.data: set[str] = set()
        self.arrays: set[str] = set()

    def learn(self, text: str) -> None:
        """Gather the pointer names that ``text`` declares."""
        for m in re.finditer(r"((?:\w+\s+)*)(\w+)\s*\*\s*(\w+)", _without_comments(text)):
            qualifiers = set(m.group(1).split()) | {m.group(2)}
            name = m.group(3)
            if m.group(2) in ("vf", "vi", "vm"):
                self.refs.add(name)
            elif qualifiers & DATA_SPACES and m.group(2) == "float":
                self.data.add(name)
        clash = self.refs & self.data
        if clash:
            raise DialectError(f"names both lane and data pointers: {sorted(clash)}")

    def glsl(self, text: str, where: str = "<source>") -> str:
        """``text`` as GLSL."""
        toks = tokens(text, where)
        return "".join(t for _, t in self._translate(toks, where))

    # ------------------------------------------------------------------ internals

    def _translate(self, toks, where):
        out: list[tuple[str, str]] = []
        k = 0
        pending_close: list[int] = []  # depths at which `|=` opened a group
        depth = 0
        while k < len(toks):
            kind, text = toks[k]
            if kind == "op" and text == "#" and self._line_start(toks, k):
                end = k
                while end < len(toks) and toks[end][0] != "nl":
                    end += 1
                out += self._directive(toks[k:end], where)
                k = end
                continue
            if kind == "id" and text in DROPPED:
                k = _significant(toks, k + 1, 1)
                continue
            if kind == "id" and text in DATA_SPACES:
                k = self._data_declaration(toks, k, out, where)
                continue
            if kind == "id" and self._is_signature(toks, k):
                k = self._signature(toks, k, out, where)
                continue
            if kind == "op" and text == "(" and self._is_cast(toks, k):
                k = self._cast(toks, k, out, where)
                continue
            if kind == "id" and (text in self.data or text in DATA_CALLS):
                k = self._data_index(toks, k, out, where)
                continue
            if kind == "op" and text in ("*", "&") and self._unary(toks, k):
                nxt = _significant(toks, k + 1, 1)
                if toks[nxt][0] == "id" and (toks[nxt][1] in self.refs or text == "&"):
                    k = nxt
                    continue
                raise DialectError(f"{where}: unary {text} outside the dialect")
            if kind == "op" and text in ("&", "|"):
                out.append(("op", text * 2))
                k += 1
                continue
            if kind == "op" and text == "|=":
                target = out[_significant(out, len(out) - 1, -1)][1]
                out += [("op", "="), ("ws", " "), ("id", target), ("ws", " "), ("op", "||")]
                out += [("ws", " "), ("op", "(")]
                pending_close.append(depth)
                k += 1
                continue
            if kind == "op" and text in "([{":
                depth += 1
            elif kind == "op" and text in ")]}":
                depth -= 1
            if kind == "op" and text == ";" and pending_close and pending_close[-1] == depth:
                pending_close.pop()
                out.append(("op", ")"))
            if kind == "id":
                text = RENAMES.get(text, text)
            out.append((kind, text))
            k += 1
        return out

    @staticmethod
    def _line_start(toks, k) -> bool:
        j = k - 1
        while j >= 0 and toks[j][0] == "ws":
            j -= 1
        return j < 0 or toks[j][0] == "nl"

    def _directive(self, line, where):
        """A preprocessor line: a #define's body translated, pragmas dropped."""
        words = [t for kind, t in line if kind == "id"]
        if words[:1] == ["pragma"]:
            return []
        if words[:1] != ["define"]:
            return line
        k = next(j for j, (_, t) in enumerate(line) if t == "define")
        k = _significant(line, k + 1, 1)  # the name
        head_end = k + 1
        if head_end < len(line) and line[head_end][1] == "(":
            head_end = _closing(line, head_end) + 1
        return list(line[:head_end]) + self._translate(list(line[head_end:]), where)

    def _is_signature(self, toks, k) -> bool:
        """Whether toks[k] is a function definition's return type."""
        if toks[k][1] not in CAST_TYPES | {"void"}:
            return False
        name = _significant(toks, k + 1, 1)
        if name >= len(toks) or toks[name][0] != "id":
            return False
        paren = _significant(toks, name + 1, 1)
        if paren >= len(toks) or toks[paren][1] != "(":
            return False
        after = _significant(toks, _closing(toks, paren) + 1, 1)
        return after < len(toks) and toks[after][1] == "{"

    def _signature(self, toks, k, out, where):
        """A function definition's head: pointer parameters as GLSL parameters."""
        name = _significant(toks, k + 1, 1)
        paren = _significant(toks, name + 1, 1)
        close = _closing(toks, paren)
        body_end = _closing(toks, _significant(toks, close + 1, 1))
        body = "".join(t for _, t in toks[close:body_end])
        out += [("id", toks[k][1]), ("ws", " "), toks[name], ("op", "(")]
        params, current = [], []
        for tok in toks[paren + 1 : close]:
            if tok[1] == ",":
                params.append(current)
                current = []
            else:
                current.append(tok)
        if current:
            params.append(current)
        refs = [[t for kind, t in param if kind == "id"][-1] for param in params if param]
        # a function that indexes one of its lane pointers walks every chain: all arrays
        chained = any(re.search(rf"\b{n}\s*\[", body) for n in refs if n in self.refs)
        written = []
        for param in params:
            words = [t for kind, t in param if kind == "id"]
            if not words:
                continue
            pname = words[-1]
            if any(t == "*" for _, t in param):
                base = next(w for w in words if w in CAST_TYPES)
                if pname in self.data:
                    written.append(f"int {pname}")
                elif chained:
                    mode = "in" if "const" in words else "inout"
                    written.append(f"{mode} {base} {pname}[CHAINS]")
                else:
                    written.append(f"inout {base} {pname}")
            else:
                kept = [w for w in words if w not in DROPPED]
                written.append(" ".join(kept))
        out.append(("id", ", ".join(written)))
        out.append(("op", ")"))
        return close + 1

    def _data_declaration(self, toks, k, out, where):
        """``LIST_SPACE const float *name`` as ``int name``."""
        j = k
        while j < len(toks) and toks[j][1] != "*":
            if toks[j][0] == "id" and toks[j][1] not in DATA_SPACES | {"const", "float"}:
                raise DialectError(f"{where}: {toks[j][1]} in a data pointer's type")
            j += 1
        name = _significant(toks, j + 1, 1)
        out += [("id", "int"), ("ws", " "), toks[name]]
        return name + 1

    def _is_cast(self, toks, k) -> bool:
        inner = _significant(toks, k + 1, 1)
        close = _significant(toks, inner + 1, 1)
        if inner >= len(toks) or toks[inner][1] not in CAST_TYPES:
            return False
        if close >= len(toks) or toks[close][1] != ")":
            return False
        before = _significant(toks, k - 1, -1)
        return before < 0 or toks[before][0] != "id"

    def _operand_end(self, toks, k) -> int:
        """The index after the unary expression starting at k."""
        k = _significant(toks, k, 1)
        if toks[k][1] in ("-", "+", "!"):
            return self._operand_end(toks, k + 1)
        if toks[k][1] == "(":
            if self._is_cast(toks, k):
                close = _significant(toks, _significant(toks, k + 1, 1) + 1, 1)
                return self._operand_end(toks, close + 1)
            end = _closing(toks, k) + 1
        elif toks[k][0] in _VALUE_END:
            end = k + 1
        else:
            raise DialectError(f"cast of {toks[k][1]!r}")
        while True:
            nxt = _significant(toks, end, 1)
            if nxt < len(toks) and toks[nxt][1] in ("(", "["):
                end = _closing(toks, nxt) + 1
            else:
                return end

    def _cast(self, toks, k, out, where):
        type_ = toks[_significant(toks, k + 1, 1)][1]
        close = _significant(toks, _significant(toks, k + 1, 1) + 1, 1)
        end = self._operand_end(toks, close + 1)
        inner = self._translate(toks[close + 1 : end], where)
        out += [("id", type_), ("op", "(")] + inner + [("op", ")")]
        return end

    def _data_index(self, toks, k, out, where):
        """``name[e]`` (or ``PARAMS(i)[e]``) as ``MV_DATA[name + (e)]``; the name
        alone (an offset) as it is."""
        end, head = k + 1, [toks[k]]
        if toks[k][1] in DATA_CALLS:
            end = _closing(toks, _significant(toks, k + 1, 1)) + 1
            head += self._translate(toks[k + 1 : end], where)
        nxt = _significant(toks, end, 1)
        if nxt < len(toks) and toks[nxt][1] == "[":
            close = _closing(toks, nxt)
            index = self._translate(toks[nxt + 1 : close], where)
            out += [("id", "MV_DATA"), ("op", "[")] + head + [("op", " + (")]
            out += index + [("op", ")]")]
            return close + 1
        out += head
        return end

    @staticmethod
    def _unary(toks, k) -> bool:
        before = _significant(toks, k - 1, -1)
        if before < 0:
            return True
        kind, text = toks[before]
        return not (kind in _VALUE_END or text in (")", "]"))


def _without_comments(text: str) -> str:
    return re.sub(r"/\*.*?\*/|//[^\n]*", " ", text, flags=re.S)
