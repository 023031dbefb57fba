"""A strict, bounded YAML reader for the files robokit is pointed at.

PyYAML's ``safe_load`` is safe against code execution but not against everything a file
from the internet or a typo can hold. :func:`load_yaml_text` adds, with a message that
names the file and the line:

* duplicate keys in a mapping are refused (PyYAML keeps the last one silently);
* aliases (``*name``) are refused — they are how a 500-byte file expands to gigabytes;
* numbers follow YAML 1.2: ``2e-4``, ``1E3`` and ``1.5e+3`` are floats (YAML 1.1, which
  PyYAML implements, reads them as strings);
* nesting deeper than :data:`MAX_DEPTH` and files larger than :data:`MAX_BYTES` are refused
  (no recursion error, no minutes of parsing);
* text that is not UTF-8 is refused with the byte offset.

:func:`load_pyyaml_text` reads a file **as PyYAML's** ``safe_load`` **does** — for files that
another program (the xacro program) reads with PyYAML, whose meaning must be the same here: YAML
1.1 scalars (``1e-3`` is a string, ``yes`` is true, ``0o17``/``1_000``/``1:30`` are integers),
anchors, aliases and merge keys (``<<: *base``), and a duplicate key keeps its last value (each
duplicate is reported back, for one note). It keeps the bounds: nesting, file size, and the size
of the data *with every alias expanded* (:data:`MAX_EXPANDED_NODES`), computed while the file is
composed, so an alias bomb is refused before anything is expanded; an alias to a node that
contains it (a recursive structure) and integers over :data:`MAX_INT_DIGITS` digits are refused.
"""
from __future__ import annotations

import os
import re
from typing import Any, Callable

import yaml

from robokit._io import read_input_text
from robokit.errors import InputError

__all__ = ["MAX_BYTES", "MAX_DEPTH", "MAX_EXPANDED_NODES", "MAX_INT_DIGITS", "load_pyyaml_text", "load_yaml_file",
           "load_yaml_text"]

#: Largest YAML file robokit reads (a 100-joint DH table with inertias is about 30 kB).
MAX_BYTES = 1 << 20
#: Deepest nesting of lists/mappings accepted (a DH file needs 4).
MAX_DEPTH = 20
#: Most nodes (scalars, lists, mappings) a file read by :func:`load_pyyaml_text` may hold with
#: every alias expanded (a 1 MB file without aliases holds at most about 250,000).
MAX_EXPANDED_NODES = 200_000
#: Longest integer :func:`load_pyyaml_text` converts, in characters (PyYAML's sexagesimal
#: ``1:2:3:…`` integers take quadratic time in their length).
MAX_INT_DIGITS = 100

# YAML 1.2 core schema floats (and ints written with an exponent).
_FLOAT_12 = re.compile(
    r"""^(?:[-+]?(?:\.[0-9]+|[0-9]+(?:\.[0-9]*)?)(?:[eE][-+]?[0-9]+)?
        |[-+]?\.(?:inf|Inf|INF)
        |\.(?:nan|NaN|NAN))\Z""",
    re.X,
)
_INT_12 = re.compile(r"^[-+]?[0-9]+\Z")


class _Error(Exception):
    def __init__(self, message: str, mark: Any = None) -> None:
        super().__init__(message)
        self.mark = mark


class _StrictLoader(yaml.SafeLoader):
    """SafeLoader with YAML 1.2 numbers, no aliases, no duplicate keys, bounded depth."""

    _depth = 0

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            event = self.peek_event()
            raise _Error(f"aliases (*{event.anchor}) are not allowed", event.start_mark)
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise _Error(f"nested deeper than {MAX_DEPTH} levels", self.peek_event().start_mark)
            return super().compose_node(parent, index)
        finally:
            self._depth -= 1

    def construct_mapping(self, node: Any, deep: bool = False) -> Any:
        seen: dict[Any, Any] = {}
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            try:
                hash(key)
            except TypeError:
                raise _Error("a mapping key must be a plain value", key_node.start_mark) from None
            if key in seen:
                raise _Error(
                    f"duplicate key {key!r} (first at line {seen[key] + 1})", key_node.start_mark
                )
            seen[key] = key_node.start_mark.line
        return super().construct_mapping(node, deep=deep)


# Replace the YAML 1.1 int/float resolvers by YAML 1.2's (copy the table so that
# PyYAML's own SafeLoader is untouched).
_StrictLoader.yaml_implicit_resolvers = {
    ch: [(tag, rx) for tag, rx in resolvers if tag not in ("tag:yaml.org,2002:float", "tag:yaml.org,2002:int")]
    for ch, resolvers in yaml.SafeLoader.yaml_implicit_resolvers.items()
}
_StrictLoader.add_implicit_resolver("tag:yaml.org,2002:int", _INT_12, list("-+0123456789"))
_StrictLoader.add_implicit_resolver("tag:yaml.org,2002:float", _FLOAT_12, list("-+0123456789."))


def _construct_float(loader: Any, node: Any) -> float:
    text = loader.construct_scalar(node)
    low = text.lower()
    if low in (".inf", "+.inf"):
        return float("inf")
    if low == "-.inf":
        return float("-inf")
    if low == ".nan":
        return float("nan")
    return float(text)


def _construct_int(loader: Any, node: Any) -> int:
    text = loader.construct_scalar(node)
    if len(text.lstrip("+-")) > 30:  # a 400-digit integer is a typo, not a length
        raise _Error(f"integer with {len(text)} digits is too large", node.start_mark)
    return int(text)


_StrictLoader.add_constructor("tag:yaml.org,2002:float", _construct_float)
_StrictLoader.add_constructor("tag:yaml.org,2002:int", _construct_int)


def load_yaml_text(text: str, source: str = "<string>",
                   scalar_tags: dict[str, Callable[[str], Any]] | None = None) -> Any:
    """Parse YAML ``text`` strictly (see the module docstring); errors name ``source``, the line and
    the column.

    scalar_tags : optional ``{"!tag": function}``; a scalar written ``!tag text`` becomes
    ``function(text)`` (e.g. xacro's unit tags ``!degrees 90``). Other tags stay refused.

    Raises :class:`robokit.InputError` for anything refused.
    """
    _check_size(text, source)
    try:
        return yaml.load(text, Loader=_with_tags(_StrictLoader, scalar_tags))  # noqa: S506 - a SafeLoader subclass
    except (_Error, yaml.YAMLError, RecursionError) as exc:
        raise _input_error(exc, source) from None


def _check_size(text: str, source: str) -> None:
    if len(text) > MAX_BYTES:
        raise InputError(f"{source}: file too large ({len(text)} characters; at most {MAX_BYTES})")


def _with_tags(base: type, scalar_tags: dict[str, Callable[[str], Any]] | None) -> type:
    """``base``, or a subclass where a scalar ``!tag text`` becomes ``scalar_tags[tag](text)``."""
    if not scalar_tags:
        return base
    constructors = dict(getattr(base, "yaml_constructors"))
    loader = type(f"_Tagged{base.__name__}", (base,), {"yaml_constructors": constructors})
    for tag, fn in scalar_tags.items():
        loader.add_constructor(  # type: ignore[attr-defined]
            tag, lambda ld, node, fn=fn: fn(ld.construct_scalar(node)))
    return loader


def _input_error(exc: BaseException, source: str) -> InputError:
    """The one-line InputError for what a YAML loader raised, naming ``source``, the line and the column."""
    if isinstance(exc, _Error):
        where = f" at line {exc.mark.line + 1}, column {exc.mark.column + 1}" if exc.mark is not None else ""
        return InputError(f"{source}: {exc}{where}")
    if isinstance(exc, yaml.YAMLError):
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(exc, "problem", None) or "syntax error"
        return InputError(f"{source}: not valid YAML{where} ({problem})")
    if isinstance(exc, RecursionError):
        return InputError(f"{source}: nested too deeply")
    return InputError(f"{source}: not valid YAML ({' '.join(str(exc).split())[:200]})")


def load_yaml_file(path: str | os.PathLike[str]) -> Any:
    """Read and parse a YAML file strictly; errors name the file (missing, unreadable, not UTF-8, too large)."""
    text = read_input_text(path, MAX_BYTES, "a YAML file")
    return load_yaml_text(text, source=str(path))


class _PyYamlLoader(yaml.SafeLoader):
    """PyYAML's SafeLoader (YAML 1.1, aliases, merge keys, last duplicate wins) with bounded
    nesting, bounded alias expansion, no recursive aliases, duplicates recorded."""

    def __init__(self, stream: str) -> None:
        super().__init__(stream)
        self._depth = 0
        self._sizes: dict[int, int] = {}  # id(node) -> its node count with aliases expanded
        self._done: set[int] = set()  # nodes fully composed
        self.duplicates: list[tuple[Any, int, int]] = []  # (key, line, first line)

    def compose_node(self, parent: Any, index: Any) -> Any:
        if self.check_event(yaml.AliasEvent):
            event = self.peek_event()
            target = self.anchors.get(event.anchor)
            if target is not None and id(target) not in self._done:
                raise _Error(f"the alias *{event.anchor} refers to a node that contains it (a recursive structure)",
                             event.start_mark)
            return super().compose_node(parent, index)
        self._depth += 1
        try:
            if self._depth > MAX_DEPTH:
                raise _Error(f"nested deeper than {MAX_DEPTH} levels", self.peek_event().start_mark)
            node = super().compose_node(parent, index)
        finally:
            self._depth -= 1
        if isinstance(node, yaml.MappingNode):
            children = [n for pair in node.value for n in pair]
        elif isinstance(node, yaml.SequenceNode):
            children = list(node.value)
        else:
            children = []
        size = 1 + sum(self._sizes.get(id(c), 1) for c in children)
        if size > MAX_EXPANDED_NODES:
            raise _Error(f"more than {MAX_EXPANDED_NODES} values once its aliases are expanded (an alias bomb?)",
                         node.start_mark)
        self._sizes[id(node)] = size
        self._done.add(id(node))
        return node

    def construct_mapping(self, node: Any, deep: bool = False) -> Any:
        if isinstance(node, yaml.MappingNode):
            seen: dict[Any, int] = {}
            for key_node, _ in node.value:
                if key_node.tag == "tag:yaml.org,2002:merge" or not isinstance(key_node, yaml.ScalarNode):
                    continue
                key = self.construct_object(key_node, deep=True)
                try:
                    hash(key)
                except TypeError:
                    continue
                if key in seen:
                    self.duplicates.append((key, key_node.start_mark.line + 1, seen[key] + 1))
                seen[key] = key_node.start_mark.line
        return super().construct_mapping(node, deep=deep)


def _pyyaml_int(loader: Any, node: Any) -> int:
    text = loader.construct_scalar(node)
    if len(text) > MAX_INT_DIGITS:
        raise _Error(f"an integer written with {len(text)} characters (at most {MAX_INT_DIGITS})", node.start_mark)
    return int(yaml.SafeLoader.construct_yaml_int(loader, node))


def _pyyaml_timestamp(loader: Any, node: Any) -> str:
    return str(yaml.SafeLoader.construct_yaml_timestamp(loader, node))


def _pyyaml_binary(loader: Any, node: Any) -> Any:
    raise _Error("a !!binary value (bytes are not robot data)", node.start_mark)


_PyYamlLoader.yaml_constructors = dict(yaml.SafeLoader.yaml_constructors)
_PyYamlLoader.add_constructor("tag:yaml.org,2002:int", _pyyaml_int)
_PyYamlLoader.add_constructor("tag:yaml.org,2002:timestamp", _pyyaml_timestamp)
_PyYamlLoader.add_constructor("tag:yaml.org,2002:binary", _pyyaml_binary)


def load_pyyaml_text(text: str, source: str = "<string>", scalar_tags: dict[str, Callable[[str], Any]] | None = None
                     ) -> tuple[Any, list[tuple[Any, int, int]]]:
    """Parse YAML ``text`` as PyYAML's ``safe_load`` does, with bounds (see the module docstring).

    Parameters
    ----------
    text : str
        The file's text.
    source : str
        The file named in errors.
    scalar_tags : dict, optional
        ``{"!tag": function}``: a scalar written ``!tag text`` becomes ``function(text)``.

    Returns
    -------
    data : object
        What ``yaml.safe_load`` returns (a timestamp as its text; ``!!binary`` is refused).
    duplicates : list of (key, line, first_line)
        Keys given twice in one mapping (the last value is kept, as PyYAML does).

    Raises
    ------
    InputError
        Not YAML, too large, nested too deeply, an alias bomb or a recursive alias, a huge
        integer; the message names ``source`` and the line.
    """
    _check_size(text, source)
    loader = _with_tags(_PyYamlLoader, scalar_tags)(text)
    try:
        data = loader.get_single_data()
        return data, loader.duplicates
    except (_Error, yaml.YAMLError, RecursionError, ValueError) as exc:
        raise _input_error(exc, source) from None
    finally:
        loader.dispose()
