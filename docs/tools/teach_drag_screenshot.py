"""Writes docs/img/teach_drag_ur5.png: the UR5's teach page after a drag to a target (``#q=…&T=…``,
the same entry point as the gizmo), with the gizmo, the ghost arm of every IK branch and their
labels; rendered by headless Chromium (software WebGL), reduced to a 192-colour palette.

Run from the repository root: ``python docs/tools/teach_drag_screenshot.py`` (needs the viz extra,
with ziglang, and chromium).
"""
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import robokit
from robokit.codegen.wasm import wasm_module
from robokit.viz.teach import teach_html

OUT = Path(__file__).resolve().parents[1] / "img" / "teach_drag_ur5.png"
Q_START = np.array([0.3, -1.2, 1.5, -1.9, -1.2, 0.4])  # where the arm was
Q_TARGET = np.array([0.9, -1.3, 1.7, -1.6, -1.0, 0.6])  # the pose dragged to is this q's tool pose


def main() -> int:
    chromium = shutil.which("chromium")
    if chromium is None:
        print("chromium not found", file=sys.stderr)
        return 1
    robot = robokit.load("ur5")
    T = robot.frame_pose(Q_TARGET)
    with tempfile.TemporaryDirectory() as tmp:
        page = Path(tmp) / "ur5.html"
        page.write_text(teach_html(robot, Q_START, wasm=wasm_module(robot).wasm), encoding="utf-8")
        frag = "#q=" + ",".join(repr(float(v)) for v in Q_START) + "&T=" + ",".join(repr(float(v)) for v in T.ravel())
        png = Path(tmp) / "shot.png"
        subprocess.run([chromium, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
                        "--use-angle=swiftshader", "--disable-quic", "--no-first-run", "--disable-background-networking",
                        "--disable-component-update", "--disable-sync", f"--user-data-dir={tmp}/profile",
                        "--window-size=1200,760", "--virtual-time-budget=15000", f"--screenshot={png}",
                        page.as_uri() + frag], check=True, capture_output=True, timeout=300)
        from PIL import Image

        Image.open(png).convert("RGB").quantize(colors=192).save(OUT, optimize=True)
    print(f"wrote {OUT} ({OUT.stat().st_size // 1024} kB)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
