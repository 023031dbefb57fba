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

One departure from XML 1.0, in :func:`parse_xml` (URDF, MJCF, SDFormat): a comment holding
``--`` (``<!-- gz service … --reqtype … -->``, ``<!-- ---- links ---- -->``) is read, as the
engines of those formats read it — urdfdom, MuJoCo, libsdformat (Gazebo, Drake) and PyBullet all
parse with TinyXML, which accepts it; 20 of gz-sim's example worlds have one. :func:`check_xml`
alone stays strict: xacro's own parser (expat) refuses such a file, and so does robokit's xacro.

The limits: a serial manipulator has at most :data:`robokit.description.limits.MAX_JOINTS`
joints, which an MJCF file nests one body per joint; 512 levels leave room for that and for
the few levels of ``<mujoco><worldbody>`` and ``<visual><geometry><mesh>`` around it. The
largest example-robot-data URDF has about 5,000 elements; 200,000 leaves room for detailed
descriptions while keeping a parse well under a second.
"""
from __future__ import annotations

import os
import xml.etree.ElementTree as ET
import xml.parsers.expat
from typing import Any

from robokit.errors import InputError

__all__ = ["MAX_XML_DEPTH", "MAX_XML_ELEMENTS", "check_xml", "parse_xml", "tolerant_comments"]

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


def parse_xml(raw: bytes | str, source: str | os.PathLike[str]) -> ET.Element:
    """:func:`check_xml`, then the root element as :mod:`xml.etree.ElementTree` parses it;
    comments holding ``--`` are read, as TinyXML reads them (:func:`tolerant_comments`).

    Parameters
    ----------
    raw : bytes or str
        The document.
    source : str or Path
        The file it came from, named in the messages.

    Returns
    -------
    xml.etree.ElementTree.Element
        The root element.

    Raises
    ------
    InputError
        See :func:`check_xml`.

    Examples
    --------
    >>> parse_xml(b"<mujoco model='m'/>", "m.xml").get("model")
    'm'
    """
    raw = tolerant_comments(raw)
    check_xml(raw, source)
    try:
        return ET.fromstring(raw)
    except ET.ParseError as exc:  # pragma: no cover - check_xml refused malformed text
        line, col = exc.position
        raise InputError(f"{source}: not well-formed XML at line {line}, column {col + 1}") from None
