r"""xacro without code execution: robokit's own evaluator for ``${…}`` and ``$(eval …)``, and
bounds on what a xacro file may make robokit read and do.

The ``xacro`` package evaluates every ``${expression}`` with Python's ``eval`` behind a thin
filter (a top-level ``__`` is refused, the same gadget inside a ``lambda`` is not), so a
robot file could run any code. While robokit expands a file (:func:`guarded`), xacro's
evaluation functions are replaced by :func:`evaluate`, which parses the expression with
:mod:`ast` and **interprets** it itself — nothing a file writes ever reaches ``eval``. What a
robot description needs is accepted:

* literals: numbers, strings (at most :data:`MAX_STRING` characters), ``True``/``False``/``None``;
  lists, tuples and dicts of values;
* arithmetic ``+ - * / // % **`` (integer powers bounded to :data:`MAX_INT_BITS` bits, repeated
  strings and lists to :data:`MAX_STRING` items), comparisons, ``and``/``or``/``not``,
  ``a if c else b``, subscripts and slices of values;
* names that are xacro properties, macro parameters or arguments (their values are data);
* the ``math`` functions and constants (``pi``, ``sin``, ``radians``, …, also as ``math.sin``),
  the builtins xacro documents that compute on data (``abs min max round len int float str
  bool list tuple dict sorted sum any all range zip enumerate reversed divmod ord set``, also
  as ``python.len``), a few string and dict methods (``upper lower strip split join replace
  startswith endswith find count get keys values items``);
* ``xacro.arg``, ``xacro.tokenize``, ``xacro.dotify``, ``xacro.abs_filename``, ``xacro.fatal``,
  ``xacro.message``/``warning``/``error`` (shown as robokit notes) and ``xacro.load_yaml``
  (read with robokit's strict, bounded YAML reader, confined like an include);
* attribute access to keys of a loaded YAML mapping or of an include's namespace.

Everything else — attribute access to anything not listed (``__class__``,
``__subclasses__``, ``func_globals``…), lambdas, comprehensions, f-strings, starred
arguments, keyword arguments, calls to anything not listed, walrus — is refused with one line
naming the file and the expression.

Substitution arguments: ``$(find pkg)`` resolves through robokit's package search only;
``$(env NAME)`` and ``$(optenv NAME default)`` never read the environment: the value comes
from ``xacro_args``/``--xacro-arg NAME:=…`` if the user gives it; otherwise ``$(env …)`` is
refused and ``$(optenv …)`` takes its default with a note.

Reading: the top file and every ``<xacro:include>`` are read with robokit's bounded reader
(regular files only, :data:`robokit.description.urdf_check.MAX_URDF_BYTES`) and checked by
:func:`robokit._xml.check_xml` (no DTD, bounded depth and size) before xacro parses them; an
include or a YAML file must lie inside the allowed roots of
:mod:`robokit.description.meshes` (the file's folder, its package, the package folders given
and the packages found), at most :data:`MAX_INCLUDES` files are read, nested at most
:data:`MAX_INCLUDE_DEPTH` deep.

Work: at most :data:`MAX_MACRO_DEPTH` nested macro calls, :data:`MAX_ELEMENTS` elements
processed in total and :data:`MAX_SECONDS` seconds of expansion (a self-doubling macro fails
in a fraction of a second with one line).
"""
from __future__ import annotations

import ast
import contextlib
import functools
import math
import operator
import os
import time
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence

from robokit.description._notes import note
from robokit.errors import InputError

__all__ = ["MAX_ELEMENTS", "MAX_EXPRESSION", "MAX_INCLUDE_DEPTH", "MAX_INCLUDES", "MAX_INT_BITS", "MAX_MACRO_DEPTH", "MAX_SECONDS",
           "MAX_STRING", "UnsafeXacro", "evaluate", "guarded"]

#: Longest ``${…}`` expression accepted (characters).
MAX_EXPRESSION = 10_000
#: Longest string (or list) an expression may produce.
MAX_STRING = 100_000
#: Largest integer an expression may produce, in bits.
MAX_INT_BITS = 4096
#: Deepest nesting of macro calls.
MAX_MACRO_DEPTH = 100
#: Most elements xacro may process while expanding one file (its includes and macros included).
#: xacro spends about 0.1-0.3 ms per element (measured here, under load), so this bounds a
#: runaway macro to a few seconds; real descriptions process a few hundred to a few thousand.
MAX_ELEMENTS = 20_000
#: Most files (includes, YAML) one expansion may read.
MAX_INCLUDES = 500
#: Deepest nesting of ``<xacro:include>`` (a file including itself stops here).
MAX_INCLUDE_DEPTH = 20
#: Longest expansion, wall-clock seconds (a safety net: a real description takes < 1 s).
MAX_SECONDS = 30.0


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


class _Fn:
    """A whitelisted function, usable only as the callee of a call."""

    def __init__(self, name: str, fn: Callable[..., Any]) -> None:
        self.name, self.fn = name, fn


class _Namespace:
    """``math``, ``python`` or ``xacro``: usable only before a dot."""

    def __init__(self, name: str) -> None:
        self.name = name


def _bounded_range(*args: Any) -> list[int]:
    r = range(*args)
    if len(r) > MAX_STRING:
        raise _Refused(f"range of {len(r)} items (at most {MAX_STRING})")
    return list(r)


def _bounded_round(x: Any, ndigits: Any = None) -> Any:
    if ndigits is None:
        return round(x)
    if not isinstance(ndigits, int) or abs(ndigits) > 100:
        raise _Refused("round() with more than 100 digits")
    return round(x, ndigits)


def _numeric_sum(items: Any, start: Any = 0) -> Any:
    values = list(items)
    if not all(isinstance(v, (int, float)) for v in values + [start]):
        raise _Refused("sum() of values that are not numbers")
    return sum(values, start)


def _bounded_replace(s: str, old: str, new: str, count: int = -1) -> str:
    n = s.count(old) if count < 0 else min(count, s.count(old))
    if len(s) + n * (len(new) - len(old)) > MAX_STRING:
        raise _Refused(f"a replace() result of more than {MAX_STRING} characters")
    return s.replace(old, new, count)


_MATH_FUNCS = {k: v for k, v in vars(math).items() if not k.startswith("_") and callable(v)
               and k not in ("factorial", "comb", "perm", "prod")}
_MATH_CONSTS = {k: v for k, v in vars(math).items() if isinstance(v, float)}
_PYTHON_FUNCS: dict[str, Callable[..., Any]] = {
    "abs": abs, "min": min, "max": max, "round": _bounded_round, "len": len, "int": int, "float": float, "str": str,
    "bool": bool, "list": list, "tuple": tuple, "dict": dict, "sorted": sorted, "sum": _numeric_sum, "any": any, "all": all,
    "range": _bounded_range, "zip": lambda *a: list(zip(*a)), "enumerate": lambda a, s=0: list(enumerate(a, s)),
    "reversed": lambda a: list(reversed(a)), "divmod": divmod, "ord": ord, "set": set,
}
_STR_METHODS = {"upper", "lower", "strip", "lstrip", "rstrip", "split", "rsplit", "join", "replace", "startswith",
                "endswith", "find", "rfind", "count", "index", "capitalize", "title", "isdigit", "isalpha"}
_DICT_METHODS = {"get", "keys", "values", "items"}
_LIST_METHODS = {"index", "count"}

_BINOPS: dict[type, Callable[[Any, Any], Any]] = {
    ast.Add: operator.add, ast.Sub: operator.sub, ast.Mult: operator.mul, ast.Div: operator.truediv,
    ast.FloorDiv: operator.floordiv, ast.Mod: operator.mod, ast.Pow: operator.pow,
}
_CMPOPS: dict[type, Callable[[Any, Any], Any]] = {
    ast.Eq: operator.eq, ast.NotEq: operator.ne, ast.Lt: operator.lt, ast.LtE: operator.le, ast.Gt: operator.gt,
    ast.GtE: operator.ge, ast.In: lambda a, b: a in b, ast.NotIn: lambda a, b: a not in b,
    ast.Is: operator.is_, ast.IsNot: operator.is_not,
}


class _Refused(Exception):
    pass


def _size(v: Any, depth: int = 0) -> int:
    """The size of a value in items: characters of a string, the sizes of a container's items
    (at least 1 each) — stops counting past :data:`MAX_STRING`."""
    if isinstance(v, str):
        return len(v)
    if isinstance(v, (list, tuple, set, frozenset, dict)):
        if depth > 20:
            raise _Refused("values nested too deeply")
        total = len(v)
        for x in (v.items() if isinstance(v, dict) else v):
            total += _size(x, depth + 1)
            if total > MAX_STRING:
                break
        return total
    return 1


def _check_value(v: Any, depth: int = 0) -> Any:
    """``v`` if it is plain data (numbers, strings, lists/tuples/dicts of them) of bounded size
    (at most :data:`MAX_STRING` characters and items in all), else refuse."""
    if v is None or isinstance(v, (bool, float)):
        return v
    if isinstance(v, int):
        if v.bit_length() > MAX_INT_BITS:
            raise _Refused(f"an integer of {v.bit_length()} bits (at most {MAX_INT_BITS})")
        return v
    if isinstance(v, (str, list, tuple, set, frozenset, dict)):
        if _size(v) > MAX_STRING:
            raise _Refused(f"a value of more than {MAX_STRING} characters and items")
        if not isinstance(v, str):
            for x in (v.items() if isinstance(v, dict) else v):
                _check_item(x, depth + 1)
        return v
    if _is_namespace_table(v):
        return v
    raise _Refused(f"a value of type {type(v).__name__}")


def _check_item(x: Any, depth: int) -> None:
    if isinstance(x, tuple) and depth > 0:
        for y in x:
            _check_item(y, depth + 1)
        return
    if depth > 20:
        raise _Refused("values nested too deeply")
    if x is None or isinstance(x, (bool, int, float, str)):
        if isinstance(x, int) and not isinstance(x, bool) and x.bit_length() > MAX_INT_BITS:
            raise _Refused(f"an integer of {x.bit_length()} bits (at most {MAX_INT_BITS})")
        return
    if isinstance(x, (list, tuple, set, frozenset, dict)):
        for y in (x.items() if isinstance(x, dict) else x):
            _check_item(y, depth + 1)
        return
    if not _is_namespace_table(x):
        raise _Refused(f"a value of type {type(x).__name__}")


def _is_namespace_table(v: Any) -> bool:
    """A xacro include namespace (``<xacro:include ns=...>``) or a dotified YAML dict."""
    cls = type(v).__name__
    return cls in ("NameSpace", "Table", "YamlDictWrapper", "YamlListWrapper")


class _Interpreter:
    def __init__(self, symbols: Mapping[str, Any], functions: Mapping[str, Callable[..., Any]],
                 namespaces: Mapping[str, Mapping[str, Callable[..., Any]]], globals_ids: set[int]) -> None:
        self.symbols = symbols
        self.functions = functions
        self.namespaces = namespaces
        self.globals_ids = globals_ids  # ids of xacro's own global objects (functions, namespaces)
        self.steps = 0
        self.work = 0

    def run(self, node: ast.AST) -> Any:
        self.steps += 1
        if self.steps > 100_000:
            raise _Refused("too much work in one expression")
        method = getattr(self, "_" + type(node).__name__, None)
        if method is None:
            raise _Refused(f"{type(node).__name__} is not allowed")
        v = method(node)
        if isinstance(v, (str, list, tuple, dict, set, frozenset)):
            self.work += len(v)  # every value built is also checked: bound the total
            if self.work > 100 * MAX_STRING:
                raise _Refused("too much work in one expression")
        return v

    def _Expression(self, node: ast.Expression) -> Any:
        return _check_value(self.value(node.body))

    def value(self, node: ast.AST) -> Any:
        v = self.run(node)
        if isinstance(v, (_Fn, _Namespace)):
            raise _Refused(f"{v.name} is a function, not a value")
        return v

    def _Constant(self, node: ast.Constant) -> Any:
        if isinstance(node.value, (bytes, complex)) or node.value is Ellipsis:
            raise _Refused(f"a {type(node.value).__name__} literal")
        return _check_value(node.value)

    def _Name(self, node: ast.Name) -> Any:
        name = node.id
        if name.startswith("__"):
            raise _Refused(f"the name {name!r}")
        try:
            v = self.symbols[name]
        except KeyError:
            v = _MISSING
        if v is not _MISSING and id(v) not in self.globals_ids and not callable(v):
            return _check_value(v)  # a property, parameter or argument: data
        if name in self.namespaces:
            return _Namespace(name)
        if name in self.functions:
            return _Fn(name, self.functions[name])
        if name in _MATH_CONSTS:
            return _MATH_CONSTS[name]
        if name in ("True", "False", "None"):
            return {"True": True, "False": False, "None": None}[name]
        if v is not _MISSING:
            raise _Refused(f"the name {name!r} (not a property, parameter or allowed function)")
        raise NameError(f"name '{name}' is not defined")

    def _Attribute(self, node: ast.Attribute) -> Any:
        attr = node.attr
        if attr.startswith("_"):
            raise _Refused(f"the attribute {attr!r}")
        base = self.run(node.value)
        if isinstance(base, _Namespace):
            table = self.namespaces[base.name]
            if attr in table:
                return _Fn(f"{base.name}.{attr}", table[attr])
            if base.name == "math" and attr in _MATH_CONSTS:
                return _MATH_CONSTS[attr]
            raise _Refused(f"{base.name}.{attr}")
        if isinstance(base, _Fn):
            raise _Refused(f"an attribute of the function {base.name}")
        if isinstance(base, str) and attr == "replace":
            return _Fn("str.replace", lambda *a: _bounded_replace(base, *a))
        if isinstance(base, str) and attr in _STR_METHODS:
            return _Fn(f"str.{attr}", getattr(base, attr))
        if isinstance(base, (list, tuple)) and attr in _LIST_METHODS:
            return _Fn(f"list.{attr}", getattr(base, attr))
        if isinstance(base, dict) and attr in _DICT_METHODS and not _is_namespace_table(base):
            return _Fn(f"dict.{attr}", lambda *a, _m=getattr(base, attr): _listify(_m(*a)))
        if _is_namespace_table(base):  # an include's namespace, a YAML mapping: its keys
            try:
                return _check_value(base[attr])
            except (KeyError, AttributeError):
                raise NameError(f"name '{attr}' is not defined") from None
        raise _Refused(f"the attribute {attr!r} of a {type(base).__name__}")

    def _Call(self, node: ast.Call) -> Any:
        if isinstance(node.func, ast.Name) and node.func.id not in self.functions:
            raise _Refused(f"a call to {node.func.id!r} (not an allowed function)")
        fn = self.run(node.func)
        if not isinstance(fn, _Fn):
            raise _Refused("calling a value that is not an allowed function")
        if node.keywords:
            raise _Refused(f"keyword arguments to {fn.name}")
        args = []
        for a in node.args:
            if isinstance(a, ast.Starred):
                raise _Refused("starred arguments")
            args.append(self.value(a))
        return _check_value(fn.fn(*args))

    def _BinOp(self, node: ast.BinOp) -> Any:
        op = _BINOPS.get(type(node.op))
        if op is None:
            raise _Refused(f"the operator {type(node.op).__name__}")
        a, b = self.value(node.left), self.value(node.right)
        if isinstance(node.op, ast.Pow) and isinstance(a, int) and isinstance(b, int) and not isinstance(a, bool):
            if b > 0 and max(a.bit_length(), 1) * b > MAX_INT_BITS and abs(a) > 1:
                raise _Refused(f"an integer power of about {a.bit_length() * b} bits (at most {MAX_INT_BITS})")
        if isinstance(node.op, ast.Mult):
            for seq, k in ((a, b), (b, a)):
                if isinstance(seq, (str, list, tuple)) and isinstance(k, int) and max(_size(seq), 1) * k > MAX_STRING:
                    raise _Refused(f"a repetition of more than {MAX_STRING} characters and items")
        if isinstance(node.op, ast.Mod) and isinstance(a, str):
            raise _Refused("%-formatting of strings")
        return _check_value(op(a, b))

    def _UnaryOp(self, node: ast.UnaryOp) -> Any:
        v = self.value(node.operand)
        if isinstance(node.op, ast.USub):
            return -v
        if isinstance(node.op, ast.UAdd):
            return +v
        if isinstance(node.op, ast.Not):
            return not v
        raise _Refused(f"the operator {type(node.op).__name__}")

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
        if not isinstance(key, (int, str, slice, float, tuple)):
            raise _Refused(f"a subscript of type {type(key).__name__}")
        return _check_value(base[key])

    def _Slice(self, node: ast.Slice) -> slice:
        parts = [None if p is None else self.value(p) for p in (node.lower, node.upper, node.step)]
        return slice(*parts)

    def _List(self, node: ast.List) -> list[Any]:
        return [self.value(e) for e in node.elts]

    def _Tuple(self, node: ast.Tuple) -> tuple[Any, ...]:
        return tuple(self.value(e) for e in node.elts)

    def _Dict(self, node: ast.Dict) -> dict[Any, Any]:
        if any(k is None for k in node.keys):
            raise _Refused("dict unpacking")
        return {self.value(k): self.value(v) for k, v in zip(node.keys, node.values) if k is not None}


_MISSING = object()


def _listify(v: Any) -> Any:
    return list(v) if not isinstance(v, (str, int, float, bool, type(None), list, tuple, dict)) else v


@functools.lru_cache(maxsize=4096)
def _parse(text: str) -> ast.Expression:
    """The syntax tree of an expression (cached: a macro evaluates the same text many times;
    the interpreter never modifies a tree). Python's SyntaxWarnings ("invalid escape
    sequence", "invalid decimal literal") are not shown: the text is data, not code."""
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", SyntaxWarning)
        return ast.parse(text, mode="eval")


def evaluate(expression: str, symbols: Mapping[str, Any], *, source: str = "<xacro>",
             functions: Mapping[str, Callable[..., Any]] | None = None,
             namespaces: Mapping[str, Mapping[str, Callable[..., Any]]] | None = None,
             globals_ids: set[int] | None = None) -> Any:
    """Evaluate a xacro expression with robokit's whitelist interpreter (see the module docstring).

    Parameters
    ----------
    expression : str
        The text inside ``${…}`` (or ``$(eval …)``).
    symbols : mapping
        Property, parameter and argument values by name.
    source : str
        The file named in a refusal.
    functions, namespaces : mapping, optional
        Callable names and ``ns.name`` tables; default: the ``math`` and builtin functions above.
    globals_ids : set of int, optional
        ``id`` of objects in ``symbols`` that are functions/namespaces, not data.

    Returns
    -------
    int, float, str, bool, None, list, tuple or dict
        The value.

    Raises
    ------
    UnsafeXacro
        An expression outside the whitelist, with the file and the expression.
    NameError, ArithmeticError, TypeError, KeyError, IndexError
        Ordinary evaluation errors (an undefined name, a division by zero), which xacro reports
        with their own context.

    Examples
    --------
    >>> evaluate("2 * pi * r", {"r": 0.5})
    3.141592653589793
    >>> evaluate("(lambda: 1)()", {})
    Traceback (most recent call last):
    ...
    robokit.description.xacro_safety.UnsafeXacro: <xacro>: expression ${(lambda: 1)()} refused (Lambda is not allowed)
    """
    shown = expression.strip()
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
    funcs = dict(_MATH_FUNCS)
    funcs.update(_PYTHON_FUNCS)
    funcs.update(functions or {})
    ns: dict[str, Mapping[str, Callable[..., Any]]] = {"math": _MATH_FUNCS, "python": _PYTHON_FUNCS}
    ns.update(namespaces or {})
    interp = _Interpreter(symbols, funcs, ns, globals_ids or set())
    try:
        return interp.run(tree)
    except _Refused as exc:
        raise refuse(str(exc)) from None
    except RecursionError:
        raise refuse("nested too deeply") from None
    except OverflowError:
        raise refuse("a number too large") from None


# --------------------------------------------------------------------------- hooks into xacro
@contextlib.contextmanager
def guarded(top: Path, roots: Callable[[], Sequence[Path]], user_args: Mapping[str, str], seen_args: set[str],
            max_bytes: int) -> Iterator[None]:
    """While active, the ``xacro`` package evaluates and reads only through robokit (see the
    module docstring). Call with xacro's module lock held.

    Parameters
    ----------
    top : Path
        The top-level xacro file (resolved).
    roots : callable
        Returns the folders includes and YAML files may be read from (called at each read, so
        packages found on the way count).
    user_args : mapping
        The values the user passed (``xacro_args``); ``$(env X)``/``$(optenv X)`` read ``X`` here.
    seen_args : set
        Names of user arguments consulted (filled in; unknown-argument check).
    max_bytes : int
        Largest file read.

    Yields
    ------
    None
        The body of the ``with`` block runs with xacro's evaluation and file reading replaced
        by robokit's; xacro's own functions are put back when the block exits (even on error).

    Examples
    --------
    >>> with guarded(top, lambda: [top.parent], {}, set(), 1 << 20):   # doctest: +SKIP
    ...     xacro.process_file(str(top))
    """
    import xml.dom.minidom

    from robokit._io import decode_utf8, read_input_bytes
    from robokit._optional import require

    xacro = require("xacro", "reading a .xacro file")
    sargs = require("xacro.substitution_args", "reading a .xacro file")
    from robokit._xml import check_xml
    from robokit.description.meshes import confine, is_inside

    g = xacro._global_symbols
    globals_ids = {id(v) for v in g.values() if callable(v) or _is_namespace_table(v)}
    for nsname in ("math", "python", "xacro"):
        if nsname in g:
            globals_ids.update(id(v) for v in g[nsname].values())
    state = {"elements": 0, "files": 0, "start": time.monotonic()}

    def current(back: int = 1) -> str:
        stack = getattr(xacro, "filestack", None) or []
        return str(stack[-back]) if len(stack) >= back and stack[-back] else str(top)

    def budget() -> None:
        if time.monotonic() - state["start"] > MAX_SECONDS:
            raise UnsafeXacro(f"{current()}: expansion took longer than {MAX_SECONDS:g} s; stopped")

    def read_file(filename: str, what: str) -> str:
        if len(getattr(xacro, "filestack", None) or []) > MAX_INCLUDE_DEPTH:
            raise UnsafeXacro(f"{current(2)}: includes nested deeper than {MAX_INCLUDE_DEPTH} levels (an include "
                              "loop?); stopped")
        state["files"] += 1
        if state["files"] > MAX_INCLUDES:
            raise UnsafeXacro(f"{current()}: more than {MAX_INCLUDES} files included; stopped")
        p = Path(os.path.join(getattr(xacro, "root_dir", "."), filename))
        if p.resolve() != top:  # the includer is below the included file on xacro's file stack
            confine(p, roots(), current(2), f"{what} {filename!r}")
        return decode_utf8(read_input_bytes(p, max_bytes, "a xacro file"), p)

    def parse(inp: Any, filename: str | None = None) -> Any:
        if inp is None and filename is not None:
            p = Path(os.path.join(getattr(xacro, "root_dir", "."), filename))
            if not os.path.lexists(p) and (p.resolve() == top or is_inside(p, roots())):
                return saved["parse"](inp, filename)  # xacro's own "file not found", located by robokit
            text = read_file(filename, "<xacro:include filename=...>")
            check_xml(text, filename)
            return xml.dom.minidom.parseString(text)
        if isinstance(inp, str):
            check_xml(inp, current())
        return saved["parse"](inp, filename)

    def eval_all(node: Any, macros: Any, symbols: Any) -> Any:
        state["elements"] += 1
        if state["elements"] > MAX_ELEMENTS:
            raise UnsafeXacro(f"{current()}: the expansion produced more than {MAX_ELEMENTS} elements; stopped "
                              "(a macro that calls itself?)")
        if len(getattr(xacro, "macrostack", None) or []) > MAX_MACRO_DEPTH:
            names = [m.body.getAttribute("name") for m in xacro.macrostack[-3:] if getattr(m, "body", None)]
            raise UnsafeXacro(f"{current()}: macros nested deeper than {MAX_MACRO_DEPTH} calls (… {' → '.join(names)}); "
                              "stopped")
        if state["elements"] % 1000 == 0:
            budget()
        return saved["eval_all"](node, macros, symbols)

    def load_yaml(filename: Any) -> Any:
        from robokit._yaml import MAX_BYTES, load_yaml_text

        if not isinstance(filename, str):
            raise _Refused("xacro.load_yaml needs a file name")
        spec = xacro.abs_filename_spec(filename)
        state["files"] += 1
        p = Path(spec)
        confine(p, roots(), current(), f"xacro.load_yaml({filename!r})")
        data = load_yaml_text(decode_utf8(read_input_bytes(p, MAX_BYTES, "a YAML file"), p), str(p),
                              scalar_tags=unit_tags(str(p)))
        return xacro.YamlListWrapper.wrap(data)

    def unit_tags(source: str) -> dict[str, Callable[[str], Any]]:
        """xacro's YAML unit tags (``!degrees 90``), their values evaluated by robokit's interpreter."""
        def make(factor: float) -> Callable[[str], Any]:
            return lambda text: float(evaluate(text, {}, source=source)) * factor
        units = {"!radians": 1.0, "!degrees": math.pi / 180.0, "!meters": 1.0, "!millimeters": 0.001,
                 "!foot": 0.3048, "!inches": 0.0254}
        return {tag: make(f) for tag, f in units.items()}

    def message(*args: Any) -> str:
        note(f"{current()}: xacro: {' '.join(map(str, args))}")
        return ""

    def fatal(*args: Any) -> Any:
        raise UnsafeXacro(f"{current()}: xacro.fatal: {' '.join(map(str, args))}")

    def arg(name: Any) -> Any:
        return xacro.substitution_args_context["arg"][name]

    xacro_ns: dict[str, Callable[..., Any]] = {
        "arg": arg, "tokenize": xacro.tokenize, "dotify": lambda d: xacro.YamlDictWrapper(d),
        "abs_filename": xacro.abs_filename_spec, "load_yaml": load_yaml, "fatal": fatal,
        "message": message, "warning": message, "error": message, "print_location": lambda *a: "",
    }
    top_level = {"load_yaml": load_yaml, "abs_filename": xacro.abs_filename_spec,
                 "dotify": xacro_ns["dotify"], "sorted": sorted, "range": _bounded_range}

    def safe_eval(expr: str, globals: Any, locals: Any = None) -> Any:
        budget()
        symbols = locals if locals is not None else globals
        return evaluate(expr, symbols, source=current(), functions=top_level, namespaces={"xacro": xacro_ns},
                        globals_ids=globals_ids)

    def user_value(kind: str, name: str) -> str | None:
        if name in user_args:
            seen_args.add(name)
            return str(user_args[name])
        return None

    def eval_env(name: str) -> str:
        v = user_value("env", name)
        if v is None:
            raise UnsafeXacro(f"{current()}: $(env {name}): robokit does not read the environment into a robot "
                              f"description; pass the value with --xacro-arg {name}:=VALUE (xacro_args=)")
        return v

    def eval_optenv(name: str, default: str = "") -> str:
        v = user_value("optenv", name)
        if v is None:
            note(f"{current()}: $(optenv {name}): the environment is not read; the default {default!r} is used "
                 f"(pass --xacro-arg {name}:=VALUE for another)")
            return default
        return v

    def sargs_eval(s: str, context: Any) -> str:
        budget()
        args = context.get("arg", {}) if isinstance(context, dict) else {}

        class _Args(dict):
            def __getitem__(self, key: str) -> Any:
                return sargs.convert_value(args[key], "auto")

        names = _Args()
        functions: dict[str, Callable[..., Any]] = {
            "arg": lambda name: sargs.convert_value(sargs._eval_arg(name, args=args), "auto"),
            "dirname": lambda: sargs._eval_dirname(context.get("filename")),
            "env": eval_env, "optenv": eval_optenv,
        }
        if "find" in sargs._eval_dict:
            functions["find"] = sargs._eval_dict["find"]
        return str(evaluate(s, names, source=current(), functions=functions))

    import glob as _glob
    import types

    def safe_glob(pattern: str) -> list[str]:
        parts = Path(pattern).parts
        fixed = []
        for part in parts:
            if any(ch in part for ch in "*?["):
                break
            fixed.append(part)
        base = Path(*fixed) if fixed else Path(".")
        confine(base if base.is_absolute() else Path(os.path.join(getattr(xacro, "root_dir", "."), base)),
                roots(), current(), f"<xacro:include filename={pattern!r}>")
        found = sorted(_glob.glob(pattern))
        if len(found) > MAX_INCLUDES:
            raise UnsafeXacro(f"{current()}: <xacro:include filename={pattern!r}> matches more than {MAX_INCLUDES} files")
        return found

    saved = {"parse": xacro.parse, "eval_all": xacro.eval_all, "safe_eval": xacro.safe_eval,
             "load_yaml": xacro.load_yaml, "_eval": sargs._eval, "_eval_env": sargs._eval_env,
             "_eval_optenv": sargs._eval_optenv}
    xacro.parse, xacro.eval_all, xacro.safe_eval, xacro.load_yaml = parse, eval_all, safe_eval, load_yaml
    saved_glob = xacro.glob
    xacro.glob = types.SimpleNamespace(glob=safe_glob)
    sargs._eval, sargs._eval_env, sargs._eval_optenv = sargs_eval, eval_env, eval_optenv
    saved_env = sargs._eval_dict.get("env"), sargs._eval_dict.get("optenv")
    sargs._eval_dict["env"], sargs._eval_dict["optenv"] = eval_env, eval_optenv
    try:
        yield
    finally:
        xacro.parse, xacro.eval_all, xacro.safe_eval, xacro.load_yaml = (
            saved["parse"], saved["eval_all"], saved["safe_eval"], saved["load_yaml"])
        xacro.glob = saved_glob
        sargs._eval, sargs._eval_env, sargs._eval_optenv = saved["_eval"], saved["_eval_env"], saved["_eval_optenv"]
        for key, val in zip(("env", "optenv"), saved_env):
            if val is not None:
                sargs._eval_dict[key] = val
