r"""A small C99 writer with constant folding, shared by the emitters (no public names).

A value is either a Python ``float`` — a constant of the robot, known when the code is
generated — or a ``str`` — a C expression (usually the name of a ``const`` temporary).
Arithmetic on values folds constants: ``0·x`` disappears, ``1·x`` is ``x``, two constants
multiply in Python, so that the emitted code keeps only the operations that depend on the
joint values. Every non-trivial result is bound to a named temporary
(:meth:`CWriter.let`), which keeps the output readable line by line.

Code is always written as ``double`` C; :func:`to_float32` turns it into ``float`` C
(``float`` for ``double``, an ``f`` on every floating literal, ``sinf`` for ``sin`` …) on the
code part of each line, leaving comments alone.
"""
from __future__ import annotations

import math
import re
from collections import Counter
from typing import Iterable, Sequence, Union

from robokit.errors import InputError

Val = Union[float, str]

#: Constants closer than this to 0 (or ±1) are folded to exactly 0 (±1): Pinocchio's axes
#: carry round-off of 1e-17; folding changes results by less than 1e-14 (relative).
SNAP = 1e-14

# used with fullmatch (``$`` would accept a trailing newline)
_IDENT = re.compile(r"[A-Za-z_][A-Za-z_0-9]*(\[[0-9]+\])?")
_PRODUCT = re.compile(r"[A-Za-z_0-9.\[\]]+( \* [A-Za-z_0-9.\[\]]+)*")


def snap(x: float) -> float:
    """x with round-off near 0 and ±1 removed (see :data:`SNAP`)."""
    x = float(x)
    if abs(x) < SNAP:
        return 0.0
    if abs(x - 1.0) < SNAP:
        return 1.0
    if abs(x + 1.0) < SNAP:
        return -1.0
    return x


_ASCII = {"\u2013": "-", "\u2014": "-", "\u2212": "-", "\u00b0": " deg", "\u00d7": "x", "\u2192": "->",
          "\u03b8": "th", "\u03b1": "al", "\u03c9": "w", "\u2009": " ", "\u00b2": "^2",
          **{chr(0x2080 + i): str(i) for i in range(10)}}


def safe_comment(text: str) -> str:
    """text fit for a C comment: printable ASCII, no ``*/`` (names come from robot files)."""
    text = "".join(_ASCII.get(ch, ch) for ch in str(text))
    out = "".join(ch if 32 <= ord(ch) < 127 else "?" for ch in text)
    return out.replace("*/", "* /").replace("/*", "/ *")


def c_string(text: str) -> str:
    """A C string literal of text (UTF-8; bytes outside printable ASCII as octal escapes)."""
    out = []
    for b in str(text).encode("utf-8"):
        ch = chr(b)
        out.append(ch if 32 <= b < 127 and ch not in '"\\?' else f"\\{b:03o}")
    return '"' + "".join(out) + '"'


def lit(x: float) -> str:
    """A C double literal that reads back as exactly ``x`` (``repr`` round-trips); a constant that
    is not finite (an overflow while folding) is refused, never written as ``HUGE_VAL``."""
    x = float(x)
    if not math.isfinite(x):
        raise InputError(f"codegen: a constant of the generated code is {x!r} (the robot's numbers overflow a "
                         "double when combined)")
    s = repr(x)
    if "e" not in s and "." not in s:
        s += ".0"
    return s


def atom(v: Val) -> str:
    """v as a C operand that can be multiplied without parentheses."""
    if isinstance(v, float):
        return lit(v) if v >= 0.0 else f"({lit(v)})"
    if _PRODUCT.fullmatch(v) or _one_group(v):
        return v
    return f"({v})"


def _one_group(v: str) -> bool:
    """True if v is one parenthesised group or one function call: ``(a + b)``, ``atan2(y, x)``."""
    m = re.match(r"^[A-Za-z_][A-Za-z_0-9]*\(", v) or (v.startswith("(") and re.match(r"^", v))
    if not m or not v.endswith(")"):
        return False
    depth = 0
    start = v.index("(")
    for k, ch in enumerate(v[start:], start):
        depth += ch == "("
        depth -= ch == ")"
        if depth == 0 and k != len(v) - 1:
            return False
    return True


def lin(terms: Iterable[tuple[float, Val]], const: float = 0.0) -> Val:
    """Σ cₖ·vₖ + const, folded: a float when every term is constant, else a C expression."""
    parts: list[tuple[float, str]] = []
    for c, v in terms:
        c = float(c)
        if c == 0.0:
            continue
        if isinstance(v, float):
            const += c * v
            continue
        if v.startswith("-") and _IDENT.fullmatch(v[1:]):
            c, v = -c, v[1:]
        parts.append((c, v))
    if not parts:
        return float(const)
    out = ""
    for k, (c, v) in enumerate(parts):
        neg = c < 0.0
        mag = -c if neg else c
        body = atom(v) if mag == 1.0 else f"{lit(mag)} * {atom(v)}"
        if k == 0 and c == 1.0:  # (a + b) + c is a + b + c in C (left to right): no parentheses needed
            body = v[1:-1] if v.startswith("(") and _one_group(v) else v
        if k == 0:
            out = f"-{body}" if neg else body
        else:
            out += f" - {body}" if neg else f" + {body}"
    if const != 0.0:
        out += f" - {lit(-const)}" if const < 0.0 else f" + {lit(const)}"
    return out


def mul(a: Val, b: Val) -> Val:
    """a·b folded."""
    if isinstance(a, float) and isinstance(b, float):
        return a * b
    if isinstance(a, float):
        return lin([(a, b)])
    if isinstance(b, float):
        return lin([(b, a)])
    return f"{atom(a)} * {atom(b)}"


def add(*vals: Val) -> Val:
    """Σ vals folded."""
    return lin([(1.0, v) for v in vals])


def sub(a: Val, b: Val) -> Val:
    """a − b folded."""
    return lin([(1.0, a), (-1.0, b)])


def dot(a: Sequence[Val], b: Sequence[Val]) -> Val:
    """Σ aₖbₖ folded (products of two expressions kept as they are)."""
    terms: list[tuple[float, Val]] = []
    for x, y in zip(a, b):
        if isinstance(x, float) and isinstance(y, float):
            terms.append((x * y, 1.0))
        elif isinstance(x, float):
            terms.append((x, y))
        elif isinstance(y, float):
            terms.append((y, x))
        else:
            terms.append((1.0, f"{atom(x)} * {atom(y)}"))
    return lin(terms)


def cross(a: Sequence[Val], b: Sequence[Val]) -> list[Val]:
    """a × b folded (3-vectors)."""
    return [sub(mul(a[1], b[2]), mul(a[2], b[1])),
            sub(mul(a[2], b[0]), mul(a[0], b[2])),
            sub(mul(a[0], b[1]), mul(a[1], b[0]))]


class CWriter:
    """Lines of C being written; ``let`` binds folded values to named ``const`` temporaries."""

    def __init__(self, indent: str = "    ") -> None:
        self.lines: list[str] = []
        self.indent = indent
        self.names: set[str] = set()

    def line(self, text: str = "") -> None:
        self.lines.append(self.indent + text if text else "")

    def comment(self, text: str) -> None:
        self.lines.append(f"{self.indent}/* {safe_comment(text)} */")

    def let(self, name: str, value: Val) -> Val:
        """``const double name = value;`` unless value is a constant or already a plain name (then
        value itself is returned and nothing is emitted)."""
        if isinstance(value, float):
            return value
        if _IDENT.fullmatch(value):
            return value
        if name in self.names:
            raise AssertionError(f"codegen: temporary {name} emitted twice")
        self.names.add(name)
        self.line(f"const double {name} = {value};")
        return name

    def assign(self, target: str, value: Val) -> None:
        """``target = value;`` (an output array element)."""
        self.line(f"{target} = {lit(value) if isinstance(value, float) else value};")

    def prune(self) -> None:
        """Drop the ``const`` temporaries nothing reads (so ``-Wunused-variable`` stays quiet), until
        none is left."""
        decl = re.compile(r"^\s*const double ([A-Za-z_][A-Za-z_0-9]*) = ")
        word = re.compile(r"[A-Za-z_][A-Za-z_0-9]*")
        counts = Counter(t for line in self.lines for t in word.findall(line))
        alive = [True] * len(self.lines)
        changed = True
        while changed:
            changed = False
            for k, line in enumerate(self.lines):
                m = decl.match(line) if alive[k] else None
                if m and counts[m.group(1)] == 1:
                    alive[k] = False
                    counts.subtract(word.findall(line))
                    changed = True
        self.lines = [line for line, keep in zip(self.lines, alive) if keep]

    def text(self) -> str:
        return "\n".join(self.lines)


_FLOAT_LIT = re.compile(r"(?<![\w.])((?:\d+\.\d*|\.\d+)(?:[eE][+-]?\d+)?|\d+[eE][+-]?\d+)(?![\w.])")
_MATH = re.compile(r"\b(sin|cos|tan|atan|atan2|acos|asin|cbrt|sqrt|fabs|hypot|remainder|fmod|fmax|fmin|floor)\(")


def _float_code(code: str) -> str:
    code = re.sub(r"\bdouble\b", "float", code)
    code = re.sub(r"\bHUGE_VAL\b", "HUGE_VALF", code)
    code = _MATH.sub(lambda m: m.group(1) + "f(", code)
    return _FLOAT_LIT.sub(lambda m: m.group(1) + "f", code)


def to_float32(text: str) -> str:
    """The same C with ``float`` for ``double`` (see the module docstring); comments untouched."""
    out = []
    in_comment = False
    for line in text.split("\n"):
        res = ""
        rest = line
        while rest:
            if in_comment:
                end = rest.find("*/")
                if end < 0:
                    res += rest
                    rest = ""
                else:
                    res += rest[: end + 2]
                    rest = rest[end + 2:]
                    in_comment = False
                continue
            starts = [i for i in (rest.find("/*"), rest.find("//"), rest.find('"')) if i >= 0]
            if not starts:
                res += _float_code(rest)
                break
            i = min(starts)
            res += _float_code(rest[:i])
            rest = rest[i:]
            if rest.startswith("//"):
                res += rest
                rest = ""
            elif rest.startswith('"'):
                end = rest.find('"', 1)
                res += rest[: end + 1]
                rest = rest[end + 1:]
            else:
                in_comment = True
        out.append(res)
    return "\n".join(out)


#: The normal range of each target type: a constant written into the C must be 0 or have a
#: magnitude in [smallest normal, largest finite] (a larger one does not compile under
#: ``-Werror``, a smaller one is truncated to zero or kept as a subnormal that single-precision
#: FPUs flush to zero).
RANGES = {False: (2.2250738585072014e-308, 1.7976931348623157e308),  # DBL_MIN, DBL_MAX
          True: (1.1754943508222875e-38, 3.4028234663852886e38)}     # FLT_MIN, FLT_MAX

_COMMENT_OR_STRING = re.compile(r'/\*.*?\*/|//[^\n]*|"(?:\\.|[^"\\\n])*"', re.S)
_ANY_LIT = re.compile(r"(?<![\w.])((?:\d+\.\d*|\.\d+)(?:[eE][+-]?\d+)?|\d+[eE][+-]?\d+)f?(?![\w.])")
_DEFINITION = re.compile(r"^(?:#define (\w+)|[A-Za-z_][\w ]*?\b(\w+)\s*(?:\(|\[|=))")


def out_of_range(x: float, float32: bool) -> bool:
    """Whether the constant ``x`` cannot be written as a normal number of the target type
    (see :data:`RANGES`)."""
    tiny, huge = RANGES[float32]
    a = abs(float(x))
    return not (a == 0.0 or tiny <= a <= huge)


def check_literals(text: str, float32: bool, file: str) -> None:
    """Refuse generated C with a floating constant outside the target type's normal range
    (:data:`RANGES`), naming the function, table or macro that holds it (comments and strings
    are skipped).

    Raises
    ------
    InputError
        ``codegen --float32: FILE: NAME_rnea holds the constant 1e+39, outside float's range …``.
    """
    code = _COMMENT_OR_STRING.sub(lambda m: "\n" * m.group(0).count("\n"), text)
    where = "the file"
    for line in code.split("\n"):
        d = _DEFINITION.match(line)
        if d:
            where = d.group(1) or d.group(2)
        for m in _ANY_LIT.finditer(line):
            x = float(m.group(1))
            if out_of_range(x, float32):
                kind = "float" if float32 else "double"
                tiny, huge = RANGES[float32]
                raise InputError(f"codegen{' --float32' if float32 else ''}: {file}: {where} holds the constant "
                                 f"{m.group(1)}, outside {kind}'s normal range ({tiny:.3g} to {huge:.3g} in "
                                 "magnitude), computed from the robot's numbers; a robot of such sizes cannot be "
                                 f"written as {kind} C")
