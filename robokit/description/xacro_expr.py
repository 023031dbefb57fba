r"""robokit's interpreter for xacro expressions: ``${…}`` and ``$(eval …)``.

The ``xacro`` program evaluates every expression with Python's ``eval`` behind a thin filter
(a top-level ``__`` is refused; the same gadget inside a ``lambda`` body is not), so a robot
file could run any code. robokit parses each expression with :mod:`ast` and **interprets** it
itself: nothing a file writes ever reaches ``eval``, and every value an expression produces is
plain data. What the xacro program evaluates, this interpreter evaluates the same way, within
bounds:

* literals: numbers, strings, ``True``/``False``/``None``, lists, tuples, dicts, sets (with
  ``*``/``**`` unpacking); names of properties, macro parameters and arguments (``true`` and
  ``false`` too inside ``$(eval …)``);
* every Python operator on data (``+ - * / // % ** << >> & | ^ ~``, comparisons, ``and``/``or``/
  ``not``, ``a if c else b``, subscripts and slices), ``%``-formatting, f-strings;
* list, set and dict comprehensions and generator expressions (``[x * 2 for x in l if x]``);
* calls of the allowed functions, with positional, keyword, ``*args`` and ``**kwargs``
  arguments: the ``math`` functions and constants (also as ``math.sin``); the builtins xacro
  offers (``abs all any bool dict divmod enumerate filter float frozenset int len list map max
  min ord range repr reversed round set sorted str sum tuple zip``, also as ``python.len``) —
  ``map``, ``filter``, ``sorted(key=…)``, ``min``/``max(key=…)`` take an allowed function;
  the read-only methods of strings (``upper split join format replace startswith`` …), lists
  (``index count``) and dicts (``get keys values items``); the xacro helpers the caller
  passes (``xacro.load_yaml``, ``xacro.arg`` …);
* attribute access to the keys of a loaded YAML mapping or of an include's namespace.

Refused, with one line naming the file and the expression: attribute access to anything not
listed (``__class__``, ``func_globals``, ``str.encode``), ``lambda`` (functions are never
values here: a property only ever holds data), ``:=``, calls to anything not listed (``open``,
``type``, ``vars``, ``getattr``, ``hash``, ``complex``, ``isinstance``), methods that change a
value in place (``list.append``, ``dict.update``), ``format`` fields with attribute or index
access (``'{0.__class__}'``) and nested specifications.

**Growth is checked before it happens.** Every operation whose result can be larger than its
operands — ``+`` and ``*`` on strings, lists and tuples, integer ``*``, ``**`` and ``<<``,
``str.join``, ``str.replace``, ``str.format``, ``%``, f-strings, ``str``/``repr`` of a value,
``center``/``ljust``/``zfill``, ``list``/``sorted``/``zip``/``enumerate``/``dict``/``range``
/``map`` and the comprehensions, ``math.factorial``/``comb``/``perm``/``prod``/``lcm`` — first
computes an upper bound of its result's size from its operands (in time bounded by the limit,
whatever the operands), and is refused if that bound exceeds :data:`MAX_STRING` characters and
items (integers: :data:`MAX_INT_BITS` bits; format widths and precisions: :data:`MAX_PRECISION`
digits). Every value is checked again after it is built, every expression evaluates at most
:data:`MAX_STEPS` nodes (loop iterations included) and builds at most :data:`MAX_WORK` items
in all.
"""
from __future__ import annotations

import ast
import functools
import math
import operator
import re
import string
import warnings
from typing import Any, Callable, Iterable, Iterator, Mapping

from robokit.errors import InputError

__all__ = ["MAX_EXPRESSION", "MAX_INT_BITS", "MAX_PRECISION", "MAX_STEPS", "MAX_STRING", "MAX_WORK", "UnsafeXacro",
           "evaluate"]

#: Longest ``${…}`` expression accepted (characters).
MAX_EXPRESSION = 10_000
#: Largest value an expression may produce or hold: characters of strings plus items of lists,
#: tuples, sets and dicts, counted through every level (an integer beyond 64 bits counts its digits).
MAX_STRING = 100_000
#: Largest integer an expression may produce, in bits.
MAX_INT_BITS = 4096
#: Largest precision of a format (``'%.1000f'``, ``'{:.1000}'``), in digits.
MAX_PRECISION = 1000
#: Most syntax-tree nodes one expression evaluates (each loop iteration counts).
MAX_STEPS = 100_000
#: Most characters and items one expression may build in all (a loop building many values).
MAX_WORK = 100 * MAX_STRING
#: Deepest nesting of lists, tuples and dicts in a value.
MAX_VALUE_DEPTH = 32


class UnsafeXacro(InputError):
    """A xacro file asked for something robokit does not do: code, a file outside its roots, the
    environment, unbounded work. The message names the file and the expression or element.

    A subclass of :class:`~robokit.errors.InputError` (so the CLI exits with status 2).

    Attributes
    ----------
    args : tuple
        ``(message,)``, as for any exception: one line naming the file and what was refused.

    Examples
    --------
    >>> issubclass(UnsafeXacro, ValueError)
    True
    """


class Refused(Exception):
    """Internal: why an expression is refused (turned into :class:`UnsafeXacro` with the file)."""


# --------------------------------------------------------------------------- sizes
_TABLE_TYPES = ("NameSpace", "YamlDictWrapper", "YamlListWrapper")


def is_table(v: Any) -> bool:
    """A xacro include namespace (``<xacro:include ns=...>``) or a loaded YAML mapping or list:
    data whose size was bounded where it was made (read from a file, or built from checked values)."""
    return type(v).__name__ in _TABLE_TYPES


def _int_size(v: int) -> int:
    bits = v.bit_length()
    return 1 if bits <= 64 else int(bits * 0.30103) + 1


def _measure(v: Any, limit: int, leaf: Callable[[Any, int], int], container: Callable[[Any], int]) -> int:
    """Sum of ``leaf(x, room left)`` over the non-container values in ``v`` and ``container(c)``
    over its lists, tuples, sets and dicts (keys and values), through every level, without
    recursion; stops once past ``limit`` (so the time is bounded by ``limit``, whatever ``v`` is)."""
    total = 0
    stack = [v]
    while stack:
        x = stack.pop()
        if isinstance(x, (dict, list, tuple, set, frozenset)):
            total += container(x)
            if total > limit:
                return total
            if isinstance(x, dict):
                stack.extend(dict.keys(x))
                stack.extend(dict.values(x))
            else:
                stack.extend(list.__iter__(x) if isinstance(x, list) else x)
        else:
            total += leaf(x, limit - total)
        if total > limit:
            return total
    return total


def _leaf_size(x: Any, _room: int) -> int:
    if isinstance(x, str):
        return len(x)
    if isinstance(x, int) and not isinstance(x, bool):
        return _int_size(x)
    return 1


def size_of(v: Any, limit: int = MAX_STRING) -> int:
    """Characters and items in ``v`` through every level; counting stops once past ``limit``
    (so the time is bounded by ``limit``, whatever ``v`` is)."""
    return _measure(v, limit, _leaf_size, len)


def _repr_str_bound(s: str, limit: int = MAX_STRING) -> int:
    """``len(repr(s))``: computed for a string within ``limit`` (at most 10 characters each), else
    a lower bound that already exceeds it."""
    return len(repr(s)) if len(s) <= limit else len(s) + 2


def _leaf_text(x: Any, room: int) -> int:
    if isinstance(x, str):
        return _repr_str_bound(x, room)
    if isinstance(x, bool) or x is None:
        return 5
    if isinstance(x, float):
        return 24
    if isinstance(x, int):
        return int(x.bit_length() * 0.30103) + 2
    return 64


def _container_text(x: Any) -> int:
    # brackets and separators ("frozenset({…})"); a dict's ": " too
    return 2 + 4 * len(x) if isinstance(x, dict) else 12 + 2 * len(x)


def text_bound(v: Any, limit: int = MAX_STRING, top: bool = True) -> int:
    """An upper bound of ``len(str(v))`` (``top=False``: of ``len(repr(v))``); stops once past ``limit``."""
    if isinstance(v, str):
        return len(v) if top else _repr_str_bound(v, limit)
    return _measure(v, limit, _leaf_text, _container_text)


def _refuse_size(what: str, n: int) -> Refused:
    return Refused(f"{what} of more than {MAX_STRING} characters and items (about {n})")


def _need(what: str, n: int) -> None:
    """Refuse unless an estimated result size ``n`` is within :data:`MAX_STRING`."""
    if n > MAX_STRING:
        raise _refuse_size(what, n)


def _need_bits(what: str, bits: float) -> None:
    if bits > MAX_INT_BITS:
        raise Refused(f"{what} of about {int(bits)} bits (at most {MAX_INT_BITS})")


def check_value(v: Any) -> Any:
    """``v`` if it is plain data (numbers, strings, lists/tuples/sets/dicts of them, a YAML or
    include table) of bounded size, else :class:`Refused`."""
    if v is None or isinstance(v, (bool, float)):
        return v
    if isinstance(v, int):
        if v.bit_length() > MAX_INT_BITS:
            _need_bits("an integer", v.bit_length())
        return v
    if is_table(v):
        return v
    if isinstance(v, str):
        _need("a string", len(v))
        return v
    if not isinstance(v, (list, tuple, set, frozenset, dict)):
        raise Refused(f"a value of type {type(v).__name__}")
    n = size_of(v)
    _need("a value", n)
    stack: list[tuple[Any, int]] = [(v, 0)]
    while stack:
        x, depth = stack.pop()
        if depth > MAX_VALUE_DEPTH:
            raise Refused(f"values nested deeper than {MAX_VALUE_DEPTH} levels")
        if x is None or isinstance(x, (bool, float, str)):
            continue
        if isinstance(x, int):
            _need_bits("an integer", x.bit_length())
        elif is_table(x):
            continue
        elif isinstance(x, dict):
            stack.extend((y, depth + 1) for y in dict.keys(x))
            stack.extend((y, depth + 1) for y in dict.values(x))
        elif isinstance(x, (list, tuple, set, frozenset)):
            stack.extend((y, depth + 1) for y in x)
        else:
            raise Refused(f"a value of type {type(x).__name__}")
    return v


# --------------------------------------------------------------------------- formatting
_SPEC = re.compile(r"(?:.?[<>=^])?[-+ ]?z?#?0?(?P<width>\d*)[,_]?(?:\.(?P<prec>\d+))?(?P<type>[bcdeEfFgGnosxX%])?",
                   re.S)
_PERCENT = re.compile(r"%(?:\((?P<key>[^)]*)\))?[-#0 +]*(?P<width>\*|\d+)?(?:\.(?P<prec>\*|\d*))?[hlL]?"
                      r"(?P<type>[diouxXeEfFgGcrsa%])")


def _digits(text: str | None, what: str, limit: int) -> int:
    if not text:
        return 0
    if len(text) > 7 or int(text) > limit:
        raise Refused(f"a format {what} of {text[:12]} (at most {limit})")
    return int(text)


def _field_bound(value: Any, width: int, prec: int | None, kind: str) -> int:
    """Upper bound of one formatted field: ``value`` with ``width``, precision and type ``kind``
    (``s`` str, ``r`` repr, a numeric type letter, or ``""``)."""
    if kind == "r" or kind == "a":
        base = text_bound(value, top=False)
    elif isinstance(value, str) or kind == "s":
        base = text_bound(value)
        if prec is not None:
            base = min(base, prec)
    elif isinstance(value, (int, float)) and not isinstance(value, bool) or (kind and kind in "bcdeEfFgGnoxX%iu"):
        bits = value.bit_length() if isinstance(value, int) else 0
        base = (max(bits, 330) + (prec or 0) + 8) * 4 // 3  # binary digits, or a float's 309 digits; grouping
    else:
        base = text_bound(value)
    return max(width, base)


def format_field(value: Any, spec: str, conversion: str = "") -> str:
    """``format(value, spec)`` after ``!r``/``!s``/``!a`` ``conversion``, its size checked first."""
    if conversion == "r":
        _need("a repr()", text_bound(value, top=False))
        value = repr(value)
    elif conversion == "a":
        _need("an ascii()", text_bound(value, top=False))
        value = ascii(value)
    elif conversion == "s":
        _need("a str()", text_bound(value))
        value = str(value)
    m = _SPEC.fullmatch(spec)
    if m is None:
        raise Refused(f"the format specification {spec[:40]!r}")
    width = _digits(m["width"], "width", MAX_STRING)
    prec = _digits(m["prec"], "precision", MAX_PRECISION) if m["prec"] is not None else None
    _need("a formatted value", _field_bound(value, width, prec, m["type"] or ""))
    return format(value, spec)


def percent_format(fmt: str, args: Any) -> str:
    """``fmt % args`` with the result's size bounded from ``fmt`` and ``args`` first."""
    positional = list(args) if isinstance(args, tuple) else [args]
    total, i = len(fmt), 0
    for m in _PERCENT.finditer(fmt):
        if m["type"] == "%":
            continue
        if m["width"] == "*" or m["prec"] == "*":
            raise Refused("a '*' width or precision in %-formatting")
        width = _digits(m["width"], "width", MAX_STRING)
        prec = _digits(m["prec"], "precision", MAX_PRECISION) if m["prec"] is not None else None
        if m["key"] is not None:
            value = args.get(m["key"]) if isinstance(args, dict) else None
        else:
            value = positional[i] if i < len(positional) else None
            i += 1
        total += _field_bound(value, width, prec, m["type"])
        _need("a %-formatted string", total)
    if "%" in _PERCENT.sub("", fmt):  # a conversion the estimate above did not see
        raise Refused("a %-format conversion robokit does not read (write %s, %d, %5.2f, %(name)s …)")
    return fmt % args


_FIELD = re.compile(r"\d*|[A-Za-z_]\w*")


def str_format(fmt: str, *args: Any, **kwargs: Any) -> str:
    """``fmt.format(*args, **kwargs)`` for fields that are positions or names (no attribute or
    index access, no nested fields), with every field's size bounded first."""
    total, auto, pieces = 0, 0, []
    for literal, field, spec, conversion in string.Formatter().parse(fmt):
        total += len(literal)
        pieces.append(literal)
        if field is None:
            continue
        if not _FIELD.fullmatch(field):
            raise Refused(f"the format field {{{field[:40]}}} (only positions and names)")
        if "{" in (spec or ""):
            raise Refused("a format field nested in a format specification")
        if field == "":
            key: Any = auto
            auto += 1
        else:
            key = int(field) if field.isdigit() else field
        value = (args[key] if key < len(args) else None) if isinstance(key, int) else kwargs.get(key)
        if isinstance(key, int) and key >= len(args):
            raise IndexError(f"Replacement index {key} out of range for positional args tuple")
        if isinstance(key, str) and key not in kwargs:
            raise KeyError(key)
        piece = format_field(value, spec or "", conversion or "")
        total += len(piece)
        _need("a formatted string", total)
        pieces.append(piece)
    return "".join(pieces)


# --------------------------------------------------------------------------- functions
class Fn:
    """An allowed function: ``fn`` called with plain data after ``estimate`` (an upper bound of
    the result's size from the same arguments, or None) is checked."""

    def __init__(self, name: str, fn: Callable[..., Any], estimate: Callable[..., int] | None = None,
                 takes_functions: bool = False) -> None:
        self.name, self.fn, self.estimate, self.takes_functions = name, fn, estimate, takes_functions

    def call(self, args: list[Any], kwargs: dict[str, Any]) -> Any:
        if self.estimate is not None:
            try:
                n = self.estimate(*args, **kwargs)
            except TypeError:  # arguments the function does not take: nothing to bound, nothing to run
                raise Refused(f"{self.name}() with arguments it does not take") from None
            _need(f"the result of {self.name}()", n)
        return check_value(self.fn(*args, **kwargs))


class _Namespace:
    """``math``, ``python`` or ``xacro``: usable only before a dot."""

    def __init__(self, name: str) -> None:
        self.name = name


def _as_function(f: Any, what: str) -> Callable[..., Any] | None:
    if f is None:
        return None
    if not isinstance(f, Fn):
        raise Refused(f"{what} must be an allowed function (a lambda is not)")
    return lambda *a: f.call(list(a), {})


def _items(v: Any) -> Iterator[Any]:
    """Iterate a value as Python does (strings by character, dicts by key)."""
    return iter(v)  # v is data (checked): Python's own TypeError for a number


def _len_of(v: Any) -> int:
    return len(v) if isinstance(v, (str, list, tuple, dict, set, frozenset)) else 1


def _seq_estimate(it: Any = (), /, *_: Any, **__: Any) -> int:
    """Size of a list made from ``it`` (a string becomes one item per character)."""
    return 2 * len(it) if isinstance(it, str) else size_of(it)


def _collect(what: str, values: Iterable[Any]) -> list[Any]:
    """A list of ``values``, each added only after the list's size with it is checked."""
    out: list[Any] = []
    total = 0
    for v in values:
        total += 1 + size_of(v, MAX_STRING - total)
        _need(what, total)
        out.append(v)
    return out


def _map(f: Any, /, *iterables: Any) -> list[Any]:
    g = _as_function(f, "map's first argument")
    if g is None or not iterables:
        raise Refused("map() takes a function and at least one iterable")
    return _collect("a map() result", (g(*xs) for xs in zip(*map(_items, iterables))))


def _filter(f: Any, iterable: Any, /) -> list[Any]:
    g = _as_function(f, "filter's first argument") or bool
    return [x for x in _items(iterable) if g(x)]


def _sorted(iterable: Any, /, *, key: Any = None, reverse: Any = False) -> list[Any]:
    return sorted(_items(iterable), key=_as_function(key, "sorted's key"), reverse=reverse)


def _min_max(fn: Callable[..., Any]) -> Callable[..., Any]:
    def run(*args: Any, key: Any = None, **kwargs: Any) -> Any:
        if key is not None:
            kwargs["key"] = _as_function(key, f"{fn.__name__}'s key")
        return fn(*args, **kwargs)
    return run


def _range(*args: Any) -> list[int]:
    return list(range(*args))


def _range_estimate(*args: Any) -> int:
    return 2 * len(range(*args))  # the items and the integers


def _zip_estimate(*its: Any, **_: Any) -> int:
    if not its:
        return 0
    n = min(_len_of(i) for i in its)
    return n * (1 + len(its)) + sum(_seq_estimate(i) for i in its)


def _dict_estimate(*args: Any, **kwargs: Any) -> int:
    return (_seq_estimate(args[0]) if args else 0) + size_of(kwargs)


def _bounded_round(number: Any, ndigits: Any = None) -> Any:
    if ndigits is None:
        return round(number)
    if not isinstance(ndigits, int) or abs(ndigits) > MAX_PRECISION:
        raise Refused(f"round() to more than {MAX_PRECISION} digits")
    return round(number, ndigits)


def _numeric_sum(items: Any, /, start: Any = 0) -> Any:
    values = list(_items(items))
    if not all(isinstance(v, (int, float)) for v in values + [start]):
        raise Refused("sum() of values that are not numbers")
    if any(isinstance(v, int) and v.bit_length() > 64 for v in values):
        _need_bits("a sum()", max(v.bit_length() for v in values if isinstance(v, int)) + len(values).bit_length())
    return sum(values, start)


def _bits(x: Any) -> int:
    return x.bit_length() if isinstance(x, int) else 0


def _lgamma_bits(x: float) -> float:
    return math.lgamma(x) / math.log(2)


def _factorial_bits(n: Any) -> float:
    return _lgamma_bits(float(n) + 1) if isinstance(n, int) and n > 1 else 1


def _comb_bits(n: Any, k: Any) -> float:
    if not (isinstance(n, int) and isinstance(k, int)) or not 0 <= k <= n:
        return 1
    return _lgamma_bits(float(n) + 1) - _lgamma_bits(float(k) + 1) - _lgamma_bits(float(n - k) + 1) + 2


def _perm_bits(n: Any, k: Any = None) -> float:
    if not isinstance(n, int) or n < 0:
        return 1
    k = n if k is None else k
    if not isinstance(k, int) or not 0 <= k <= n:
        return 1
    return _lgamma_bits(float(n) + 1) - _lgamma_bits(float(n - k) + 1) + 2


def _checked_bits(name: str, fn: Callable[..., Any], bits: Callable[..., float]) -> Callable[..., Any]:
    def run(*args: Any, **kwargs: Any) -> Any:
        _need_bits(f"math.{name}()", bits(*args, **kwargs))
        return fn(*args, **kwargs)
    return run


_MATH_CONSTS = {k: v for k, v in vars(math).items() if isinstance(v, float)}
_MATH_FUNCS: dict[str, Fn] = {k: Fn(f"math.{k}", v) for k, v in vars(math).items()
                              if not k.startswith("_") and callable(v)}
_MATH_FUNCS.update({
    "factorial": Fn("math.factorial", _checked_bits("factorial", math.factorial, _factorial_bits)),
    "comb": Fn("math.comb", _checked_bits("comb", math.comb, _comb_bits)),
    "perm": Fn("math.perm", _checked_bits("perm", math.perm, _perm_bits)),
    "prod": Fn("math.prod", _checked_bits("prod", math.prod,
                                          lambda it, start=1: sum(map(_bits, _items(it))) + _bits(start))),
    "lcm": Fn("math.lcm", _checked_bits("lcm", math.lcm, lambda *a: sum(map(_bits, a)))),
})


def _str(*args: Any, **kwargs: Any) -> str:
    return str(*args, **kwargs)


def _str_estimate(*args: Any, **kwargs: Any) -> int:
    return text_bound(args[0] if args else kwargs.get("object", ""))


def _repr(v: Any, /) -> str:
    return repr(v)


#: The builtins xacro offers that compute on data (the ``python`` namespace).
_PYTHON_FUNCS: dict[str, Fn] = {f.name: f for f in [
    Fn("abs", abs), Fn("all", lambda it, /: all(_items(it))), Fn("any", lambda it, /: any(_items(it))),
    Fn("bool", bool), Fn("divmod", divmod), Fn("float", float), Fn("int", int), Fn("len", len), Fn("ord", ord),
    Fn("round", _bounded_round), Fn("sum", _numeric_sum),
    Fn("min", _min_max(min), takes_functions=True), Fn("max", _min_max(max), takes_functions=True),
    Fn("str", _str, _str_estimate), Fn("repr", _repr, lambda v, /: text_bound(v, top=False)),
    Fn("list", lambda it=(), /: list(_items(it)), _seq_estimate),
    Fn("tuple", lambda it=(), /: tuple(_items(it)), _seq_estimate),
    Fn("set", lambda it=(), /: set(_items(it)), _seq_estimate),
    Fn("frozenset", lambda it=(), /: frozenset(_items(it)), _seq_estimate),
    Fn("reversed", lambda it, /: list(reversed(it if isinstance(it, (list, tuple, str)) else list(_items(it)))),
       _seq_estimate),
    Fn("sorted", _sorted, _seq_estimate, takes_functions=True),
    Fn("dict", dict, _dict_estimate),
    Fn("range", _range, _range_estimate),
    Fn("zip", lambda *its, strict=False: list(zip(*map(_items, its), strict=strict)), _zip_estimate),
    Fn("enumerate", lambda iterable, start=0: list(enumerate(_items(iterable), start)),
       lambda iterable, start=0: 3 * _len_of(iterable) + _seq_estimate(iterable)),
    Fn("map", _map, lambda f, /, *its: 0, takes_functions=True),
    Fn("filter", _filter, lambda f, it, /: _seq_estimate(it), takes_functions=True),
]}
#: Builtins xacro offers that robokit refuses, with the reason.
_REFUSED_FUNCS = {
    "type": "type objects are not data", "vars": "it reads the evaluator's internals",
    "isinstance": "type objects are not data", "issubclass": "type objects are not data",
    "hash": "its value changes from run to run", "complex": "complex numbers are not robot data",
    "slice": "slice objects are not data (write a[i:j])",
}


def _str_method(s: str, name: str) -> Fn:
    def case(*_: Any, **__: Any) -> int:
        return len(s) if s.isascii() else 3 * len(s)

    def split(sep: Any = None, maxsplit: Any = -1) -> int:
        parts = s.count(sep) + 1 if isinstance(sep, str) and sep else len(s) // 2 + 1
        return len(s) + parts

    def join(iterable: Any) -> int:
        if isinstance(iterable, str):
            return len(iterable) + len(s) * max(len(iterable) - 1, 0)
        n = _len_of(iterable)
        total = len(s) * max(n - 1, 0)
        for item in _items(iterable):
            total += len(item) if isinstance(item, str) else 0
            if total > MAX_STRING:
                break
        return total

    def replace(old: Any, new: Any, count: Any = -1) -> int:
        if not (isinstance(old, str) and isinstance(new, str)):
            return 0
        n = (len(s) + 1) if old == "" else s.count(old)
        if isinstance(count, int) and count >= 0:
            n = min(n, count)
        return len(s) + n * max(len(new) - len(old), 0)

    def pad(width: Any, *_: Any) -> int:
        return max(width, len(s)) if isinstance(width, int) else len(s)

    def tabs(tabsize: Any = 8) -> int:
        return len(s) + s.count("\t") * (tabsize if isinstance(tabsize, int) and tabsize > 0 else 0)

    estimates: dict[str, Callable[..., int]] = {
        "upper": case, "lower": case, "casefold": case, "swapcase": case, "title": case, "capitalize": case,
        "split": split, "rsplit": split, "splitlines": lambda *a, **k: 2 * len(s) + 1,
        "partition": lambda *a: len(s) + 3, "rpartition": lambda *a: len(s) + 3, "join": join, "replace": replace,
        "center": pad, "ljust": pad, "rjust": pad, "zfill": pad, "expandtabs": tabs,
    }
    fn: Callable[..., Any] = getattr(s, name)
    if name == "format":
        return Fn("str.format", functools.partial(str_format, s))
    return Fn(f"str.{name}", fn, estimates.get(name))


_STR_METHODS = {"upper", "lower", "casefold", "swapcase", "title", "capitalize", "strip", "lstrip", "rstrip", "split",
                "rsplit", "splitlines", "partition", "rpartition", "join", "replace", "format", "startswith",
                "endswith", "find", "rfind", "index", "rindex", "count", "center", "ljust", "rjust", "zfill",
                "expandtabs", "removeprefix", "removesuffix", "isdigit", "isalpha", "isalnum", "isspace", "islower",
                "isupper", "isnumeric", "isdecimal", "isidentifier", "istitle", "isascii", "isprintable"}
_LIST_METHODS = {"index", "count"}
_DICT_METHODS = {"get", "keys", "values", "items"}
_NUMBER_METHODS = {"is_integer", "bit_length"}
_MUTATORS = {"append", "extend", "insert", "pop", "remove", "clear", "sort", "reverse", "update", "setdefault",
             "popitem", "add", "discard", "difference_update", "intersection_update", "symmetric_difference_update"}


def _tokenize(s: Any, sep: Any = ",; ", skip_empty: Any = True) -> list[str]:
    """xacro.tokenize: ``s`` split at any character of ``sep`` (a set of characters; the xacro
    program builds a regular expression ``[sep]`` from it, so ``sep`` may not use regex syntax)."""
    if re.search(r"[\[\]\\^]", sep) or "-" in sep[1:-1] or not sep:
        raise Refused(f"xacro.tokenize with the separator set {sep[:20]!r} (a plain set of characters is accepted)")
    parts = re.split("[" + re.escape(sep) + "]", s)
    return [p for p in parts if p] if skip_empty else parts


# --------------------------------------------------------------------------- binary operators
_BINOPS: dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
    ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow, ast.LShift: operator.lshift,
    ast.RShift: operator.rshift, ast.BitAnd: operator.and_, ast.BitOr: operator.or_, ast.BitXor: operator.xor,
}
_CMPOPS: dict[type, Callable[[Any, Any], Any]] = {
    ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt,
    ast.GtE: operator.ge, ast.In: lambda a, b: a in b, ast.NotIn: lambda a, b: a not in b,
    ast.Is: operator.is_, ast.IsNot: operator.is_not,
}
_SEQ = (str, list, tuple)


def _is_int(v: Any) -> bool:
    return isinstance(v, int)  # bool included: True * 'a' is 'a'


def check_binop(op: ast.operator, a: Any, b: Any) -> None:
    """Refuse ``a op b`` if its result could exceed the bounds (estimated from ``a`` and ``b``)."""
    if isinstance(op, ast.Add) and isinstance(a, (str, list, tuple)) and isinstance(b, (str, list, tuple)):
        _need("a concatenation", size_of(a) + size_of(b))
    elif isinstance(op, ast.Mult):
        for seq, k in ((a, b), (b, a)):
            if isinstance(seq, _SEQ) and _is_int(k):
                _need("a repetition", max(size_of(seq, MAX_STRING), 1) * max(k, 0))
        if _is_int(a) and _is_int(b):
            _need_bits("an integer product", _bits(a) + _bits(b))
    elif isinstance(op, ast.Pow) and _is_int(a) and _is_int(b) and b > 0 and abs(a) > 1:
        _need_bits("an integer power", b * math.log2(abs(a)))
    elif isinstance(op, ast.LShift) and _is_int(a) and _is_int(b) and a != 0:
        _need_bits("a left shift", _bits(a) + max(b, 0))
    elif isinstance(op, (ast.BitOr, ast.BitXor)) and isinstance(a, (dict, set, frozenset)) \
            and isinstance(b, (dict, set, frozenset)):
        _need("a union", size_of(a) + size_of(b))


# --------------------------------------------------------------------------- the interpreter
class _Interpreter:
    def __init__(self, symbols: Mapping[str, Any], functions: Mapping[str, Fn],
                 namespaces: Mapping[str, Mapping[str, Fn]], globals_ids: set[int], constants: Mapping[str, Any]) -> None:
        self.symbols = symbols
        self.functions = functions
        self.namespaces = namespaces
        self.globals_ids = globals_ids  # ids of xacro's own global objects (functions, namespaces)
        self.constants = constants
        self.scopes: list[dict[str, Any]] = []  # comprehension variables, innermost last
        self.steps = 0
        self.work = 0

    def tick(self) -> None:
        self.steps += 1
        if self.steps > MAX_STEPS:
            raise Refused(f"more than {MAX_STEPS} evaluation steps")

    def run(self, node: ast.AST) -> Any:
        self.steps += 1
        if self.steps > MAX_STEPS:
            raise Refused(f"more than {MAX_STEPS} evaluation steps")
        method = _DISPATCH.get(type(node))
        if method is None:
            raise Refused(_NOT_ALLOWED.get(type(node).__name__, f"{type(node).__name__} is not allowed"))
        v = method(self, node)
        if isinstance(v, (str, list, tuple, dict, set, frozenset)):
            self.work += len(v)  # every value built is also checked: bound the total
            if self.work > MAX_WORK:
                raise Refused(f"more than {MAX_WORK} characters and items built in one expression")
        return v

    def value(self, node: ast.AST) -> Any:
        v = self.run(node)
        if isinstance(v, (Fn, _Namespace)):
            raise Refused(f"{v.name} is a function, not a value")
        return v

    def argument(self, node: ast.AST, fn: Fn) -> Any:
        """An argument of ``fn``: data, or an allowed function if ``fn`` takes functions."""
        v = self.run(node)
        if isinstance(v, _Namespace) or (isinstance(v, Fn) and not fn.takes_functions):
            raise Refused(f"{v.name} is a function, not a value")
        return v

    def _Expression(self, node: ast.Expression) -> Any:
        return check_value(self.value(node.body))

    def _Constant(self, node: ast.Constant) -> Any:
        if isinstance(node.value, (bytes, complex)) or node.value is Ellipsis:
            raise Refused(f"a {type(node.value).__name__} literal")
        return check_value(node.value)

    def _Name(self, node: ast.Name) -> Any:
        name = node.id
        if name.startswith("__"):
            raise Refused(f"the name {name!r}")
        for scope in reversed(self.scopes):
            if name in scope:
                return scope[name]
        try:
            v = self.symbols[name]
        except KeyError:
            v = _MISSING
        if v is not _MISSING and id(v) not in self.globals_ids and not callable(v):
            return check_value(v)  # a property, parameter or argument: data
        if name in self.namespaces:
            return _Namespace(name)
        if name in self.functions:
            return self.functions[name]
        if name in self.constants:
            return self.constants[name]
        if name in _REFUSED_FUNCS:
            raise Refused(f"{name}() ({_REFUSED_FUNCS[name]})")
        if v is not _MISSING:
            raise Refused(f"the name {name!r} (not a property, parameter or allowed function)")
        raise NameError(f"name '{name}' is not defined")

    def _Attribute(self, node: ast.Attribute) -> Any:
        attr = node.attr
        if attr.startswith("_"):
            raise Refused(f"the attribute {attr!r}")
        base = self.run(node.value)
        if isinstance(base, _Namespace):
            table = self.namespaces[base.name]
            if attr in table:
                return table[attr]
            if base.name == "math" and attr in _MATH_CONSTS:
                return _MATH_CONSTS[attr]
            if base.name == "python" and attr in _REFUSED_FUNCS:
                raise Refused(f"python.{attr}() ({_REFUSED_FUNCS[attr]})")
            raise Refused(f"{base.name}.{attr}")
        if isinstance(base, Fn):
            raise Refused(f"an attribute of the function {base.name}")
        if attr in _MUTATORS and isinstance(base, (list, dict, set)):
            raise Refused(f"{type(base).__name__}.{attr}() (it changes a value in place)")
        if isinstance(base, str) and attr in _STR_METHODS:
            return _str_method(base, attr)
        if isinstance(base, (list, tuple)) and attr in _LIST_METHODS:
            return Fn(f"list.{attr}", getattr(base, attr))
        if isinstance(base, dict) and attr in _DICT_METHODS:
            method = getattr(dict, attr)
            return Fn(f"dict.{attr}", lambda *a: _listify(method(base, *a)))
        if isinstance(base, (int, float)) and not isinstance(base, bool) and attr in _NUMBER_METHODS \
                and hasattr(base, attr):
            return Fn(f"{type(base).__name__}.{attr}", getattr(base, attr))
        if is_table(base) and isinstance(base, dict):  # an include's namespace, a YAML mapping: its keys
            try:
                return check_value(base[attr])
            except (KeyError, AttributeError):
                raise NameError(f"name '{attr}' is not defined") from None
        raise Refused(f"the attribute {attr!r} of a {type(base).__name__}")

    def _Call(self, node: ast.Call) -> Any:
        try:
            fn = self.run(node.func)
        except NameError:
            if not isinstance(node.func, ast.Name):
                raise
            raise Refused(f"a call to {node.func.id!r} (not an allowed function)") from None
        if not isinstance(fn, Fn):
            raise Refused("calling a value that is not an allowed function")
        args: list[Any] = []
        for a in node.args:
            if isinstance(a, ast.Starred):
                v = self.value(a.value)
                _need("the arguments of a call", len(args) + _len_of(v))
                args.extend(_items(v))
            else:
                args.append(self.argument(a, fn))
        kwargs: dict[str, Any] = {}
        for kw in node.keywords:
            if kw.arg is None:
                kwargs.update(**self.value(kw.value))  # Python's own TypeError for keys that are not names
            else:
                kwargs[kw.arg] = self.argument(kw.value, fn)
        return fn.call(args, kwargs)

    def _BinOp(self, node: ast.BinOp) -> Any:
        op = _BINOPS.get(type(node.op))
        if op is None:
            raise Refused(f"the operator {type(node.op).__name__}")
        a, b = self.value(node.left), self.value(node.right)
        if isinstance(node.op, ast.Mod) and isinstance(a, str):
            return check_value(percent_format(a, b))
        check_binop(node.op, a, b)
        return check_value(op(a, b))

    def _UnaryOp(self, node: ast.UnaryOp) -> Any:
        v = self.value(node.operand)
        if isinstance(node.op, ast.USub):
            return -v
        if isinstance(node.op, ast.UAdd):
            return +v
        if isinstance(node.op, ast.Not):
            return not v
        if isinstance(node.op, ast.Invert):
            return ~v
        raise Refused(f"the operator {type(node.op).__name__}")

    def _BoolOp(self, node: ast.BoolOp) -> Any:
        is_and = isinstance(node.op, ast.And)
        v: Any = None
        for sub in node.values:
            v = self.value(sub)
            if (not v) if is_and else bool(v):
                return v
        return v

    def _Compare(self, node: ast.Compare) -> Any:
        left = self.value(node.left)
        for op, right_node in zip(node.ops, node.comparators):
            right = self.value(right_node)
            if not _CMPOPS[type(op)](left, right):
                return False
            left = right
        return True

    def _IfExp(self, node: ast.IfExp) -> Any:
        return self.value(node.body) if self.value(node.test) else self.value(node.orelse)

    def _Subscript(self, node: ast.Subscript) -> Any:
        base = self.value(node.value)
        key = self.run(node.slice) if isinstance(node.slice, ast.Slice) else self.value(node.slice)
        if not isinstance(key, (int, str, slice, float, tuple)) and key is not None:
            raise Refused(f"a subscript of type {type(key).__name__}")
        return check_value(base[key])

    def _Slice(self, node: ast.Slice) -> slice:
        parts = [None if p is None else self.value(p) for p in (node.lower, node.upper, node.step)]
        return slice(*parts)

    def elements(self, nodes: list[ast.expr], what: str) -> list[Any]:
        """The items of a list/tuple/set display, ``*iterable`` unpacked, size checked as it grows."""
        out: list[Any] = []
        total = 0
        for e in nodes:
            if isinstance(e, ast.Starred):
                v = self.value(e.value)
                total += _seq_estimate(v)
                _need(what, total)
                out.extend(_items(v))
            else:
                v = self.value(e)
                total += 1 + size_of(v, MAX_STRING - total)
                _need(what, total)
                out.append(v)
        return out

    def _List(self, node: ast.List) -> list[Any]:
        return self.elements(node.elts, "a list")

    def _Tuple(self, node: ast.Tuple) -> tuple[Any, ...]:
        return tuple(self.elements(node.elts, "a tuple"))

    def _Set(self, node: ast.Set) -> set[Any]:
        return set(self.elements(node.elts, "a set"))

    def _Dict(self, node: ast.Dict) -> dict[Any, Any]:
        out: dict[Any, Any] = {}
        total = 0
        for k, v in zip(node.keys, node.values):
            if k is None:  # {**mapping}
                m = {**self.value(v)}  # Python's own TypeError for a value that is not a mapping
                total += size_of(m, MAX_STRING - total)
                _need("a dict", total)
                out.update(m)
            else:
                key, val = self.value(k), self.value(v)
                total += 1 + size_of(key, MAX_STRING - total) + size_of(val, MAX_STRING - total)
                _need("a dict", total)
                out[key] = val
        return out

    def _JoinedStr(self, node: ast.JoinedStr) -> str:
        pieces, total = [], 0
        for part in node.values:
            if isinstance(part, ast.Constant) and isinstance(part.value, str):
                piece = part.value
            elif isinstance(part, ast.FormattedValue):
                value = self.value(part.value)
                spec = self._JoinedStr(part.format_spec) if isinstance(part.format_spec, ast.JoinedStr) else ""
                conversion = {-1: "", 115: "s", 114: "r", 97: "a"}.get(part.conversion, "")
                piece = format_field(value, spec, conversion)
            else:
                raise Refused(f"{type(part).__name__} in an f-string")
            total += len(piece)
            _need("an f-string", total)
            pieces.append(piece)
        return "".join(pieces)

    # comprehensions -----------------------------------------------------------------------
    def bind(self, target: ast.AST, value: Any, scope: dict[str, Any]) -> None:
        if isinstance(target, ast.Name):
            if target.id.startswith("__"):
                raise Refused(f"the name {target.id!r}")
            scope[target.id] = value
        elif isinstance(target, (ast.Tuple, ast.List)):
            items = list(_items(value))
            if len(items) != len(target.elts):
                raise Refused(f"{len(items)} values unpacked into {len(target.elts)} names")
            for t, v in zip(target.elts, items):
                self.bind(t, v, scope)
        else:
            raise Refused(f"a loop variable of the form {type(target).__name__}")

    def iterate(self, generators: list[ast.comprehension], emit: Callable[[], None]) -> None:
        scope: dict[str, Any] = {}
        self.scopes.append(scope)
        try:
            self._loop(generators, 0, scope, emit)
        finally:
            self.scopes.pop()

    def _loop(self, generators: list[ast.comprehension], i: int, scope: dict[str, Any],
              emit: Callable[[], None]) -> None:
        if i == len(generators):
            emit()
            return
        g = generators[i]
        if g.is_async:
            raise Refused("async comprehensions")
        for item in list(_items(self.value(g.iter))):
            self.tick()
            self.bind(g.target, item, scope)
            if all(self.value(c) for c in g.ifs):
                self._loop(generators, i + 1, scope, emit)

    def comprehension(self, node: ast.ListComp | ast.SetComp | ast.GeneratorExp, what: str) -> list[Any]:
        out: list[Any] = []
        total = [0]

        def emit() -> None:
            v = self.value(node.elt)
            total[0] += 1 + size_of(v, MAX_STRING - total[0])
            _need(what, total[0])
            out.append(v)

        self.iterate(node.generators, emit)
        return out

    def _ListComp(self, node: ast.ListComp) -> list[Any]:
        return self.comprehension(node, "a list comprehension")

    def _GeneratorExp(self, node: ast.GeneratorExp) -> list[Any]:
        return self.comprehension(node, "a generator expression")

    def _SetComp(self, node: ast.SetComp) -> set[Any]:
        return set(self.comprehension(node, "a set comprehension"))

    def _DictComp(self, node: ast.DictComp) -> dict[Any, Any]:
        out: dict[Any, Any] = {}
        total = [0]

        def emit() -> None:
            k, v = self.value(node.key), self.value(node.value)
            total[0] += 1 + size_of(k, MAX_STRING - total[0]) + size_of(v, MAX_STRING - total[0])
            _need("a dict comprehension", total[0])
            out[k] = v

        self.iterate(node.generators, emit)
        return out


#: Syntax-tree node type -> the interpreter's method for it (the node types it evaluates).
_DISPATCH: dict[type, Callable[[_Interpreter, Any], Any]] = {
    getattr(ast, name[1:]): method for name, method in vars(_Interpreter).items()
    if name.startswith("_") and not name.startswith("__") and isinstance(getattr(ast, name[1:], None), type)}
_NOT_ALLOWED = {
    "Lambda": "Lambda is not allowed: functions are never values (map, filter and sorted take the named functions)",
    "NamedExpr": "an assignment := inside an expression",
    "Await": "await", "Yield": "yield", "YieldFrom": "yield",
}
_MISSING = object()


def _listify(v: Any) -> Any:
    """dict.keys()/values()/items() as lists (of the mapping's raw values, as xacro gives them)."""
    return v if isinstance(v, (str, int, float, bool, type(None), list, tuple, dict)) else list(v)


@functools.lru_cache(maxsize=4096)
def _parse(text: str) -> ast.Expression:
    """The syntax tree of an expression (cached: a macro evaluates the same text many times;
    the interpreter never modifies a tree). Python's SyntaxWarnings ("invalid escape
    sequence", "invalid decimal literal") are not shown: the text is data, not code."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SyntaxWarning)
        return ast.parse(text, mode="eval")


def evaluate(expression: str, symbols: Mapping[str, Any], *, source: str = "<xacro>",
             functions: Mapping[str, Callable[..., Any]] | None = None,
             namespaces: Mapping[str, Mapping[str, Callable[..., Any]]] | None = None,
             globals_ids: set[int] | None = None, constants: Mapping[str, Any] | None = None) -> Any:
    """Evaluate a xacro expression with robokit's interpreter (see the module docstring).

    Parameters
    ----------
    expression : str
        The text inside ``${…}`` (or ``$(eval …)``).
    symbols : mapping
        Property, parameter and argument values by name.
    source : str
        The file named in a refusal.
    functions, namespaces : mapping, optional
        More callable names and ``ns.name`` tables (robokit's own hooks, e.g. ``xacro.load_yaml``),
        besides the ``math`` and builtin functions above.
    globals_ids : set of int, optional
        ``id`` of objects in ``symbols`` that are functions/namespaces, not data.
    constants : mapping, optional
        More names with fixed values (``true``/``false`` in ``$(eval …)``).

    Returns
    -------
    int, float, str, bool, None, list, tuple, set or dict
        The value (or a YAML / include table).

    Raises
    ------
    UnsafeXacro
        An expression outside what is accepted, or a result beyond the bounds, with the file,
        the expression and the reason.
    NameError, ArithmeticError, TypeError, ValueError, KeyError, IndexError
        Ordinary evaluation errors (an undefined name, a division by zero), which xacro reports
        with their own context.

    Examples
    --------
    >>> evaluate("2 * pi * r", {"r": 0.5})
    3.141592653589793
    >>> evaluate("'%s_link' % name.upper()", {"name": "base"})
    'BASE_link'
    >>> evaluate("dict(shoulder=0.0, elbow=-1.57)", {})
    {'shoulder': 0.0, 'elbow': -1.57}
    >>> evaluate("[x * x for x in l if x > 1]", {"l": [1, 2, 3]})
    [4, 9]
    >>> evaluate("('a' * 60000).join('b' * 30000)", {})
    Traceback (most recent call last):
    ...
    robokit.description.xacro_expr.UnsafeXacro: <xacro>: expression ${('a' * 60000).join('b' * 30000)} refused (the result of str.join() of more than 100000 characters and items (about 1799970000))
    >>> evaluate("(lambda: 1)()", {})
    Traceback (most recent call last):
    ...
    robokit.description.xacro_expr.UnsafeXacro: <xacro>: expression ${(lambda: 1)()} refused (Lambda is not allowed: functions are never values (map, filter and sorted take the named functions))
    """
    shown = " ".join(expression.split())
    shown = shown if len(shown) <= 120 else shown[:117] + "..."

    def refuse(why: str) -> UnsafeXacro:
        return UnsafeXacro(f"{source}: expression ${{{shown}}} refused ({why})")

    if len(expression) > MAX_EXPRESSION:
        raise refuse(f"{len(expression)} characters; at most {MAX_EXPRESSION}")
    try:
        tree = _parse(expression.strip())
    except SyntaxError as exc:
        raise SyntaxError(f"invalid expression: {exc.msg}") from None
    except (RecursionError, MemoryError, ValueError):
        raise refuse("nested too deeply") from None
    funcs: dict[str, Fn] = dict(_MATH_FUNCS)
    funcs.update(_PYTHON_FUNCS)
    for name, f in (functions or {}).items():
        funcs[name] = f if isinstance(f, Fn) else Fn(name, f)
    ns: dict[str, Mapping[str, Fn]] = {"math": _MATH_FUNCS, "python": _PYTHON_FUNCS}
    for name, table in (namespaces or {}).items():
        ns[name] = {k: (f if isinstance(f, Fn) else Fn(f"{name}.{k}", f)) for k, f in table.items()}
    consts: dict[str, Any] = dict(_MATH_CONSTS)
    consts.update({"True": True, "False": False, "None": None})
    consts.update(constants or {})
    interp = _Interpreter(symbols, funcs, ns, globals_ids or set(), consts)
    try:
        return interp.run(tree)
    except Refused as exc:
        raise refuse(str(exc)) from None
    except RecursionError:
        raise refuse("nested too deeply") from None
    except OverflowError:
        raise refuse("a number too large") from None
    except MemoryError:  # a safety net: every growing operation is bounded before it runs
        raise refuse("out of memory") from None

