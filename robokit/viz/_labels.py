"""Text labels drawn in meshcat scenes (frame names next to their triads).

Used by :mod:`robokit.viz.scene` and :mod:`robokit.viz.teach`; it imports neither, so the
two never import each other for it.
"""
from __future__ import annotations

import io

from robokit._optional import require

__all__ = ["label_png"]


def label_png(text: str, color: str = "#222222") -> bytes:
    """A small transparent PNG showing ``text``, for a label drawn on a plane in a scene.

    Parameters
    ----------
    text : str
        The label (a frame name: any text; matplotlib's ``$…$`` math is not interpreted).
    color : str
        Matplotlib colour of the text.

    Returns
    -------
    bytes
        The PNG file's bytes (160 × 50 pixels).

    Examples
    --------
    >>> label_png("dh_0")[:4]
    b'\\x89PNG'
    """
    matplotlib = require("matplotlib", "frame labels in the viewer")
    matplotlib.use("Agg", force=False)
    Figure = require("matplotlib.figure").Figure

    fig = Figure(figsize=(1.6, 0.5), dpi=100)
    fig.patch.set_alpha(0.0)
    fig.text(0.5, 0.5, str(text)[:40], ha="center", va="center", fontsize=20, color=color, weight="bold",
             parse_math=False)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", transparent=True)
    return buf.getvalue()
