"""Text labels drawn in meshcat scenes (frame names next to their triads).

A label is a three.js **sprite**: a textured square that the renderer always turns to face
the camera, so the text is never seen from behind (mirrored) nor edge-on, whichever way the
view is orbited. Its material ignores the depth buffer, so geometry never buries it.

Used by :mod:`robokit.viz.scene` and :mod:`robokit.viz.teach`; it imports neither, so the
two never import each other for it.
"""
from __future__ import annotations

import io
from typing import Any

import numpy as np

from robokit._optional import require

__all__ = ["label_png", "label_sprite", "label_offsets", "LABEL_ASPECT"]

#: Width / height of a label's image (and sprite).
LABEL_ASPECT = 3.2


def label_png(text: str, color: str = "#222222") -> bytes:
    """A transparent PNG showing ``text`` (white-outlined, so it reads on any background).

    Parameters
    ----------
    text : str
        The label (a frame name: any text; matplotlib's ``$…$`` math is not interpreted).
    color : str
        Matplotlib colour of the text.

    Returns
    -------
    bytes
        The PNG file's bytes (320 × 100 pixels).

    Examples
    --------
    >>> label_png("dh_0")[:4]
    b'\\x89PNG'
    """
    matplotlib = require("matplotlib", "frame labels in the viewer")
    matplotlib.use("Agg", force=False)
    Figure = require("matplotlib.figure").Figure
    patheffects = require("matplotlib.patheffects")

    fig = Figure(figsize=(3.2, 1.0), dpi=100)
    fig.patch.set_alpha(0.0)
    fig.text(0.5, 0.5, str(text)[:40], ha="center", va="center", fontsize=38, color=color, weight="bold",
             parse_math=False, path_effects=[patheffects.withStroke(linewidth=6, foreground="white")])
    buf = io.BytesIO()
    fig.savefig(buf, format="png", transparent=True, metadata={"Software": None})
    return _compact_png(buf.getvalue())


def _compact_png(png: bytes) -> bytes:
    """The same image in fewer bytes: grey + alpha (2 bytes a pixel instead of 4) when every pixel's
    red, green and blue are equal (a grey text with a white outline: always, unless ``color`` has a
    hue), stored with the strongest compression. Lossless: every pixel keeps its value."""
    from PIL import Image  # pillow: a dependency of matplotlib, which made the PNG


    img = Image.open(io.BytesIO(png))
    img.load()
    rgba = np.asarray(img.convert("RGBA"))
    grey = bool(np.all(rgba[..., 0] == rgba[..., 1]) and np.all(rgba[..., 1] == rgba[..., 2]))
    out = io.BytesIO()
    (img.convert("LA") if grey else img.convert("RGBA")).save(out, format="PNG", optimize=True)
    return out.getvalue() if len(out.getvalue()) < len(png) else png


def label_sprite(text: str, height: float) -> Any:
    """A camera-facing text label for a meshcat scene (``node.set_object(label_sprite(...))``).

    Parameters
    ----------
    text : str
        The label's text.
    height : float
        Height of the label in the scene (m); its width is :data:`LABEL_ASPECT` times that.

    Returns
    -------
    meshcat.geometry.Object
        A three.js ``Sprite`` with a ``SpriteMaterial`` (the text as its texture, drawn over
        the geometry: no depth test), scaled to ``height``.

    Examples
    --------
    >>> label_sprite("dh_4", 0.05).lower()["object"]["type"]
    'Sprite'
    """
    g = require("meshcat.geometry", "frame labels in the viewer")

    material_base: Any = g.GenericMaterial
    object_base: Any = g.Object

    class SpriteMaterial(material_base):
        _type = "SpriteMaterial"

    class Sprite(object_base):
        _type = "Sprite"

        def lower(self) -> dict:
            data: dict = {"metadata": {"version": 4.5, "type": "Object"}, "geometries": [], "materials": [],
                          "object": {"uuid": self.uuid, "type": self._type, "material": self.material.uuid,
                                     "matrix": [float(x) for x in np.diag([LABEL_ASPECT * height, height, 1.0, 1.0]).T.flatten()],
                                     "renderOrder": 10}}
            self.material.lower_in_object(data)
            return data

    mat = SpriteMaterial(map=g.ImageTexture(image=g.PngImage(label_png(text))), transparent=True, depthTest=False,
                         depthWrite=False, sizeAttenuation=True)
    return Sprite(g.Box([1, 1, 1]), mat)


def label_offsets(origins: Any, height: float, tol: float | None = None) -> np.ndarray:
    """Where to put the labels of frames at ``origins``: above each origin, stacked where origins coincide.

    Parameters
    ----------
    origins : array_like, shape (K, 3)
        The frames' origins (base frame, m), in drawing order.
    height : float
        A label's height (m).
    tol : float, optional
        Origins closer than this (m; default ``height``) share a stack.

    Returns
    -------
    numpy.ndarray, shape (K, 3)
        Offsets (base frame, m) from each origin to its label's centre: straight up (+z) by
        ``0.9·height`` for the first label of a stack, one more ``1.1·height`` per label below it
        in the list (a spherical wrist's ``dh_4``, ``dh_5``, ``dh_6`` and ``tool`` read as a column).

    Examples
    --------
    >>> label_offsets([[0, 0, 0], [1, 0, 0], [0, 0, 0]], 0.1)[:, 2].round(2).tolist()
    [0.09, 0.09, 0.2]
    """
    P = np.asarray(origins, dtype=float).reshape(-1, 3)
    tol = height if tol is None else tol
    out = np.zeros_like(P)
    for i in range(len(P)):
        below = sum(1 for j in range(i) if np.linalg.norm(P[j] - P[i]) < tol)
        out[i, 2] = (0.9 + 1.1 * below) * height
    return out
