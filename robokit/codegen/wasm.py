r"""The robot's generated C (``robokit codegen``) compiled to a small WebAssembly module.

The teach page computes its tool pose, Jacobian and closed-form IK with the *same* C that
goes to the controller board (:func:`robokit.codegen.generate_c`), compiled here with the
Zig toolchain from PyPI (``ziglang``, in the ``viz`` extra) for ``wasm32-wasi`` as a
*reactor* (no ``main``). The math functions (``sin``, ``atan2``, ``cbrt`` …) come from the
compiler's libm (wasi-libc, i.e. musl's); the module imports nothing (no WASI system call
is linked in), so a browser or Node instantiates it with an empty import object.

Besides ``NAME_fk``, ``NAME_joint_poses``, ``NAME_jacobian``, ``NAME_gravity`` and ``NAME_ik_ex`` the
module exports a few robot-independent entry points (a small C file written next to the generated
one), working on static buffers in the module's memory:

* ``rk_n()``, ``rk_has_ik()``, ``rk_max_solutions()``, ``rk_label_count()``,
  ``rk_label(i)`` (address of a NUL-terminated label, ``ik_analytic``'s wording);
* ``rk_q()``, ``rk_T()``, ``rk_P()``, ``rk_J()``, ``rk_tau()``, ``rk_sol()``, ``rk_info()``: addresses
  of the buffers (doubles; ``rk_info`` ints);
* ``rk_fk()``: ``T ← NAME_fk(q)``; ``rk_joint_poses()``: ``P ← NAME_joint_poses(q)`` (n row-major
  4×4: joint k's frame pose, Pinocchio's ``oMi[k]``); ``rk_jacobian()``: ``J ← NAME_jacobian(q)``
  (6×n, row-major);
  ``rk_gravity()``: ``tau ← NAME_gravity(q)``; ``rk_ik(wrist_ref)``: every closed-form solution
  of ``T`` into ``sol`` (one row of n per solution), ``info`` 4 ints per solution (label
  index, repeat number, within limits, degenerate; see ``NAME_ik_ex``), returns the count;
  ``rk_dls(lambda, iters, tol)``: damped-least-squares steps ``dq = Jᵀ(JJᵀ + λ²I)⁻¹e`` from ``q``
  toward ``T`` (any arm, redundant ones included: the step has no null-space part), ``q``
  updated in place; returns the steps taken, −1 if the pose error (rad and m together) is
  still above ``tol``.

``robokit/viz/teach_wasm.js`` is the JavaScript side (the teach page's and Node's); ``robokit
teach`` compiles the module and :func:`robokit.viz.teach.teach_html` embeds it.
"""
from __future__ import annotations

import base64
import os
import subprocess
import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

from robokit._optional import require
from robokit._progress import Slow

if TYPE_CHECKING:
    from robokit.codegen.generate import CSource

__all__ = ["WasmModule", "wasm_module", "compile_wasm", "zig_path"]

#: Flags of every compile: C99 as ``robokit codegen`` writes it, optimised for size (-Os: a fifth
#: smaller than -O2, see benchmarks/teach_wasm.py for the speed), stripped, a reactor.
WASM_FLAGS = ("--target=wasm32-wasi", "-std=c99", "-Os", "-s", "-mexec-model=reactor")

#: Bytes of shadow stack the module gets (the general-6R solver's eliminant needs a few kB).
STACK_BYTES = 256 * 1024


@dataclass(frozen=True)
class WasmModule:
    """A robot's generated C compiled to WebAssembly.

    Attributes
    ----------
    name : str
        The C prefix NAME.
    n : int
        Number of joints.
    has_ik : bool
        Whether the module has the closed-form IK (``rk_ik``).
    wasm : bytes
        The module (``\\0asm`` …).

    Examples
    --------
    >>> m = wasm_module(rk.load("puma560"))
    >>> m.wasm[:4], m.has_ik
    (b'\\x00asm', True)
    """

    name: str
    n: int
    has_ik: bool
    wasm: bytes

    def base64(self) -> str:
        """The module as base64 text (what the teach page embeds).

        Returns
        -------
        str
            ASCII base64 of :attr:`wasm`.

        Examples
        --------
        >>> WasmModule("x", 1, False, b"\\0asm").base64()
        'AGFzbQ=='
        """
        return base64.b64encode(self.wasm).decode("ascii")


def zig_path() -> Path:
    """The ``zig`` executable of the ``ziglang`` package (the ``viz`` extra).

    Returns
    -------
    pathlib.Path
        Path of the ``zig`` binary shipped in the wheel.

    Raises
    ------
    robokit.errors.MissingExtraError
        When ``ziglang`` is not installed (one line naming the extra).

    Examples
    --------
    >>> zig_path().name
    'zig'
    """
    zig = require("ziglang", "compiling the teach page's WebAssembly")
    folder = Path(zig.__file__).parent
    exe = folder / ("zig.exe" if os.name == "nt" else "zig")
    return exe


def _glue(P: str, has_ik: bool) -> str:
    """The robot-independent entry points (see the module docstring), over NAME's functions."""
    ik = f"""
static double rk_sol_buf[{P}_MAX_SOLUTIONS * {P}_N];
static int rk_info_buf[4 * {P}_MAX_SOLUTIONS];
double *rk_sol(void) {{ return rk_sol_buf; }}
int *rk_info(void) {{ return rk_info_buf; }}
int rk_has_ik(void) {{ return 1; }}
int rk_max_solutions(void) {{ return {P}_MAX_SOLUTIONS; }}
int rk_label_count(void) {{ return {P}_IK_LABEL_COUNT; }}
const char *rk_label(int i) {{ return (i >= 0 && i < {P}_IK_LABEL_COUNT) ? {P}_ik_label_names[i] : ""; }}
int rk_ik(double wrist_ref) {{ return {P}_ik_ex(rk_T_buf, wrist_ref, rk_sol_buf, rk_info_buf); }}
""" if has_ik else """
double *rk_sol(void) { return 0; }
int *rk_info(void) { return 0; }
int rk_has_ik(void) { return 0; }
int rk_max_solutions(void) { return 0; }
int rk_label_count(void) { return 0; }
const char *rk_label(int i) { (void)i; return ""; }
int rk_ik(double wrist_ref) { (void)wrist_ref; return -1; }
"""
    return f"""/* robokit teach page: robot-independent entry points over {P}.h (generated) */
#include <math.h>
#include "{P}.h"
static double rk_q_buf[{P}_N];
static double rk_T_buf[16];
static double rk_J_buf[6 * {P}_N];
static double rk_tau_buf[{P}_N];
static double rk_P_buf[16 * {P}_N];
int rk_n(void) {{ return {P}_N; }}
double *rk_P(void) {{ return rk_P_buf; }}
void rk_joint_poses(void) {{ {P}_joint_poses(rk_q_buf, rk_P_buf); }}
double *rk_q(void) {{ return rk_q_buf; }}
double *rk_T(void) {{ return rk_T_buf; }}
double *rk_J(void) {{ return rk_J_buf; }}
double *rk_tau(void) {{ return rk_tau_buf; }}
void rk_fk(void) {{ {P}_fk(rk_q_buf, rk_T_buf); }}
void rk_jacobian(void) {{ {P}_jacobian(rk_q_buf, rk_J_buf); }}
void rk_gravity(void) {{ {P}_gravity(rk_q_buf, rk_tau_buf); }}
{_DLS.replace("NAME", P)}
{ik}"""


#: Damped least squares toward the pose in rk_T from the joint values in rk_q (written back):
#: the course's resolved-rate rule dq = Jᵀ (J Jᵀ + λ² I)⁻¹ e, e = (ω, v) the rotation vector of
#: R_T R(q)ᵀ and p_T − p(q) (base axes, as the Jacobian's rows), so the step has no null-space
#: part. Returns the iterations used, or −1 if |e| is still above ``tol`` after ``iters``.
_DLS = r"""
static void rk_rotvec(const double A[16], const double B[16], double w[3])
{  /* rotation vector of R = R_A R_B^T */
    double R[9], c, th, s, k;
    int i, j;
    for (i = 0; i < 3; i++)
        for (j = 0; j < 3; j++)
            R[3 * i + j] = A[4 * i] * B[4 * j] + A[4 * i + 1] * B[4 * j + 1] + A[4 * i + 2] * B[4 * j + 2];
    c = 0.5 * (R[0] + R[4] + R[8] - 1.0);
    c = c > 1.0 ? 1.0 : (c < -1.0 ? -1.0 : c);
    th = acos(c);
    s = sin(th);
    w[0] = R[7] - R[5]; w[1] = R[2] - R[6]; w[2] = R[3] - R[1];
    if (s > 1e-6) {
        k = 0.5 * th / s;
    } else if (th < 1.0) {
        k = 0.5 + th * th / 12.0;  /* th / (2 sin th) near 0 */
    } else {  /* near pi: the axis from the diagonal, its sign from the antisymmetric part */
        double d[3] = {R[0], R[4], R[8]}, a[3];
        int m = (d[1] > d[0]) ? ((d[2] > d[1]) ? 2 : 1) : ((d[2] > d[0]) ? 2 : 0);
        a[m] = sqrt(0.5 * (d[m] + 1.0));
        a[(m + 1) % 3] = (R[3 * m + (m + 1) % 3] + R[3 * ((m + 1) % 3) + m]) / (4.0 * a[m]);
        a[(m + 2) % 3] = (R[3 * m + (m + 2) % 3] + R[3 * ((m + 2) % 3) + m]) / (4.0 * a[m]);
        if (a[0] * w[0] + a[1] * w[1] + a[2] * w[2] < 0.0) { a[0] = -a[0]; a[1] = -a[1]; a[2] = -a[2]; }
        w[0] = th * a[0]; w[1] = th * a[1]; w[2] = th * a[2];
        return;
    }
    w[0] *= k; w[1] *= k; w[2] *= k;
}

int rk_dls(double lambda, int iters, double tol)
{
    double Tq[16], J[6 * NAME_N], A[36], e[6], y[6];
    int it, i, j, k;
    for (it = 0; it <= iters; it++) {
        NAME_fk(rk_q_buf, Tq);
        rk_rotvec(rk_T_buf, Tq, e);
        e[3] = rk_T_buf[3] - Tq[3]; e[4] = rk_T_buf[7] - Tq[7]; e[5] = rk_T_buf[11] - Tq[11];
        if (sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3] + e[4] * e[4] + e[5] * e[5]) <= tol)
            return it;
        if (it == iters)
            break;
        NAME_jacobian(rk_q_buf, J);
        for (i = 0; i < 6; i++)
            for (j = 0; j < 6; j++) {
                double sum = (i == j) ? lambda * lambda : 0.0;
                for (k = 0; k < NAME_N; k++)
                    sum += J[i * NAME_N + k] * J[j * NAME_N + k];
                A[6 * i + j] = sum;
            }
        for (i = 0; i < 6; i++) {  /* Cholesky A = L L^T in place (A is symmetric positive definite) */
            for (j = 0; j <= i; j++) {
                double sum = A[6 * i + j];
                for (k = 0; k < j; k++)
                    sum -= A[6 * i + k] * A[6 * j + k];
                if (i == j) {
                    if (sum <= 0.0)
                        return -1;
                    A[6 * i + i] = sqrt(sum);
                } else {
                    A[6 * i + j] = sum / A[6 * j + j];
                }
            }
        }
        for (i = 0; i < 6; i++) {  /* L z = e, then L^T y = z */
            double sum = e[i];
            for (k = 0; k < i; k++)
                sum -= A[6 * i + k] * y[k];
            y[i] = sum / A[6 * i + i];
        }
        for (i = 5; i >= 0; i--) {
            double sum = y[i];
            for (k = i + 1; k < 6; k++)
                sum -= A[6 * k + i] * y[k];
            y[i] = sum / A[6 * i + i];
        }
        for (k = 0; k < NAME_N; k++) {
            double dq = 0.0;
            for (i = 0; i < 6; i++)
                dq += J[i * NAME_N + k] * y[i];
            rk_q_buf[k] += dq;
        }
    }
    return -1;
}
"""

_GLUE_EXPORTS = ("rk_n", "rk_q", "rk_T", "rk_P", "rk_J", "rk_tau", "rk_sol", "rk_info", "rk_has_ik",
                 "rk_max_solutions", "rk_label_count", "rk_label", "rk_fk", "rk_joint_poses", "rk_jacobian",
                 "rk_gravity", "rk_ik", "rk_dls")


def compile_wasm(src: CSource, n: int) -> WasmModule:
    """Compile generated C to a WebAssembly module with the ``ziglang`` toolchain.

    Parameters
    ----------
    src : robokit.codegen.CSource
        From :func:`robokit.codegen.generate_c` (double precision).
    n : int
        The robot's number of joints.

    Returns
    -------
    WasmModule

    Raises
    ------
    RuntimeError
        If the compiler fails (its message).

    Examples
    --------
    >>> from robokit.codegen.generate import generate_c
    >>> m = compile_wasm(generate_c(rk.load("twolink")), 2)
    >>> m.wasm[:4], m.has_ik
    (b'\\x00asm', True)
    """
    from robokit.codegen.generate import write_c

    zig = zig_path()
    P = src.name
    exports = [f"{P}_fk", f"{P}_joint_poses", f"{P}_jacobian", f"{P}_gravity"] + ([f"{P}_ik_ex"] if src.has_ik else [])
    exports += list(_GLUE_EXPORTS)
    with tempfile.TemporaryDirectory(prefix="robokit-wasm-") as tmp:
        folder = Path(tmp)
        _, c_path = write_c(src, folder)
        glue = folder / "rk_glue.c"
        glue.write_text(_glue(P, src.has_ik), encoding="utf-8")
        out = folder / f"{P}.wasm"
        cmd = [str(zig), "cc", *WASM_FLAGS, f"-Wl,-z,stack-size={STACK_BYTES}",
               *(f"-Wl,--export={e}" for e in exports), "-o", str(out), str(c_path), str(glue)]
        with Slow(f"robokit: compiling {P}.c to WebAssembly (the first time on a machine, zig also builds its "
                  "libc for WebAssembly, once) ...", after=2.0, done=f"robokit: {P}.wasm compiled",
                  still="still compiling"):
            res = subprocess.run(cmd, capture_output=True, text=True, cwd=tmp)
        if res.returncode != 0:
            raise RuntimeError(f"compiling {P}.c to WebAssembly failed ({' '.join(cmd)}):\n{res.stderr}")
        data = out.read_bytes()
    return WasmModule(P, n, src.has_ik, data)


def wasm_module(robot: Any, name: str | None = None) -> WasmModule:
    """The robot's FK, Jacobian, gravity and closed-form IK as a WebAssembly module.

    Generates the robot's C (:func:`robokit.codegen.generate_c`, double precision) and
    compiles it (:func:`compile_wasm`). The first compile on a machine builds the compiler's
    libc for WebAssembly once (a minute or two; Zig caches it).

    Parameters
    ----------
    robot : robokit.Robot
        Any robot ``robokit.load`` returns.
    name : str, optional
        The C prefix (default :func:`robokit.codegen.c_name` of the robot's name).

    Returns
    -------
    WasmModule

    Raises
    ------
    robokit.errors.MissingExtraError
        Without the ``viz`` extra's ``ziglang``.
    RuntimeError
        If the compiler fails.

    Examples
    --------
    >>> m = wasm_module(rk.load("ur5"))
    >>> m.name, m.n, m.has_ik
    ('ur5', 6, True)
    """
    from robokit.codegen.generate import generate_c

    return compile_wasm(generate_c(robot, name=name), int(robot.n))
