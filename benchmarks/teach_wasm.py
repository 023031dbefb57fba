"""The teach page's IK update: the robot's generated C compiled to WebAssembly, run in Node.

For each robot the module is built (``robokit.codegen.wasm.wasm_module``) and timed in Node
(``performance.now`` around loops over 256 poses, the fastest of 7 runs) through the page's own
loader, ``teach_wasm.js``: ``ik`` (every closed-form solution, copies in and out of the module
included), the IK update (``ik`` and the nearest solution's choice: what a drag frame costs before
drawing), ``fk``, ``jacobian``, ``placements`` (every body's placement, from ``NAME_joint_poses``)
and the page's whole numeric update at a configuration (``teach_math.js``'s ``readouts`` over the
module, SVD and all, plus the placements); and, for comparison in the same run, robokit's Python
``ik_analytic``. Prints a Markdown table; asserts nothing.

Run: ``.venv/bin/python -m benchmarks.teach_wasm [--quick]``
"""
from __future__ import annotations

import argparse
import json
import shutil
import subprocess
from importlib import resources

import numpy as np

from benchmarks._harness import fmt_time, machine, table, time_best

NODE_SCRIPT = r"""
var RKWasm = require(process.argv[1]), RKMath = require(process.argv[2]);
var I = JSON.parse(require("fs").readFileSync(0, "utf8"));
var k = RKWasm.load(RKWasm.decode(I.wasm)), reps = I.reps;
function best(fn) {
  var b = Infinity;
  for (var run = 0; run < 7; run++) {
    var t0 = performance.now();
    for (var r = 0; r < reps; r++) { for (var i = 0; i < I.Ts.length; i++) { fn(i); } }
    b = Math.min(b, (performance.now() - t0) / (reps * I.Ts.length));
  }
  return b * 1e-3;  // s per call
}
var sink = 0;
var out = {
  ik: best(function (i) { sink += k.ik(I.Ts[i], 0).length; }),
  update: best(function (i) { var s = k.ik(I.Ts[i], 0); sink += RKWasm.nearest(s, I.qs[i]); }),
  fk: best(function (i) { sink += k.fk(I.qs[i])[3]; }),
  jacobian: best(function (i) { sink += k.jacobian(I.qs[i])[0][0]; }),
  placements: best(function (i) { sink += k.placements(I.qs[i])[1][3]; }),
  readouts: best(function (i) { sink += RKMath.readouts(I.R, I.qs[i], k).T[3] + k.placements(I.qs[i])[1][3]; }),
  solutions: I.Ts.reduce(function (a, T) { return a + k.ik(T, 0).length; }, 0) / I.Ts.length
};
process.stdout.write(JSON.stringify(out));
"""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="fewer repetitions")
    args = ap.parse_args(argv)
    node = shutil.which("node")
    if node is None:
        print("teach_wasm: node not found; skipped")
        return
    import robokit
    from robokit.codegen.wasm import wasm_module
    from robokit.viz.teach import teach_parameters

    wasm_js = str(resources.files("robokit.viz").joinpath("teach_wasm.js"))
    math_js = str(resources.files("robokit.viz").joinpath("teach_math.js"))
    rows = []
    from benchmarks.general_6r import jaco2_table

    for name in ("puma560", "ur5", "jaco2_6n"):
        robot = robokit.load(jaco2_table()) if name == "jaco2_6n" else robokit.load(name)
        m = wasm_module(robot)
        lo, hi = np.array(robot.qlim, dtype=float).T
        lo, hi = np.where(np.isfinite(lo), lo, -np.pi), np.where(np.isfinite(hi), hi, np.pi)
        qs = np.random.default_rng(0).uniform(lo, hi, size=(256, robot.n))
        Ts = [robot.frame_pose(q) for q in qs]
        res = subprocess.run([node, "-e", NODE_SCRIPT, wasm_js, math_js], capture_output=True, text=True, check=True,
                             input=json.dumps({"wasm": m.base64(), "reps": 5 if args.quick else 40,
                                               "R": teach_parameters(robot), "qs": qs.tolist(),
                                               "Ts": [T.ravel().tolist() for T in Ts]}))
        t = json.loads(res.stdout)
        py = time_best(lambda: [robokit.ik_analytic(robot, T) for T in Ts[:16]], batches=20 if args.quick else 100) / 16
        rows.append([name, f"{len(m.wasm) / 1000:.1f} kB", f"{t['solutions']:.2f}", fmt_time(t["ik"]),
                     fmt_time(t["update"]), fmt_time(py), f"{py / t['update']:.1f}×",
                     fmt_time(t["fk"]), fmt_time(t["jacobian"]), fmt_time(t["placements"]),
                     fmt_time(t["readouts"])])
    print(machine() + "; Node " + subprocess.run([node, "--version"], capture_output=True, text=True).stdout.strip()
          + "; fastest of 7 loops over 256 poses (Python: fastest of short batches)")
    print()
    print(table(["robot", "module", "solutions/pose", "wasm ik (all)", "IK update (ik + nearest)",
                 "ik_analytic (Python)", "ratio", "wasm fk", "wasm jacobian", "wasm placements",
                 "page numbers at q (readouts + placements)"], rows))


if __name__ == "__main__":
    main()
