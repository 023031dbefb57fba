r"""xacro without code execution: the hooks that make the ``xacro`` package evaluate, read and
expand only through robokit, and the bounds on what a xacro file may make robokit read and do.

While robokit expands a file (:func:`guarded`), the ``xacro`` package's own machinery handles
the XML (macros and their parameter defaults ``p:=v``, ``p:=^``, ``p:=^|v``, ``*block`` and
``**block``, properties and their scopes, ``xacro:if``, ``xacro:element``, ``xacro:call``,
namespaced includes), but every expression is evaluated by robokit's interpreter
(:func:`robokit.description.xacro_expr.evaluate` — nothing a file writes reaches ``eval``),
and every file is read by robokit:

* ``${…}`` and ``$(eval …)``: robokit's interpreter, with xacro's helpers ``xacro.load_yaml``,
  ``xacro.arg``, ``xacro.tokenize``, ``xacro.dotify``, ``xacro.abs_filename``, ``xacro.fatal``
  and ``xacro.message``/``warning``/``error``/``print_location`` (shown as robokit notes);
* ``xacro.load_yaml``: read as PyYAML reads it (YAML 1.1 scalars, anchors and aliases, merge
  keys, the last of duplicate keys wins — with one note naming them) by
  :func:`robokit._yaml.load_pyyaml_text`, with bounded aliases, confined like an include;
* ``$(find pkg)`` resolves through robokit's package search only; ``$(env NAME)`` and
  ``$(optenv NAME default)`` never read the environment: the value comes from
  ``xacro_args``/``--xacro-arg NAME:=…`` if the user gives it; otherwise ``$(env …)`` is
  refused and ``$(optenv …)`` takes its default with a note; ``$(dirname)`` is the folder of
  the file being processed (the xacro program 2.1 cannot expand it).

Reading: the top file and every ``<xacro:include>`` are read with robokit's bounded reader
(regular files only, at most the caller's byte limit) and checked by
:func:`robokit._xml.check_xml` (no DTD, bounded depth and size) before xacro parses them; an
include or a YAML file must lie inside the allowed roots of
:mod:`robokit.description.meshes` (the file's folder, its package, the package folders given
and the packages found) or be a file the user named as the value of a xacro argument (a
robot's factory calibration passed as ``kinematics_params:=/home/me/ur5e_calibration.yaml``:
the user's choice, not the file's), at most :data:`MAX_INCLUDES` files are read, nested at most
:data:`MAX_INCLUDE_DEPTH` deep.

Work: at most :data:`MAX_MACRO_DEPTH` nested macro calls, :data:`MAX_ELEMENTS` elements
processed in total, :data:`MAX_SECONDS` seconds of expansion (a self-doubling macro fails
in a fraction of a second with one line), at most :data:`MAX_TEXT` characters substituted into
one attribute or text, and :data:`MAX_OUTPUT` characters of text, attributes, comments and
cloned macro bodies produced by the whole expansion (``$(arg a)$(arg a)`` doubling an
argument from one ``<xacro:arg>`` to the next stops there, before it is built).
"""
from __future__ import annotations

import contextlib
import math
import os
import time
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence

from robokit.description._notes import note
from robokit.errors import InputError
from robokit.description.xacro_expr import (MAX_EXPRESSION, MAX_INT_BITS, MAX_STRING, Refused, UnsafeXacro,
                                            _tokenize, evaluate, is_table, text_bound)

__all__ = ["MAX_ELEMENTS", "MAX_EXPRESSION", "MAX_INCLUDE_DEPTH", "MAX_INCLUDES", "MAX_INT_BITS", "MAX_MACRO_DEPTH",
           "MAX_OUTPUT", "MAX_SECONDS", "MAX_STRING", "MAX_TEXT", "UnsafeXacro", "evaluate", "guarded"]

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
#: Most characters the substitutions (``${…}``, ``$(…)``) may put into one attribute or text.
MAX_TEXT = MAX_STRING
#: Most characters of evaluated text and attributes, comments and cloned macro bodies one
#: expansion may produce (real descriptions produce 50 kB to 2 MB).
MAX_OUTPUT = 20_000_000


def _node_cost(node: Any) -> int:
    """Characters and nodes of a DOM subtree (what cloning it costs), without recursion."""
    total = 0
    stack = [node]
    while stack:
        n = stack.pop()
        total += 1
        data = getattr(n, "data", None)
        if isinstance(data, str):
            total += len(data)
        attrs = getattr(n, "attributes", None)
        if attrs:
            total += sum(len(k) + len(v) for k, v in attrs.items())
        stack.extend(getattr(n, "childNodes", ()) or ())
    return total


#: What a refused include or YAML file's message adds: how to allow it.
_HINT = ("; name its folder in package_dirs (--package-path), or pass the file itself as a xacro argument "
         "(xacro_args / --xacro-arg NAME:=PATH)")


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
    import glob as _glob
    import types
    import xml.dom
    import xml.dom.minidom

    from robokit._io import decode_utf8, read_input_bytes
    from robokit._optional import require
    from robokit._xml import check_xml
    from robokit.description.meshes import confine, is_inside

    xacro = require("xacro", "reading a .xacro file")
    sargs = require("xacro.substitution_args", "reading a .xacro file")

    g = xacro._global_symbols
    # xacro's own functions and namespaces: never data (its True/False/pi are, so only callables count)
    globals_ids = {id(v) for v in g.values() if callable(v) or is_table(v)}
    for nsname in ("math", "python", "xacro"):
        if nsname in g:
            globals_ids.update(id(v) for v in g[nsname].values() if callable(v) or is_table(v))
    state = {"elements": 0, "files": 0, "output": 0, "start": time.monotonic()}
    # the files the user named in an argument (``kinematics_params:=/home/me/arm_calibration.yaml``, as
    # a ROS launch file passes a robot's factory calibration): the user's choice, not the file's, so
    # read wherever they are; an argument that names no file names nothing
    named = {Path(v).resolve() for v in user_args.values() if isinstance(v, str) and v and os.path.isfile(v)}
    clone_cost: dict[int, tuple[Any, int]] = {}  # id(macro body) -> (body, cost)
    duplicates_noted: set[str] = set()

    def current(back: int = 1) -> str:
        stack = getattr(xacro, "filestack", None) or []
        return str(stack[-back]) if len(stack) >= back and stack[-back] else str(top)

    def budget() -> None:
        if time.monotonic() - state["start"] > MAX_SECONDS:
            raise UnsafeXacro(f"{current()}: expansion took longer than {MAX_SECONDS:g} s; stopped")

    def produce(n: int, what: str) -> None:
        state["output"] += n
        if state["output"] > MAX_OUTPUT:
            raise UnsafeXacro(f"{current()}: the expansion produced more than {MAX_OUTPUT} characters ({what}); stopped")

    def location() -> str:
        """Where xacro is: the macros being instantiated, innermost first, and the file stack."""
        parts = []
        for m in reversed(getattr(xacro, "macrostack", None) or []):
            body = getattr(m, "body", None)
            name = body.getAttribute("name") if body is not None else "?"
            where = m.history[-1][-1] if getattr(m, "history", None) and m.history[-1] else None
            parts.append(f"macro {name} ({where or '?'})")
        files = [str(f) if f else "string" for f in reversed(getattr(xacro, "filestack", None) or [])]
        return "; ".join(parts + ["file " + " included from ".join(files)]) if files else "; ".join(parts)

    def read_file(filename: str, what: str) -> str:
        if len(getattr(xacro, "filestack", None) or []) > MAX_INCLUDE_DEPTH:
            raise UnsafeXacro(f"{current(2)}: includes nested deeper than {MAX_INCLUDE_DEPTH} levels (an include "
                              "loop?); stopped")
        state["files"] += 1
        if state["files"] > MAX_INCLUDES:
            raise UnsafeXacro(f"{current()}: more than {MAX_INCLUDES} files included; stopped")
        p = Path(os.path.join(getattr(xacro, "root_dir", "."), filename))
        if p.resolve() != top and p.resolve() not in named:  # (the includer is below it on xacro's file stack)
            confine(p, roots(), current(2), f"{what} {filename!r}", hint=_HINT)
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
        # comments and CDATA are carried into the output without passing through eval_text
        produce(sum(len(c.data) for c in node.childNodes
                    if c.nodeType in (xml.dom.Node.COMMENT_NODE, xml.dom.Node.CDATA_SECTION_NODE)), "comments")
        return saved["eval_all"](node, macros, symbols)

    def handle_macro_call(node: Any, macros: Any, symbols: Any) -> Any:
        name = getattr(node, "tagName", "")
        if name.startswith("xacro:") and name != "xacro:call":
            try:
                m = xacro.resolve_macro(name[6:], macros, symbols)[2]
            except (KeyError, TypeError, AttributeError):
                m = None
            body = getattr(m, "body", None)
            if body is not None:
                if id(body) not in clone_cost:
                    clone_cost[id(body)] = (body, _node_cost(body))
                produce(clone_cost[id(body)][1], f"copies of the macro {name[6:]}")
        return saved["handle_macro_call"](node, macros, symbols)

    def eval_text(text: Any, symbols: Any) -> Any:
        """xacro's text evaluation (``${…}``, ``$(…)``, ``$$`` escapes, literal text), each
        substituted piece's size added up before the pieces are joined."""
        budget()
        lex = xacro.QuickLexer(xacro.LEXER)
        lex.lex(text)
        results: list[Any] = []
        substituted = literal = 0
        while lex.peek():
            kind, token = lex.next()
            if kind == lex.EXPR:
                expr = token[2:-1]
                try:
                    value = xacro.safe_eval(eval_text(expr, symbols), symbols)
                except Exception as exc:
                    raise xacro.XacroException(exc=exc, suffix=os.linesep + f"when evaluating expression '{expr}'"
                                               ) from None
                substituted += text_bound(value)
            elif kind == lex.EXTENSION:
                value = xacro.eval_extension(f"$({eval_text(token[2:-1], symbols)})")
                substituted += text_bound(value)
            elif kind == lex.DOLLAR_DOLLAR_BRACE:
                value = token[1:]
                literal += len(value)
            else:
                value = token
                literal += len(value)
            if substituted > MAX_TEXT:
                raise UnsafeXacro(f"{current()}: the substitutions in one attribute or text give more than {MAX_TEXT} "
                                  f"characters (in {' '.join(str(text).split())[:80]!r}); stopped")
            results.append(value)
        produce(substituted + literal, "text and attributes")
        if len(results) == 1:
            return results[0]
        return "".join(map(str, results))

    def load_yaml(filename: Any) -> Any:
        from robokit._yaml import MAX_BYTES, load_pyyaml_text

        if not isinstance(filename, str):
            raise Refused("xacro.load_yaml needs a file name")
        spec = xacro.abs_filename_spec(filename)
        state["files"] += 1
        if state["files"] > MAX_INCLUDES:
            raise UnsafeXacro(f"{current()}: more than {MAX_INCLUDES} files included; stopped")
        p = Path(spec)
        if p.resolve() not in named:  # a file the user named in an argument is read wherever it is
            confine(p, roots(), current(), f"xacro.load_yaml({filename!r})", hint=_HINT)
        try:
            raw = read_input_bytes(p, MAX_BYTES, "a YAML file")
        except InputError as exc:  # which call of which macro asked for it (a file name left empty, say)
            empty = " (an empty file name: an argument not given?)" if not filename.strip() else ""
            raise InputError(f"{current()}: xacro.load_yaml({filename!r}){empty}: {exc} (at {location()})") from None
        data, duplicates = load_pyyaml_text(decode_utf8(raw, p), str(p), scalar_tags=unit_tags(str(p)))
        if duplicates and str(p) not in duplicates_noted:  # one note per file, however often it is read
            duplicates_noted.add(str(p))
            shown = ", ".join(f"{k!r} ({f'twice on line {line}' if line == first else f'lines {first} and {line}'})"
                              for k, line, first in duplicates[:3])
            more = f" and {len(duplicates) - 3} more" if len(duplicates) > 3 else ""
            note(f"{p}: duplicate key {shown}{more}; the last value is used, as PyYAML (and so the xacro program) "
                 "reads it")
        return xacro.YamlListWrapper.wrap(data)

    def unit_tags(source: str) -> dict[str, Callable[[str], Any]]:
        """xacro's YAML unit tags (``!degrees 90``), their values evaluated by robokit's interpreter."""
        def make(factor: float) -> Callable[[str], Any]:
            return lambda text: float(evaluate(text, {}, source=source)) * factor
        units = {"!radians": 1.0, "!degrees": math.pi / 180.0, "!meters": 1.0, "!millimeters": 0.001,
                 "!foot": 0.3048, "!inches": 0.0254}
        return {tag: make(f) for tag, f in units.items()}

    def say(kind: str, default_location: bool) -> Callable[..., str]:
        def run(*args: Any, print_location: Any = default_location, **_: Any) -> str:
            text = " ".join(map(str, args))
            if print_location:
                text += f" (at {location()})"
            note(f"{current()}: xacro.{kind}: {text}")
            return ""
        return run

    def fatal(*args: Any) -> Any:
        raise UnsafeXacro(f"{current()}: xacro.fatal: {' '.join(map(str, args))}")

    def arg(name: Any) -> Any:
        return xacro.substitution_args_context["arg"][name]

    def dirname(*_: Any) -> str:
        return str(Path(os.path.abspath(current())).parent)

    xacro_ns: dict[str, Callable[..., Any]] = {
        "arg": arg, "tokenize": _tokenize, "dotify": lambda d: xacro.YamlDictWrapper(d),
        "abs_filename": xacro.abs_filename_spec, "load_yaml": load_yaml, "fatal": fatal,
        "message": say("message", False), "warning": say("warning", True), "error": say("error", True),
        "print_location": say("print_location", True),
    }
    top_level = {"load_yaml": load_yaml, "abs_filename": xacro.abs_filename_spec, "dotify": xacro_ns["dotify"]}

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

        functions: dict[str, Callable[..., Any]] = {
            "arg": lambda name: sargs.convert_value(sargs._eval_arg(name, args=args), "auto"),
            "dirname": dirname, "env": eval_env, "optenv": eval_optenv,
        }
        if "find" in sargs._eval_dict:
            functions["find"] = sargs._eval_dict["find"]
        value = evaluate(s, _Args(), source=current(), functions=functions, constants={"true": True, "false": False})
        if text_bound(value) > MAX_TEXT:
            raise UnsafeXacro(f"{current()}: $(eval {s[:60]}) gives more than {MAX_TEXT} characters; stopped")
        return str(value)

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

    names = ("parse", "eval_all", "safe_eval", "load_yaml", "eval_text", "handle_macro_call", "glob")
    saved: dict[str, Any] = {n: getattr(xacro, n) for n in names}
    saved_sargs = {n: getattr(sargs, n) for n in ("_eval", "_eval_env", "_eval_optenv", "_eval_dirname")}
    saved_dict = {k: sargs._eval_dict.get(k) for k in ("env", "optenv")}
    xacro.parse, xacro.eval_all, xacro.safe_eval, xacro.load_yaml = parse, eval_all, safe_eval, load_yaml
    xacro.eval_text, xacro.handle_macro_call = eval_text, handle_macro_call
    xacro.glob = types.SimpleNamespace(glob=safe_glob)
    sargs._eval, sargs._eval_env, sargs._eval_optenv, sargs._eval_dirname = sargs_eval, eval_env, eval_optenv, dirname
    sargs._eval_dict["env"], sargs._eval_dict["optenv"] = eval_env, eval_optenv
    try:
        yield
    finally:
        for n in names:
            setattr(xacro, n, saved[n])
        for n, v in saved_sargs.items():
            setattr(sargs, n, v)
        for k, v in saved_dict.items():
            if v is not None:
                sargs._eval_dict[k] = v

