"""The calibration data file of ``robokit calibrate``: a CSV of joint values and measured tool poses.

Format: a header row, then one row per measurement, comma-separated, with the columns

``q1, …, qn, x, y, z`` (tool positions, m) or ``q1, …, qn, x, y, z, qw, qx, qy, qz`` (tool poses:
position and unit quaternion, scalar first), all in the robot's base frame; joint values in rad (m
for prismatic joints). Blank lines and lines starting with ``#`` are skipped; a cell may be quoted
(``"q1"``). A number is what :mod:`robokit._table` reads (``-0.5``, ``12``, ``1.5e-3``; no ``1_0``,
no digits of other scripts, no ``inf``/``nan``), at most 1e12 in magnitude like every number of a
robot file. The file is bounded (:data:`MAX_BYTES`, :data:`MAX_ROWS`, lines of at most 16,384
characters) and must be a regular file. Any bad cell is refused with the file, the line and the
column named; joint values outside the model's limits only give a note (a real arm may have wider
limits than its model).
"""
from __future__ import annotations

import os
import stat
import warnings
from pathlib import Path

import numpy as np

from robokit._io import read_input_text
from robokit._table import number_row, table_lines
from robokit.errors import InputError, RobokitWarning
from robokit.spatial.quaternion import matrix_from_quaternion

__all__ = ["read_calibration_csv", "write_calibration_csv", "MAX_BYTES", "MAX_ROWS"]

#: Largest calibration CSV read (bytes).
MAX_BYTES = 64 * 1024 * 1024
#: Most measurement rows read.
MAX_ROWS = 200_000
#: Tolerance on a quaternion's norm.
QUATERNION_TOL = 1e-6


def _header(n: int, poses: bool) -> list[str]:
    cols = [f"q{i + 1}" for i in range(n)] + ["x", "y", "z"]
    return cols + ["qw", "qx", "qy", "qz"] if poses else cols


def read_calibration_csv(path: str | os.PathLike[str], n: int,
                         qlim: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Read a calibration CSV for an n-joint robot.

    Parameters
    ----------
    path : str or PathLike
        The CSV file (format in the module docstring).
    n : int
        The robot's number of joints.
    qlim : ndarray, shape (n, 2), optional
        Joint limits: values outside give a :class:`robokit.RobokitWarning` naming the column.

    Returns
    -------
    q : ndarray, shape (K, n)
        Joint values.
    measured : ndarray, shape (K, 4, 4) or (K, 3)
        Tool poses (quaternion columns present) or tool positions, base frame.

    Raises
    ------
    InputError
        Missing, too large or non-regular file; wrong header (names or count); a row with the wrong
        number of cells, a cell that is not a finite number, a quaternion whose norm is not 1
        within 1e-6 — naming the line and the column.

    Examples
    --------
    >>> import pathlib, tempfile
    >>> from robokit.calibration import read_calibration_csv
    >>> p = pathlib.Path(tempfile.mkdtemp()) / "d.csv"
    >>> _ = p.write_text("q1,q2,x,y,z\\n0.1,0.2,1.0,0.5,0.0\\n")
    >>> q, m = read_calibration_csv(p, 2)
    >>> q.shape, m.shape
    ((1, 2), (1, 3))
    """
    p = Path(path)
    try:
        st = p.stat()
    except FileNotFoundError:
        raise InputError(f"{p}: file not found") from None
    except OSError as exc:
        raise InputError(f"{p}: cannot read ({exc.strerror})") from None
    if not stat.S_ISREG(st.st_mode):
        raise InputError(f"{p}: not a regular file (a calibration CSV is expected)")
    text = read_input_text(p, MAX_BYTES, "a CSV file").removeprefix("\ufeff")  # a spreadsheet's byte-order mark
    header: list[str] | None = None
    header_line = 0
    rows: list[list[float]] = []
    lines: list[int] = []
    for line, row in table_lines(text, str(p)):
        if header is None:
            header = [c.lower() for c in row]
            header_line = line
            want3, want7 = _header(n, False), _header(n, True)
            if header not in (want3, want7):
                if len(header) not in (len(want3), len(want7)):
                    raise InputError(f"{p}: line {line} (header): expected {len(want3)} columns "
                                     f"({', '.join(want3)}) or {len(want7)} (… {', '.join(want7[-4:])}) for a "
                                     f"{n}-joint robot, got {len(header)}")
                want = want3 if len(header) == len(want3) else want7
                k = next(i for i, (a, b) in enumerate(zip(header, want)) if a != b)
                raise InputError(f"{p}: line {line} (header), column {k + 1}: expected {want[k]!r}, "
                                 f"got {row[k][:40]!r}")
            continue
        if len(rows) >= MAX_ROWS:
            raise InputError(f"{p}: more than {MAX_ROWS} measurement rows")
        if len(row) != len(header):
            raise InputError(f"{p}: line {line}: expected {len(header)} columns, got {len(row)}")
        rows.append(number_row(row, str(p), line, header))
        lines.append(line)
    if header is None:
        raise InputError(f"{p}: empty file (expected a header row {', '.join(_header(n, False))}, …)")
    if not rows:
        raise InputError(f"{p}: no measurement rows after the header (line {header_line})")
    data = np.array(rows)
    q = data[:, :n]
    pos = data[:, n:n + 3]
    if qlim is not None:
        for j in range(n):
            lo, hi = qlim[j]
            out = np.flatnonzero((q[:, j] < lo) | (q[:, j] > hi))
            if out.size:
                warnings.warn(f"{p}: column 'q{j + 1}': {out.size} value(s) outside the model's limits "
                              f"[{lo:.4g}, {hi:.4g}] (first at line {lines[out[0]]}); calibrating with them anyway",
                              RobokitWarning, stacklevel=2)
    if len(header) == n + 3:
        return q, pos
    quats = data[:, n + 3:]
    norms = np.linalg.norm(quats, axis=1)
    bad = np.flatnonzero(np.abs(norms - 1.0) > QUATERNION_TOL)
    if bad.size:
        k = int(bad[0])
        raise InputError(f"{p}: line {lines[k]}, columns 'qw'..'qz': quaternion norm {norms[k]:.9g} is not 1 "
                         f"within {QUATERNION_TOL:g}")
    T = np.tile(np.eye(4), (len(rows), 1, 1))
    for k in range(len(rows)):
        T[k, :3, :3] = matrix_from_quaternion(quats[k] / norms[k])
    T[:, :3, 3] = pos
    return q, T


def write_calibration_csv(path: str | os.PathLike[str], q: np.ndarray, measured: np.ndarray) -> Path:
    """Write joint values and measured poses/positions as a calibration CSV (atomically).

    Parameters
    ----------
    path : str or PathLike
        The file to write.
    q : ndarray, shape (K, n)
        Joint values.
    measured : ndarray, shape (K, 4, 4) or (K, 3)
        Tool poses or positions in the base frame.

    Returns
    -------
    Path

    Examples
    --------
    >>> import numpy as np, pathlib, tempfile
    >>> from robokit.calibration import write_calibration_csv
    >>> p = write_calibration_csv(pathlib.Path(tempfile.mkdtemp()) / "d.csv", np.zeros((1, 2)), np.ones((1, 3)))
    >>> p.read_text().splitlines()[0]
    'q1,q2,x,y,z'
    """
    from robokit._io import atomic_write
    from robokit.spatial.quaternion import quaternion_from_matrix

    q = np.asarray(q, dtype=float)
    m = np.asarray(measured, dtype=float)
    n = q.shape[1]
    poses = m.ndim == 3
    out = [",".join(_header(n, poses))]
    for k in range(q.shape[0]):
        vals = list(q[k]) + (list(m[k, :3, 3]) + list(quaternion_from_matrix(m[k, :3, :3])) if poses else list(m[k]))
        out.append(",".join(repr(float(v)) for v in vals))
    return atomic_write(path, "\n".join(out) + "\n")
