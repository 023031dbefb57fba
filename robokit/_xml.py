"""Bounded XML: every robot file robokit parses (URDF, xacro and its includes, MJCF and its
includes) goes through :func:`check_xml` before any other parser or any recursive code sees it.

The check is one streaming pass of expat (no tree is built) that refuses, with one line
naming the file and the line:

* a document type declaration (``<!DOCTYPE …>``) and with it every entity declaration — the
  way a 1 kB file expands to gigabytes ("billion laughs") or reads another file (external
  entities); robot descriptions never need one;
* elements nested deeper than :data:`MAX_XML_DEPTH` (a 20,000-deep body nest or 50,000 nested
  ``<visual>`` crash recursive parsers: Pinocchio's segfaults, Python's raise RecursionError);
* more than :data:`MAX_XML_ELEMENTS` elements;
* text that is not well-formed XML (``FILE:LINE:COLUMN: not well-formed XML (…)``).

Departures from XML 1.0 in :func:`parse_xml` (URDF, MJCF, SDFormat), where the engines of those
formats — urdfdom, MuJoCo, libsdformat (Gazebo, Drake) and PyBullet, which all parse with
TinyXML2 — read what XML 1.0 refuses; each keeps every line and column number:

* a comment holding ``--`` (``<!-- gz service … --reqtype … -->``, ``<!-- ---- links ---- -->``)
  is read (:func:`tolerant_comments`); 20 of gz-sim's example worlds have one;
* whitespace, and a byte-order mark after it, before the ``<?xml …?>`` declaration are read
  (:func:`tolerant_start`): TinyXML2 skips whitespace, then a byte-order mark, then whitespace
  again before it looks at the declaration; expat wants the declaration at the very start. A
  comment before the declaration stays refused (TinyXML2 refuses it too);
* with ``namespaces=False`` (URDF and SDFormat), a name keeps its prefix as written and needs no
  ``xmlns`` declaration (``<drake:joint_damping>``, ``gz:expressed_in="…"``): TinyXML2 knows no
  namespaces, and libsdformat takes a name holding ``:`` for a custom element or attribute, user
  data it keeps without reading. MJCF keeps XML's rule (``namespaces=True``): MuJoCo refuses a
  prefixed name, declared or not, as an unrecognized attribute or element.

:func:`check_xml` alone stays strict: xacro's own parser (expat, with namespaces) refuses such
files, and so does robokit's xacro.

The limits: a serial manipulator has at most :data:`robokit.description.limits.MAX_JOINTS`
joints, which an MJCF file nests one body per joint; 512 levels leave room for that and for
the few levels of ``<mujoco><worldbody>`` and ``<visual><geometry><mesh>`` around it. The
largest example-robot-data URDF has about 5,000 elements; 200,000 leaves room for detailed
descriptions while keeping a parse well under a second.
"""
from __future__ import annotations

import os
import re
import xml.etree.ElementTree as ET
import xml.parsers.expat
from typing import Any

from robokit.errors import InputError

__all__ = ["MAX_XML_DEPTH", "MAX_XML_ELEMENTS", "check_xml", "parse_xml", "tolerant_comments", "tolerant_start"]

#: Deepest element nesting accepted in a robot file.
MAX_XML_DEPTH = 512
#: Most elements accepted in one robot file (a xacro file: in its expansion too).
MAX_XML_ELEMENTS = 200_000


class _Refused(Exception):
    pass


def check_xml(raw: bytes | str, source: str | os.PathLike[str], *, max_depth: int = MAX_XML_DEPTH,
              max_elements: int = MAX_XML_ELEMENTS) -> int:
    """Check that ``raw`` is well-formed XML without a DTD or entities, nested at most
    ``max_depth`` deep, with at most ``max_elements`` elements (see the module docstring).

    Parameters
    ----------
    raw : bytes or str
        The document (bytes as read from the file, or text).
    source : str or Path
        The file it came from, named in the messages.
    max_depth, max_elements : int
        The bounds.

    Returns
    -------
    int
        The number of elements.

    Raises
    ------
    InputError
        One line naming ``source`` and the line of the offence.

    Examples
    --------
    >>> check_xml(b"<robot name='r'><link name='a'/></robot>", "r.urdf")
    2
    """
    parser = xml.parsers.expat.ParserCreate()
    state = {"depth": 0, "count": 0}

    def start(name: str, attrs: Any) -> None:
        state["depth"] += 1
        state["count"] += 1
        if state["depth"] > max_depth:
            raise _Refused(f"elements nested deeper than {max_depth} levels (at <{name}>)")
        if state["count"] > max_elements:
            raise _Refused(f"more than {max_elements} elements")

    def end(name: str) -> None:
        state["depth"] -= 1

    def doctype(*args: Any) -> None:
        raise _Refused("a <!DOCTYPE> declaration (DTDs and entities are not read in robot files)")

    def entity(*args: Any) -> None:
        raise _Refused("an <!ENTITY> declaration (entities are not read in robot files)")

    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.StartDoctypeDeclHandler = doctype
    parser.EntityDeclHandler = entity
    parser.ExternalEntityRefHandler = lambda *a: (_ for _ in ()).throw(_Refused("an external entity reference"))
    try:
        parser.Parse(raw, True)
    except _Refused as exc:
        raise InputError(f"{source}:{parser.CurrentLineNumber}: {exc}") from None
    except xml.parsers.expat.ExpatError as exc:
        msg = xml.parsers.expat.ErrorString(exc.code)
        raise InputError(f"{source}:{exc.lineno}:{exc.offset + 1}: not well-formed XML ({msg})") from None
    except RecursionError:  # pragma: no cover - expat is not recursive
        raise InputError(f"{source}: nested too deeply") from None
    return state["count"]


def _blank_dashes(body: bytes) -> bytes:
    """A comment's text with ``--`` (and a final ``-``) blanked, the same length."""
    body = body.replace(b"--", b"- ")
    return body[:-1] + b" " if body.endswith(b"-") else body


def _tolerant(raw: bytes) -> bytes:
    """One pass from left to right (linear in the size: an unterminated ``<!--`` or CDATA section ends
    the pass, the parser reports it), CDATA sections skipped, each comment's text blanked."""
    out, at = [], 0
    while True:
        c, d = raw.find(b"<!--", at), raw.find(b"<![CDATA[", at)
        if c < 0 and d < 0:
            break
        if d >= 0 and (c < 0 or d < c):  # a CDATA section: kept as it is
            end = raw.find(b"]]>", d + 9)
            if end < 0:
                break
            out.append(raw[at:end + 3])
            at = end + 3
            continue
        end = raw.find(b"-->", c + 4)
        if end < 0:
            break
        out.append(raw[at:c + 4])
        out.append(_blank_dashes(raw[c + 4:end]))
        out.append(b"-->")
        at = end + 3
    out.append(raw[at:])
    return b"".join(out)


def tolerant_comments(raw: bytes | str) -> bytes | str:
    """``raw`` with ``--`` inside comments (and a comment ending in ``--->``) blanked, the way
    TinyXML-based parsers read it; nothing else changes, not even a line or column number.

    Examples
    --------
    >>> tolerant_comments("<r><!-- run: gz sim --playback --></r>")
    '<r><!-- run: gz sim - playback --></r>'
    """
    if isinstance(raw, str):
        return _tolerant(raw.encode("utf-8")).decode("utf-8")
    return _tolerant(raw)


#: Whitespace as TinyXML2 skips it (C's isspace; expat reads only the first four).
_SPACES = re.compile(rb"[ \t\n\r\v\f]*")
_BOM = b"\xef\xbb\xbf"


def _start(data: bytes, blank: bytes) -> bytes | None:
    """``data`` with what stands before its first tag read as TinyXML2 reads it (whitespace, a
    byte-order mark, whitespace, a declaration), None when expat reads it as it is (linear)."""
    i = _SPACES.match(data).end()  # type: ignore[union-attr]  # matches the empty string at least
    b = len(_BOM) if data.startswith(_BOM, i) else 0
    j = _SPACES.match(data, i + b).end()  # type: ignore[union-attr]
    if j == b:
        return None  # nothing, or a byte-order mark alone, before the first tag: expat reads it
    head = data[:i] + (blank if b else b"") + data[i + b:j]
    after = data[j + 5:j + 6]
    end = data.find(b"?>", j) if data.startswith(b"<?xml", j) and (after == b"?" or after.isspace()) else -1
    if end >= 0:  # the declaration after them: expat wants it first, TinyXML2 reads it there
        head += bytes(c if c in b"\r\n" else 32 for c in data[j:end + 2])
        j = end + 2
    head = head.replace(b"\v", b" ").replace(b"\f", b" ")
    return None if head == data[:j] else head + data[j:]


def tolerant_start(raw: bytes | str) -> bytes | str:
    """``raw`` as TinyXML2 reads its start: whitespace, then a byte-order mark, then whitespace, then
    the ``<?xml …?>`` declaration. When whitespace stands before the declaration, the declaration is
    blanked (TinyXML2 reads the text as UTF-8 whatever it says); a byte-order mark after whitespace
    becomes blanks, a vertical tab or form feed a space; nothing else changes, not even a line or
    column number. A document expat reads as it is comes back unchanged.

    Examples
    --------
    >>> tolerant_start("\\n  <?xml version='1.0'?>\\n<robot/>")
    '\\n                       \\n<robot/>'
    >>> tolerant_start("<?xml version='1.0'?><robot/>")
    "<?xml version='1.0'?><robot/>"
    """
    if isinstance(raw, str):  # the text's characters kept one for one: a byte-order mark is one blank
        fixed = _start(raw.encode("utf-8"), b" ")
        return raw if fixed is None else fixed.decode("utf-8")
    fixed = _start(raw, b"   ")
    return raw if fixed is None else fixed


def _tree(raw: bytes | str) -> ET.Element:
    """The element tree of a well-formed document with every name as written (``drake:gear_ratio``,
    ``gz:expressed_in``): expat without namespace processing, as TinyXML2 reads names."""
    builder = ET.TreeBuilder()
    parser = xml.parsers.expat.ParserCreate()
    parser.buffer_text = True
    parser.StartElementHandler = builder.start
    parser.EndElementHandler = builder.end
    parser.CharacterDataHandler = builder.data
    parser.StartDoctypeDeclHandler = lambda *a: (_ for _ in ()).throw(_Refused("a <!DOCTYPE>"))  # check_xml refused it
    parser.Parse(raw, True)
    return builder.close()


def parse_xml(raw: bytes | str, source: str | os.PathLike[str], *, namespaces: bool = True) -> ET.Element:
    """:func:`check_xml`, then the root element as :mod:`xml.etree.ElementTree` parses it; comments
    holding ``--`` and whitespace before the declaration are read, as TinyXML2 reads them
    (:func:`tolerant_comments`, :func:`tolerant_start`).

    Parameters
    ----------
    raw : bytes or str
        The document.
    source : str or Path
        The file it came from, named in the messages.
    namespaces : bool
        True: XML's namespaces — a prefix must be declared and a name is ``{uri}local``. False: every
        name as written, prefix and all, declared or not, as TinyXML2 reads it (URDF, SDFormat).

    Returns
    -------
    xml.etree.ElementTree.Element
        The root element.

    Raises
    ------
    InputError
        See :func:`check_xml`; with ``namespaces``, also a prefix no ``xmlns`` declares.

    Examples
    --------
    >>> parse_xml(b"<mujoco model='m'/>", "m.xml").get("model")
    'm'
    >>> parse_xml("<sdf><model gz:x='1'><drake:joint/></model></sdf>", "m.sdf", namespaces=False)[0][0].tag
    'drake:joint'
    """
    raw = tolerant_start(tolerant_comments(raw))
    check_xml(raw, source)
    if not namespaces:
        return _tree(raw)
    try:
        return ET.fromstring(raw)
    except ET.ParseError as exc:  # check_xml read it: a namespace error, the one check it does not make
        line, col = exc.position
        reason = xml.parsers.expat.ErrorString(exc.code) if isinstance(exc.code, int) else "namespaces"
        raise InputError(f"{source}:{line}:{col + 1}: not well-formed XML ({reason}: a namespace prefix "
                         "no xmlns declares)") from None
