"""``robokit view --trajectory`` files are bounded: rows counted, a ``.npy`` header checked before
anything is loaded (dtype, declared shape against the file's size), FIFOs refused."""
import os
import subprocess

import numpy as np
import pytest

import hardening_support as hs


def test_trajectory_rows_are_bounded(tmp_path, main_cli):
    csv = tmp_path / "t.csv"
    csv.write_text("q1,q2,q3,q4,q5,q6\n" + "0,0,0,0,0,0\n" * 100_001)
    run = main_cli("view", "puma560", "-o", tmp_path / "v.html", "--trajectory", csv)
    hs.assert_one_line_error(run, "t.csv", "100000")
    assert not (tmp_path / "v.html").exists()


@pytest.mark.parametrize("kind", ["complex npy", "object npy", "fifo csv", "huge header"])
def test_trajectory_files_are_checked_before_loading(kind, tmp_path):
    from robokit.errors import InputError
    from robokit.viz.view import load_trajectory

    p = tmp_path / ("t.npy" if "npy" in kind or "header" in kind else "t.csv")
    if kind == "complex npy":
        np.save(p, np.zeros((4, 6), complex))
    elif kind == "object npy":
        np.save(p, np.array([[None] * 6] * 2, dtype=object), allow_pickle=True)
    elif kind == "fifo csv":
        os.mkfifo(p)
    else:  # a header declaring 10^11 rows of a tiny file
        header = {"descr": "<f8", "fortran_order": False, "shape": (10**11, 6)}
        with open(p, "wb") as f:
            np.lib.format.write_array_header_1_0(f, header)
    with pytest.raises(InputError, match="--trajectory"):
        load_trajectory(p, 6)



def _npy_header_only(shape, dtype="<f8") -> bytes:
    import io

    buf = io.BytesIO()
    np.lib.format.write_array_header_1_0(buf, {"descr": dtype, "fortran_order": False, "shape": shape})
    return buf.getvalue()


TRAJECTORIES = [
    ("huge.npy", _npy_header_only((10**11, 1)), "has 100000000000 rows; at most"),
    ("rows.npy", _npy_header_only((300_000, 1)) + b"\0" * 8 * 300_000, "has 300000 rows; at most"),
    ("object.npy", _npy_header_only((2, 1), "|O") + b"\0" * 16, "expected real numbers"),
    ("complex.npy", _npy_header_only((2, 1), "<c16") + b"\0" * 32, "expected real numbers"),
    ("rows.csv", "0.1\n" * 300_001, "rows; at most"),
]


@pytest.mark.parametrize("name, content, word", TRAJECTORIES, ids=[t[0] for t in TRAJECTORIES])
def test_trajectory_files_are_bounded(name, content, word, write, tmp_path, main_cli):
    """``robokit view --trajectory``: a .npy header is checked before loading and the rows are
    bounded (a (10¹¹, 1) header was a MemoryError; it runs under a 3 GB address-space limit)."""
    import resource
    import sys

    traj = write(name, content)
    model = write("pend.urdf", hs.pendulum_urdf())
    out = tmp_path / "out.html"
    if name != "huge.npy":
        run = main_cli("view", model, "--trajectory", traj, "-o", out)
    else:
        def limit():
            resource.setrlimit(resource.RLIMIT_AS, (3 * 1024**3, 3 * 1024**3))

        p = subprocess.run([sys.executable, "-m", "robokit.cli", "view", str(model), "--trajectory", str(traj),
                            "-o", str(out)], capture_output=True, text=True, timeout=hs.HANG_GUARD,
                           env=hs.subprocess_env(), preexec_fn=limit)
        run = hs.Run(p.returncode, p.stdout, p.stderr)
    hs.assert_one_line_error(run, "--trajectory", name, word)
    assert not out.exists()
