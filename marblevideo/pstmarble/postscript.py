"""The PostScript that pst-marble's options hold, read by a small interpreter:
numbers, strings ``(...)``, arrays ``[...]``, procedures ``{...}``, ``/name
... def`` and the arithmetic and stack operators a design uses. Every token
keeps its offset in the file, so a fault names its line and column.

Names the interpreter does not know are handed to ``words`` (the actions, in
:mod:`marblevideo.pstmarble.actions`); a name nobody knows is refused.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass

from marblevideo.errors import UsageError

_TOKEN = re.compile(
    r"%[^\n]*|(?P<s>\()|(?P<open>[\[\]{}])|(?P<lit>/[^\s\[\]{}()/%]*)|(?P<word>[^\s\[\]{}()/%]+)"
)
_NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?$")


class PsFault(UsageError):
    """A design pst-marble's reader cannot take, at an offset of its text."""

    def __init__(self, message: str, at: int):
        self.at = at
        super().__init__(message)


@dataclass(frozen=True)
class Token:
    kind: str  # number, string, mark, close, proc_open, proc_close, literal, name
    value: object
    at: int


@dataclass(frozen=True)
class PsString:
    text: str


@dataclass(frozen=True)
class Proc:
    tokens: tuple[Token, ...]


class _Mark:
    pass


MARK = _Mark()


def tokens(text: str, base: int = 0) -> list[Token]:
    """The tokens of ``text`` (comments dropped); offsets count from ``base``."""
    out, pos = [], 0
    while True:
        m = _TOKEN.search(text, pos)
        if m is None:
            return out
        at = base + m.start()
        if m.group("s"):
            depth, end = 1, m.end()
            while depth and end < len(text):
                depth += {"(": 1, ")": -1}.get(text[end], 0)
                end += 1
            if depth:
                raise PsFault("a string ( is never closed", at)
            out.append(Token("string", PsString(text[m.end() : end - 1]), at))
            pos = end
            continue
        pos = m.end()
        if m.group("open"):
            kind = {"[": "mark", "]": "close", "{": "proc_open", "}": "proc_close"}[m.group("open")]
            out.append(Token(kind, m.group("open"), at))
        elif m.group("lit"):
            out.append(Token("literal", m.group("lit")[1:], at))
        elif m.group("word"):
            word = m.group("word")
            if word == ")":
                raise PsFault("a ) without its (", at)
            if _NUMBER.match(word):
                out.append(Token("number", float(word), at))
            else:
                out.append(Token("name", word, at))


def _binary(f):
    def op(ps: Interpreter, at: int) -> None:
        b, a = ps.pop_number(at), ps.pop_number(at)
        ps.stack.append(f(a, b))

    return op


def _unary(f):
    def op(ps: Interpreter, at: int) -> None:
        ps.stack.append(f(ps.pop_number(at)))

    return op


def _atan(num: float, den: float) -> float:
    return math.degrees(math.atan2(num, den)) % 360.0


OPERATORS: dict[str, Callable] = {
    "add": _binary(lambda a, b: a + b),
    "sub": _binary(lambda a, b: a - b),
    "mul": _binary(lambda a, b: a * b),
    "div": _binary(lambda a, b: a / b),
    "idiv": _binary(lambda a, b: float(int(a / b))),
    "mod": _binary(lambda a, b: float(math.fmod(int(a), int(b)))),
    "exp": _binary(lambda a, b: a**b),
    "atan": _binary(_atan),
    "max": _binary(max),
    "min": _binary(min),
    "neg": _unary(lambda a: -a),
    "abs": _unary(abs),
    "sqrt": _unary(math.sqrt),
    "sin": _unary(lambda a: math.sin(math.radians(a))),
    "cos": _unary(lambda a: math.cos(math.radians(a))),
    "ln": _unary(math.log),
    "log": _unary(math.log10),
    "cvi": _unary(lambda a: float(int(a))),
    "cvr": _unary(float),
    "round": _unary(lambda a: float(math.floor(a + 0.5))),
    "floor": _unary(lambda a: float(math.floor(a))),
    "ceiling": _unary(lambda a: float(math.ceil(a))),
    "truncate": _unary(lambda a: float(int(a))),
}
CONSTANTS = {"pi": math.pi, "e": math.e}


class Interpreter:
    """Runs tokens on a stack; ``words`` maps a name to ``f(interpreter, at)``."""

    def __init__(self, words: dict[str, Callable]):
        self.stack: list = []
        self.words = words
        self.names: dict[str, object] = dict(CONSTANTS)

    def pop(self, at: int, what: str = "a value"):
        if not self.stack or self.stack[-1] is MARK:
            raise PsFault(f"expected {what}, found none", at)
        return self.stack.pop()

    def pop_number(self, at: int) -> float:
        value = self.pop(at, "a number")
        if not isinstance(value, float):
            raise PsFault(f"expected a number, got {describe(value)}", at)
        return value

    def pop_array(self, at: int) -> list:
        value = self.pop(at, "an array [...]")
        if not isinstance(value, list):
            raise PsFault(f"expected an array [...], got {describe(value)}", at)
        return value

    def run(self, toks: list[Token] | tuple[Token, ...]) -> None:
        i = 0
        while i < len(toks):
            tok = toks[i]
            if tok.kind == "proc_open":
                end = _matching(toks, i)
                self.stack.append(Proc(tuple(toks[i + 1 : end])))
                i = end + 1
                continue
            self._one(tok)
            i += 1

    def _one(self, tok: Token) -> None:
        if tok.kind in ("number", "string"):
            self.stack.append(tok.value)
        elif tok.kind == "mark":
            self.stack.append(MARK)
        elif tok.kind == "close":
            if MARK not in self.stack:
                raise PsFault("a ] without its [", tok.at)
            k = len(self.stack) - 1 - self.stack[::-1].index(MARK)
            items = self.stack[k + 1 :]
            del self.stack[k:]
            self.stack.append(items)
        elif tok.kind == "proc_close":
            raise PsFault("a } without its {", tok.at)
        elif tok.kind == "literal":
            self.stack.append(("/", tok.value))
        else:
            self.call(tok.value, tok.at)

    def call(self, name: str, at: int) -> None:
        if name in self.names:
            value = self.names[name]
            if isinstance(value, Proc):
                self.run(value.tokens)
            else:
                self.stack.append(value)
        elif name in OPERATORS:
            OPERATORS[name](self, at)
        elif name in STACK_WORDS:
            STACK_WORDS[name](self, at)
        elif name in self.words:
            self.words[name](self, at)
        else:
            raise PsFault(f"{name}: unknown name (no marblevideo counterpart)", at)


def _matching(toks, i: int) -> int:
    depth = 0
    for k in range(i, len(toks)):
        depth += {"proc_open": 1, "proc_close": -1}.get(toks[k].kind, 0)
        if depth == 0:
            return k
    raise PsFault("a { is never closed", toks[i].at)


def describe(value) -> str:
    if isinstance(value, float):
        return f"{value:g}"
    if isinstance(value, list):
        return "an array"
    if isinstance(value, PsString):
        return f"({value.text})"
    if isinstance(value, Proc):
        return "a procedure"
    return "a name" if isinstance(value, tuple) else "nothing"


def _def(ps: Interpreter, at: int) -> None:
    value, key = ps.pop(at), ps.pop(at, "a /name")
    if not isinstance(key, tuple):
        raise PsFault("def needs /name value", at)
    ps.names[key[1]] = value


def _repeat(ps: Interpreter, at: int) -> None:
    proc = ps.pop(at, "a procedure")
    count = int(ps.pop_number(at))
    if not isinstance(proc, Proc):
        raise PsFault("repeat needs a procedure {...}", at)
    for _ in range(count):
        ps.run(proc.tokens)


def _for(ps: Interpreter, at: int) -> None:
    proc = ps.pop(at, "a procedure")
    limit, step, value = ps.pop_number(at), ps.pop_number(at), ps.pop_number(at)
    if not isinstance(proc, Proc) or step == 0:
        raise PsFault("for needs start step limit {...} with a non-zero step", at)
    while (step > 0 and value <= limit + 1e-9) or (step < 0 and value >= limit - 1e-9):
        ps.stack.append(value)
        ps.run(proc.tokens)
        value += step


def _get(ps: Interpreter, at: int) -> None:
    index = int(ps.pop_number(at))
    array = ps.pop_array(at)
    if not 0 <= index < len(array):
        raise PsFault(f"get: index {index} outside an array of {len(array)}", at)
    ps.stack.append(array[index])


STACK_WORDS: dict[str, Callable] = {
    "def": _def,
    "repeat": _repeat,
    "for": _for,
    "get": _get,
    "length": lambda ps, at: ps.stack.append(float(len(ps.pop_array(at)))),
    "dup": lambda ps, at: ps.stack.append(ps.stack[-1] if ps.stack else ps.pop(at)),
    "pop": lambda ps, at: ps.pop(at),
    "exch": lambda ps, at: ps.stack.extend([ps.pop(at), ps.pop(at)]),
}
