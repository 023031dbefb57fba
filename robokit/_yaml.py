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
"""
from __future__ import annotations

import os
import re
from typing import Any, Callable

import yaml

from robokit._io import read_input_text
from robokit.errors import InputError

__all__ = ["MAX_BYTES", "MAX_DEPTH", "load_yaml_file", "load_yaml_text"]

#: Largest YAML file robokit reads (a 100-joint DH table with inertias is about 30 kB).
MAX_BYTES = 1 << 20
#: Deepest nesting of lists/mappings accepted (a DH file needs 4).
MAX_DEPTH = 20

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
    if len(text) > MAX_BYTES:
        raise InputError(f"{source}: file too large ({len(text)} characters; at most {MAX_BYTES})")
    loader: type = _StrictLoader
    if scalar_tags:
        loader = type("_TaggedLoader", (_StrictLoader,), {"yaml_constructors": dict(_StrictLoader.yaml_constructors)})
        for tag, fn in scalar_tags.items():
            loader.add_constructor(  # type: ignore[attr-defined]
                tag, lambda ld, node, fn=fn: fn(ld.construct_scalar(node)))
    try:
        return yaml.load(text, Loader=loader)  # noqa: S506 - a SafeLoader subclass
    except _Error as exc:
        where = f" at line {exc.mark.line + 1}, column {exc.mark.column + 1}" if exc.mark is not None else ""
        raise InputError(f"{source}: {exc}{where}") from None
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None) or getattr(exc, "context_mark", None)
        where = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(exc, "problem", None) or "syntax error"
        raise InputError(f"{source}: not valid YAML{where} ({problem})") from None
    except RecursionError:
        raise InputError(f"{source}: nested too deeply") from None


def load_yaml_file(path: str | os.PathLike[str]) -> Any:
    """Read and parse a YAML file strictly; errors name the file (missing, unreadable, not UTF-8, too large)."""
    text = read_input_text(path, MAX_BYTES, "a YAML file")
    return load_yaml_text(text, source=str(path))
