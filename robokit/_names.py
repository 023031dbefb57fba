"""Names that form file names: a robot, link or joint name is data and never becomes a path.

Robot files name their robot, links and joints with any text (``../../X``, ``a/b``, ``<!--``,
control characters, 10 000 characters). Wherever robokit builds a file name from such a name
(``Scene.notebook()``'s ``robokit_views/<robot>-<k>.html``, ``robokit teach``'s temporary
page) it goes through :func:`safe_stem` first, so the file lands in the folder robokit chose
and nowhere else.
"""
from __future__ import annotations

import re
import unicodedata

__all__ = ["safe_stem", "MAX_STEM"]

#: Longest stem :func:`safe_stem` returns (characters); file systems allow 255 bytes per name.
MAX_STEM = 64

_UNSAFE = re.compile(r"[^A-Za-z0-9_.+-]+")


def safe_stem(name: object, default: str = "robot") -> str:
    """A file-name stem made from ``name`` that is one plain path component.

    Parameters
    ----------
    name : object
        A robot / link / joint name (anything; ``str(name)`` is used).
    default : str
        The stem when nothing usable is left (an empty name, only punctuation).

    Returns
    -------
    str
        1 to :data:`MAX_STEM` characters from ``[A-Za-z0-9_.+-]``: accents are dropped
        (NFKD), every other run of characters (``/``, ``\\``, spaces, NUL, control
        characters, other scripts) becomes one ``_``; ``..`` never occurs; the stem never
        starts with ``.`` or ``-`` (no hidden file, no command-line option).

    Examples
    --------
    >>> safe_stem("../../X")
    'X'
    >>> safe_stem("ur5 (left arm)")
    'ur5_left_arm'
    """
    text = unicodedata.normalize("NFKD", str(name)).encode("ascii", "ignore").decode("ascii")
    text = _UNSAFE.sub("_", text)
    text = re.sub(r"\.{2,}", "_", text)
    text = re.sub(r"_{2,}", "_", text)
    text = text.lstrip("._-+").rstrip("._")
    text = text[:MAX_STEM].rstrip("._")
    return text or default
