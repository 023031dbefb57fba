"""robokit.viz — meshcat scenes (live and self-contained HTML) of robots.

Imported on demand (``import robokit.viz``): ``Scene`` (robot, DH frames, points, paths,
velocity ellipsoid, animations, camera framing, ``html()``), ``view_html``
(the ``robokit view`` command) and ``LiveViewer`` (a meshcat server on loopback).
"""
from robokit.viz.live import LiveViewer
from robokit.viz.scene import Scene
from robokit.viz.view import load_trajectory, view_html

__all__ = ["Scene", "LiveViewer", "view_html", "load_trajectory"]
