"""The PostScript that pst-marble's options hold, read by a small interpreter:
numbers, strings ``(...)``, arrays ``[...]``, procedures ``{...}``, ``/name
... def`` and the arithmetic and stack operators a design uses. Every token
keeps its offset in the file, so a fault names its line and column.

Names the interpreter does not know are handed to ``words`` (the actions, in
:mod:`marblevideo.pstmarble.actions`); a name nobody knows is refused.

The work a design asks for is bounded before it is done (:mod:`marblevideo.limits`):
a loop's turns and every value or name evaluated count against ``PS_STEPS``, the
stack holds at most ``PS_STACK`` values, procedures nest at most ``PS_DEPTH``
deep, and a count (an action's drops, ``tines``) is checked before anything is
made of it. Arithmetic that fails (a division by 0, an overflow) is a fault at
its operator.
"""

from __future__ import annotations

import math
import re
from collections.abc import Callable
from dataclasses import dataclass

from marblevideo.errors import UsageError
from marblevideo.limits import MAX_COUNT, PS_DEPTH, PS_STACK, PS_STEPS

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
    kind: str  # number, string, mark, close, proc, literal, name
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
    """The tokens of ``text`` (comments dropped); offsets count from ``base``. A
    procedure ``{...}`` is one token, its value the :class:`Proc` of its tokens."""
    out, pos = [], 0
    opened: list[tuple[list[Token], int]] = []  # the enclosing lists and where each { is
    while True:
        m = _TOKEN.search(text, pos)
        if m is None:
            if opened:
                raise PsFault("a { is never closed", opened[-1][1])
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
        if m.group("open") == "{":
            opened.append((out, at))
            out = []
        elif m.group("open") == "}":
            if not opened:
                raise PsFault("a } without its {", at)
            body = tuple(out)
            out, start = opened.pop()
            out.append(Token("proc", Proc(body), start))
        elif m.group("open"):
            kind = {"[": "mark", "]": "close"}[m.group("open")]
            out.append(Token(kind, m.group("open"), at))
        elif m.group("lit"):
            out.append(Token("literal", m.group("lit")[1:], at))
        elif m.group("word"):
            word = m.group("word")
            if word == ")":
                raise PsFault("a ) without its (", at)
            if _NUMBER.match(word):
                if not math.isfinite(float(word)):
                    raise PsFault(f"{word}: a number out of range", at)
                out.append(Token("number", float(word), at))
            else:
                out.append(Token("name", word, at))


def _power(a: float, b: float) -> float:
    value = a**b
    if isinstance(value, complex):
        raise ValueError("a negative number to a fractional power")
    return value


def _finite(value: float) -> float:
    if not math.isfinite(value):
        raise ArithmeticError(f"the result is out of range ({value})")
    return value


def _binary(f):
    def op(ps: Interpreter, at: int) -> None:
        b, a = ps.pop_number(at), ps.pop_number(at)
        ps.stack.append(_finite(f(a, b)))

    return op


def _unary(f):
    def op(ps: Interpreter, at: int) -> None:
        ps.stack.append(_finite(f(ps.pop_number(at))))

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
    "exp": _binary(_power),
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
        self.steps = 0  # spent of PS_STEPS
        self.depth = 0  # procedures running

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

    def pop_count(
        self, at: int, action: str, noun: str, limit: int = MAX_COUNT, name: str = "MAX_COUNT"
    ) -> int:
        """The whole part of a count of ``noun`` for ``action``, 0 to ``limit`` (the
        limit called ``name`` in :mod:`marblevideo.limits`), checked before anything
        is made of it."""
        value = self.pop_number(at)
        if not value >= 0:  # NaN too
            raise PsFault(f"{action}: {value:g} {noun}, expected a count of 0 or more", at)
        if value > limit:
            raise PsFault(f"{action}: {value:g} {noun}, over the limit of {limit:,} ({name})", at)
        return int(value)

    def spend(self, steps: float, at: int, what: str) -> None:
        """Count ``steps`` against PS_STEPS before they are taken."""
        self.afford(steps, at, what)
        self.steps += int(steps)

    def afford(self, steps: float, at: int, what: str) -> None:
        """PsFault when ``steps`` more would take the design over PS_STEPS."""
        if not self.steps + steps <= PS_STEPS:  # NaN too
            raise PsFault(
                f"{what}: {steps:g} steps, over the limit of {PS_STEPS:,} a design may take "
                f"({self.steps:,} taken; PS_STEPS)",
                at,
            )

    def run(self, toks: list[Token] | tuple[Token, ...]) -> None:
        self.depth += 1
        try:
            if self.depth > PS_DEPTH and toks:
                raise PsFault(
                    f"procedures nested over the limit of {PS_DEPTH} (PS_DEPTH)", toks[0].at
                )
            for tok in toks:
                if self.steps >= PS_STEPS:
                    raise PsFault(f"the design takes over {PS_STEPS:,} steps (PS_STEPS)", tok.at)
                self.steps += 1
                self._one(tok)
                if len(self.stack) > PS_STACK:
                    raise PsFault(
                        f"{len(self.stack):,} values on the stack, over the limit of "
                        f"{PS_STACK:,} (PS_STACK)",
                        tok.at,
                    )
        finally:
            self.depth -= 1

    def _one(self, tok: Token) -> None:
        if tok.kind in ("number", "string", "proc"):
            self.stack.append(tok.value)
        elif tok.kind == "mark":
            self.stack.append(MARK)
        elif tok.kind == "close":
            k = next((k for k in range(len(self.stack) - 1, -1, -1) if self.stack[k] is MARK), -1)
            if k < 0:
                raise PsFault("a ] without its [", tok.at)
            items = self.stack[k + 1 :]
            del self.stack[k:]
            self.stack.append(items)
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
            return
        f = OPERATORS.get(name) or STACK_WORDS.get(name) or self.words.get(name)
        if f is None:
            raise PsFault(f"{name}: unknown name (no marblevideo counterpart)", at)
        try:
            f(self, at)
        except PsFault:
            raise
        except (ArithmeticError, ValueError) as exc:  # a division by 0, an overflow
            raise PsFault(f"{name}: {exc}", at) from None


def bounded(items, action: str, noun: str, at: int):
    """``items``, at most MAX_COUNT of them (the drops an action makes)."""
    if len(items) > MAX_COUNT:
        limit = f"over the limit of {MAX_COUNT:,} (MAX_COUNT)"
        raise PsFault(f"{action}: {len(items):,} {noun}, {limit}", at)
    return items


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
    count = ps.pop_number(at)
    if not isinstance(proc, Proc):
        raise PsFault("repeat needs a procedure {...}", at)
    turns = max(count, 0.0)
    ps.spend(turns, at, "repeat")  # every turn is a step, before any is taken
    for _ in range(int(turns)):
        ps.run(proc.tokens)


def _for(ps: Interpreter, at: int) -> None:
    proc = ps.pop(at, "a procedure")
    limit, step, value = ps.pop_number(at), ps.pop_number(at), ps.pop_number(at)
    if not isinstance(proc, Proc) or step == 0:
        raise PsFault("for needs start step limit {...} with a non-zero step", at)
    ps.afford(max((limit - value) / step, 0.0), at, "for")  # its turns, before any
    if value + step == value:
        raise PsFault(f"for: a step of {step:g} is lost in {value:g}", at)
    while (step > 0 and value <= limit + 1e-9) or (step < 0 and value >= limit - 1e-9):
        ps.spend(1, at, "for")
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
