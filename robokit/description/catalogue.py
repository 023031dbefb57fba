r"""The names ``robokit.load`` knows without a file, and what to say about a name it does not know.

:class:`ModelCatalogue` is what ``robokit.models()`` returns (built by
:func:`robokit.description.loading.models`): the shipped DH models and the example-robot-data
names, one :class:`ModelInfo` row each, and the file formats ``load`` reads. It iterates over the
names (``"panda" in rk.models()``) and prints as a table.

:func:`unknown_model_hint` writes the end of the error for a name that is none of these: the
nearest known names (:func:`difflib.get_close_matches`, case-insensitive, so ``Panda`` gives
``panda``), or — for a well-known arm robokit does not ship (:data:`ELSEWHERE`: the KUKA iiwa,
the UR e-series, the Kinova Gen3, the Franka FR3, the Kinova Jaco) — where its description file
is published and how to load it.
"""
from __future__ import annotations

import difflib
from dataclasses import dataclass
from typing import Iterator, Mapping, Sequence

__all__ = ["ModelInfo", "ModelCatalogue", "ELSEWHERE", "FORMAT_NAMES", "unknown_model_hint"]

#: What each file suffix ``robokit.load`` reads holds (a suffix without an entry shows as itself).
FORMAT_NAMES = {
    ".yaml": "DH table", ".yml": "DH table", ".urdf": "URDF", ".xacro": "xacro", ".xml": "MJCF", ".sdf": "SDFormat",
}

_MENAGERIE = "MuJoCo Menagerie (github.com/google-deepmind/mujoco_menagerie)"
_DRAKE = "Drake's models (github.com/RobotLocomotion/models)"
_UR2 = "Universal Robots' ROS 2 description (github.com/UniversalRobots/Universal_Robots_ROS2_Description)"

#: Well-known arms robokit does not ship, by name and aliases: (what it is, where its file is, how to load it).
ELSEWHERE: dict[tuple[str, ...], tuple[str, str, str]] = {
    ("iiwa", "iiwa14", "iiwa7", "kuka", "lbr", "lbr_iiwa", "kuka_iiwa"): (
        "the KUKA LBR iiwa 14",
        f"kuka_iiwa_14/iiwa14.xml in {_MENAGERIE}, or iiwa_description/urdf/iiwa14_no_collision.urdf in {_DRAKE}",
        'rk.load("kuka_iiwa_14/iiwa14.xml")'),
    ("ur5e", "ur3e", "ur10e", "ur16e", "ur20", "ur30"): (
        "the Universal Robots e-series",
        f"urdf/ur.urdf.xacro in {_UR2} (or universal_robots_ur5e/ur5e.xml in {_MENAGERIE})",
        'rk.load("Universal_Robots_ROS2_Description/urdf/ur.urdf.xacro", xacro_args={"ur_type": "ur5e"})'),
    ("gen3", "kinova_gen3", "kortex"): (
        "the Kinova Gen3",
        f"kinova_gen3/gen3.xml in {_MENAGERIE}",
        'rk.load("kinova_gen3/gen3.xml")'),
    ("fr3", "franka_fr3", "franka_research_3"): (
        "the Franka Research 3",
        f"robots/fr3/fr3.urdf.xacro in Franka's franka_description (github.com/frankaemika/franka_description), "
        f"or franka_fr3/fr3.xml in {_MENAGERIE}",
        'rk.load("franka_description/robots/fr3/fr3.urdf.xacro")'),
    ("jaco", "jaco2", "j2s7s300", "j2n6s300", "kinova_jaco"): (
        "the Kinova Jaco",
        f"jaco_description/urdf/j2s7s300.urdf in {_DRAKE} (example-robot-data's 'kinova' is a 6-joint Jaco: "
        "rk.load(\"kinova\"))",
        'rk.load("jaco_description/urdf/j2s7s300.urdf")'),
}


@dataclass(frozen=True)
class ModelInfo:
    """One name ``robokit.load`` knows without a file.

    Attributes
    ----------
    name : str
        What to pass to ``robokit.load``.
    source : str
        ``"shipped DH table"`` or ``"example-robot-data"``.
    note : str
        The default tip of an arm, a floating base fixed when loaded, … (may be empty).
    """

    name: str
    source: str
    note: str = ""


class ModelCatalogue(Sequence[str]):
    """The names ``robokit.load`` knows without a file, and the file formats it reads.

    A sequence of names (``"panda" in catalogue``, ``list(catalogue)``); ``rows`` has one
    :class:`ModelInfo` per name, ``formats`` the file suffixes with what they hold. It prints as
    a table (``repr``, and ``_repr_html_`` in a notebook).

    Parameters
    ----------
    rows : sequence of ModelInfo
        The names, in the order shown.
    formats : mapping of str to str
        File suffix → what it holds.

    Attributes
    ----------
    rows : tuple of ModelInfo
    formats : dict of str to str

    Examples
    --------
    >>> cat = ModelCatalogue([ModelInfo("twolink", "shipped DH table")], {".urdf": "URDF"})
    >>> "twolink" in cat, len(cat)
    (True, 1)
    >>> print(cat)
    robokit.load knows 1 name without a file (1 shipped DH table):
    name     source
    -------  ----------------
    twolink  shipped DH table
    and reads files: .urdf (URDF)
    """

    def __init__(self, rows: Sequence[ModelInfo], formats: Mapping[str, str]) -> None:
        self.rows = tuple(rows)
        self.formats = dict(formats)
        self._names = [r.name for r in self.rows]

    def __getitem__(self, i):  # type: ignore[no-untyped-def]
        return self._names[i]

    def __len__(self) -> int:
        return len(self._names)

    def __iter__(self) -> Iterator[str]:
        return iter(self._names)

    def __contains__(self, name: object) -> bool:
        return name in self._names

    def _summary(self) -> str:
        counts: dict[str, int] = {}
        for r in self.rows:
            counts[r.source] = counts.get(r.source, 0) + 1
        parts = ", ".join(f"{c} {s}" for s, c in counts.items())
        return f"robokit.load knows {len(self)} name{'s' if len(self) != 1 else ''} without a file ({parts}):"

    def _format_line(self) -> str:
        by_kind: dict[str, list[str]] = {}
        for suffix, what in self.formats.items():
            by_kind.setdefault(what, []).append(suffix)
        return "and reads files: " + ", ".join(f"{'/'.join(s)} ({w})" for w, s in by_kind.items())

    def __repr__(self) -> str:
        head = ("name", "source", "note") if any(r.note for r in self.rows) else ("name", "source")
        body = [(r.name, r.source, r.note)[: len(head)] for r in self.rows]
        widths = [max(len(x) for x in col) for col in zip(head, *body)]
        line = lambda cells: "  ".join(c.ljust(w) for c, w in zip(cells, widths)).rstrip()  # noqa: E731
        return "\n".join([self._summary(), line(head), line(tuple("-" * w for w in widths)),
                          *(line(b) for b in body), self._format_line()])

    def _repr_html_(self) -> str:
        import html

        rows = "".join(f"<tr><td><code>{html.escape(r.name)}</code></td><td>{html.escape(r.source)}</td>"
                       f"<td>{html.escape(r.note)}</td></tr>" for r in self.rows)
        return (f"<p>{html.escape(self._summary())}</p><table><tr><th>name</th><th>source</th><th>note</th></tr>"
                f"{rows}</table><p>{html.escape(self._format_line())}</p>")


def unknown_model_hint(name: str, known: Sequence[str]) -> str:
    """What to tell a user whose model name is unknown: the nearest known names, or where a
    well-known arm's file is published and how to load it.

    Parameters
    ----------
    name : str
        The name given.
    known : sequence of str
        The names ``robokit.load`` knows (shipped and example-robot-data).

    Returns
    -------
    str
        A sentence (no leading separator); empty when nothing is near.

    Examples
    --------
    >>> unknown_model_hint("Panda", ["panda", "puma560", "ur5"])
    "did you mean 'panda'?"
    >>> print(unknown_model_hint("iiwa", ["panda"]).split(":")[0])
    robokit does not ship the KUKA LBR iiwa 14
    """
    key = name.strip().lower().replace("-", "_").replace(" ", "_")
    for aliases, (what, where, how) in ELSEWHERE.items():
        if key in aliases:
            return f"robokit does not ship {what}: its description is {where}; download it and load the file: {how}"
    lower = {k.lower(): k for k in known}
    if key in lower:
        return f"did you mean {lower[key]!r}?"
    near = [lower[k] for k in difflib.get_close_matches(key, list(lower), n=3, cutoff=0.6)]
    if not near:
        aliases_of = {a: aliases for aliases in ELSEWHERE for a in aliases}
        close = difflib.get_close_matches(key, list(aliases_of), n=1, cutoff=0.75)
        if close:
            what, where, how = ELSEWHERE[aliases_of[close[0]]]
            return f"robokit does not ship {what}: its description is {where}; download it and load the file: {how}"
        return ""
    return "did you mean " + " or ".join(repr(n) for n in near) + "?"
