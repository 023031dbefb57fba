r"""Symbolic derivations from a DH table, as the lectures write them (sympy).

From a DH table whose entries are numbers, sympy symbols or any mix, this module derives

* the link transforms ``ⁱ⁻¹Tᵢ`` and the forward kinematics ``⁰Tₙ`` (Lecture 4), simplified,
  with the lectures' shorthand ``cᵢ = cos θᵢ``, ``s₁₂ = sin(θ₁ + θ₂)`` for display;
* the geometric Jacobian (Lecture 6), angular rows first, in the base frame or the tool frame;
* for arms with point masses or symbolic inertias, the Lagrangian dynamics (Lecture 7)
  ``τ = M(q) q̈ + C(q, q̇) q̇ + G(q)``, with ``V(q, q̇) = C(q, q̇) q̇``, C from the Christoffel
  symbols (so that Ṁ − 2C is skew-symmetric), and the configuration-space form
  ``τ = M q̈ + B(q)[q̇q̇] + C_cf(q)[q̇²] + G`` of Lecture 7;

and turns any of them into LaTeX or into a numeric function (``sympy.lambdify``).

Conventions: standard DH ``ⁱ⁻¹Tᵢ = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ)``; modified (Craig)
``ⁱ⁻¹Tᵢ = Rx(αᵢ₋₁) Tx(aᵢ₋₁) Rz(θᵢ) Tz(dᵢ)`` with row i holding ``aᵢ₋₁, αᵢ₋₁, dᵢ, θᵢ``.
A revolute joint adds ``qᵢ`` to θᵢ, a prismatic one adds it to dᵢ. Link i's mass, centre of
mass and inertia (about the centre of mass) are given in DH frame {i}, as in the YAML format.

Time limits (measured on the project's 2-core machine): the planar 2-link and RRR arms,
FK, Jacobians and dynamics fully simplified, take about a second each; a spatial 3-joint
arm with numeric inertias takes about 15 s fully simplified and under 1 s with
``simplify=False``; a 6-joint arm (PUMA 560 with symbolic lengths) gives FK in about 10 s
and the base-frame Jacobian in about 5 s (trigsimp only, by default). The symbolic
dynamics of more than 3 joints are refused with a clear message unless
``allow_slow=True``.

Example::

    >>> from robokit.symbolic import SymbolicArm
    >>> import sympy as sp
    >>> l1, l2 = sp.symbols("l1 l2", positive=True)
    >>> arm = SymbolicArm([(l1, 0, 0, 0), (l2, 0, 0, 0)])
    >>> arm.fk()[0, 3]
    l1*cos(q1) + l2*cos(q1 + q2)
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike
from robokit.errors import InputError
from robokit._arrays import check_reference
from robokit.frames import DEFAULT_FRAME, Frame

from robokit._optional import require

if TYPE_CHECKING:
    import sympy as sp

    from robokit.description.dh import DHTable
else:
    sp = require("sympy", "robokit.symbolic")

__all__ = ["SymbolicArm", "SymbolicDynamics", "shorthand", "to_latex", "MAX_SYMBOLIC_DYNAMICS_JOINTS"]

#: Joint count above which ``SymbolicArm.dynamics`` refuses unless ``allow_slow=True``.
MAX_SYMBOLIC_DYNAMICS_JOINTS = 3


def _rot_x(a: Any) -> sp.Matrix:
    c, s = sp.cos(a), sp.sin(a)
    return sp.Matrix([[1, 0, 0, 0], [0, c, -s, 0], [0, s, c, 0], [0, 0, 0, 1]])


def _rot_z(a: Any) -> sp.Matrix:
    c, s = sp.cos(a), sp.sin(a)
    return sp.Matrix([[c, -s, 0, 0], [s, c, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]])


def _trans(x: Any, y: Any, z: Any) -> sp.Matrix:
    return sp.Matrix([[1, 0, 0, x], [0, 1, 0, y], [0, 0, 1, z], [0, 0, 0, 1]])


def _sym(x: Any) -> Any:
    """Numbers become exact where they are (ints, simple floats kept as Float); symbols pass."""
    if isinstance(x, sp.Basic):
        return x
    if isinstance(x, (int, np.integer)):
        return sp.Integer(int(x))
    return sp.Float(float(x), 17) if float(x) != 0.0 else sp.Integer(0)


#: Simplifying more entries than this shows a progress bar on stderr (six-joint forms take 10–100 s).
_PROGRESS_ENTRIES = 12


def _simplify_matrix(m: sp.Matrix, level: str = "full") -> sp.Matrix:
    """``full``: simplify + trigsimp per entry; ``trig``: trigsimp only (cheaper); ``none``.

    Long simplifications (many entries with large expressions) show a transient progress bar
    on stderr, so a notebook or a terminal is not silent for tens of seconds.
    """
    if level == "none":
        return m
    if level == "trig":
        f = lambda e: sp.trigsimp(e) if e.free_symbols else e  # noqa: E731
    else:
        f = lambda e: sp.trigsimp(sp.expand_trig(sp.simplify(e))) if e.free_symbols else e  # noqa: E731
    work = [k for k, e in enumerate(m) if e.free_symbols]
    heavy = len(work) > _PROGRESS_ENTRIES and sum(sp.count_ops(m[k]) for k in work) > 400
    if not heavy:
        return m.applyfunc(f)
    from rich.console import Console
    from rich.progress import Progress

    out = m.copy()
    with Progress(console=Console(stderr=True), transient=True) as bar:
        task = bar.add_task(f"simplifying a {m.rows}×{m.cols} symbolic matrix", total=len(work))
        for k in work:
            out[k] = f(m[k])
            bar.advance(task)
    return out


@dataclass
class SymbolicDynamics:
    """The Lagrangian dynamics ``τ = M q̈ + V + G`` of a :class:`SymbolicArm` (Lecture 7).

    Made by :meth:`SymbolicArm.dynamics`; every entry is a sympy expression in the joint symbols
    ``q1..qn``, ``dq1..dqn`` and the arm's own symbols (SI units once numbers are substituted).

    Attributes
    ----------
    q, dq : sympy.Matrix, (n, 1)
        The joint variables and rates.
    M : sympy.Matrix, (n, n)
        Mass matrix (symmetric positive definite).
    C : sympy.Matrix, (n, n)
        Coriolis matrix from the Christoffel symbols, so that Ṁ − 2C is skew-symmetric.
    V : sympy.Matrix, (n, 1)
        Velocity terms ``C q̇``.
    G : sympy.Matrix, (n, 1)
        Gravity torques.
    B : sympy.Matrix, (n, n(n−1)/2)
        Coriolis coefficients of the configuration-space form
    ``τ = M q̈ + B [q̇ᵢq̇ⱼ]_{i<j} + Ccf [q̇ᵢ²] + G``.
    Ccf : sympy.Matrix, (n, n)
        Centrifugal coefficients of that form.
    """

    q: sp.Matrix
    dq: sp.Matrix
    M: sp.Matrix
    C: sp.Matrix
    V: sp.Matrix
    G: sp.Matrix
    B: sp.Matrix
    Ccf: sp.Matrix

    def tau(self, ddq: sp.Matrix | None = None) -> sp.Matrix:
        """The joint torques ``M q̈ + V + G``.

        Parameters
        ----------
        ddq : sympy.Matrix, (n, 1), optional
            The joint accelerations (default the symbols ``ddq1..ddqn``).

        Returns
        -------
        sympy.Matrix, (n, 1)
            τ (N·m for revolute, N for prismatic joints once numbers are substituted).

        Examples
        --------
        A pendulum: a point mass m at the end of a link of length l, gravity −g along y:

        >>> import sympy as sp
        >>> l, m, g = sp.symbols("l m g", positive=True)
        >>> dyn = SymbolicArm([(l, 0, 0, 0)]).dynamics([m], [(0, 0, 0)], gravity=(0, -g, 0))
        >>> dyn.tau()
        Matrix([[ddq1*l**2*m + g*l*m*cos(q1)]])
        """
        if ddq is None:
            ddq = sp.Matrix(sp.symbols(f"ddq1:{len(self.q) + 1}", real=True))
        return self.M * ddq + self.V + self.G


class SymbolicArm:
    """A serial arm given by a DH table with numeric and/or symbolic entries.

    Parameters
    ----------
    rows : sequence of (a, alpha, d, theta)
        One row per joint, in the table's convention; entries are numbers or sympy
        expressions (angles in radians). θ (revolute) or d (prismatic) is the offset to
        which the joint variable ``qᵢ`` is added.
    joint_types : str or sequence, default all "R"
        "R" (revolute) or "P" (prismatic) per joint.
    convention : "standard" or "modified"
    base, tool : 4×4 (numbers or sympy), optional
        Frame {0} in the base, and the tool in frame {N}.

    Examples
    --------
    The planar two-link arm with symbolic lengths (rows ``(a, α, d, θ)``):

    >>> import sympy as sp
    >>> l1, l2 = sp.symbols("l1 l2", positive=True)
    >>> arm = SymbolicArm([(l1, 0, 0, 0), (l2, 0, 0, 0)])
    >>> arm
    SymbolicArm(2 joints RR, standard DH, rows=[(l1, 0, 0, 0), (l2, 0, 0, 0)])
    """

    def __init__(self, rows: Sequence[Sequence], joint_types: Sequence[str] | str | None = None,
                 convention: str = "standard", base: Any = None, tool: Any = None) -> None:
        rows = [tuple(r) for r in rows]
        if not rows:
            raise InputError("rows: expected at least one DH row")
        for i, r in enumerate(rows):
            if len(r) != 4:
                raise InputError(f"rows[{i}]: expected (a, alpha, d, theta), got {len(r)} entries")
        n = len(rows)
        jt = ["R"] * n if joint_types is None else list(joint_types)
        if len(jt) != n or any(t not in ("R", "P") for t in jt):
            raise InputError(f"joint_types: expected {n} entries of 'R' or 'P', got {joint_types!r}")
        if convention not in ("standard", "modified"):
            raise InputError(f"convention: expected 'standard' or 'modified', got {convention!r}")
        self.n = n
        self.convention = convention
        self.joint_types = tuple(jt)
        self.rows = [tuple(_sym(x) for x in r) for r in rows]
        self.q = sp.Matrix(sp.symbols(f"q1:{n + 1}", real=True))
        self.dq = sp.Matrix(sp.symbols(f"dq1:{n + 1}", real=True))
        self.base = sp.eye(4) if base is None else sp.Matrix(base).applyfunc(_sym)
        self.tool = sp.eye(4) if tool is None else sp.Matrix(tool).applyfunc(_sym)
        self._frames_cache: list[sp.Matrix] | None = None

    def __repr__(self) -> str:
        joints = "".join(self.joint_types)
        return f"SymbolicArm({self.n} joints {joints}, {self.convention} DH, rows={self.rows})"

    @classmethod
    def from_dh_table(cls, table: DHTable, symbolic_lengths: bool = False) -> "SymbolicArm":
        """Build from a :class:`robokit.DHTable`.

        Angles are taken as exact multiples of π/2 where they are, so the forms stay readable.

        Parameters
        ----------
        table : DHTable
            The table (numbers), with its convention, joint types, base and tool.
        symbolic_lengths : bool, optional
            Reserved; the lengths are the table's numbers.

        Returns
        -------
        SymbolicArm
            The same arm with exact entries.

        Examples
        --------
        >>> SymbolicArm.from_dh_table(rk.load("twolink").dh).n
        2
        """
        def nice_angle(x: float) -> Any:
            k = float(x) / (np.pi / 2)
            if abs(k - round(k)) < 1e-12:
                return sp.Integer(int(round(k))) * sp.pi / 2
            return _sym(x)

        rows = [(_sym(l.a), nice_angle(l.alpha), _sym(l.d), nice_angle(l.theta)) for l in table.links]
        return cls(rows, [l.joint for l in table.links], table.convention,
                   base=np.asarray(table.base), tool=np.asarray(table.tool))

    def _level(self, simplify: bool | str, heavy: bool = False) -> str:
        """Resolve ``simplify`` (True / False / "auto") to a simplification level.

        "auto": full simplification up to ``MAX_SYMBOLIC_DYNAMICS_JOINTS`` joints; beyond,
        trigsimp only — and none for ``heavy`` results (the tool-frame Jacobian), whose
        simplification takes minutes for a 6-joint arm.
        """
        if simplify is True:
            return "full"
        if simplify is False:
            return "none"
        if simplify != "auto":
            raise InputError(f"simplify: expected True, False or 'auto', got {simplify!r}")
        if self.n <= MAX_SYMBOLIC_DYNAMICS_JOINTS:
            return "full"
        return "none" if heavy else "trig"

    # ---------------------------------------------------------------- kinematics
    def link_transform(self, i: int) -> sp.Matrix:
        """The link transform ``ⁱ⁻¹Tᵢ`` with the joint variable ``qᵢ`` added to θ (or d).

        Parameters
        ----------
        i : int
            The joint, 1..n.

        Returns
        -------
        sympy.Matrix, (4, 4)
            ``Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ)`` (standard) or ``Rx(αᵢ₋₁) Tx(aᵢ₋₁) Rz(θᵢ) Tz(dᵢ)`` (modified).

        Examples
        --------
        >>> arm.link_transform(1)[:2, 3].T
        Matrix([[l1*cos(q1), l1*sin(q1)]])
        """
        if not 1 <= i <= self.n:
            raise InputError(f"i: expected 1..{self.n}, got {i}")
        a, alpha, d, theta = self.rows[i - 1]
        qi = self.q[i - 1]
        if self.joint_types[i - 1] == "R":
            theta = theta + qi
        else:
            d = d + qi
        if self.convention == "standard":
            return _rot_z(theta) * _trans(0, 0, d) * _trans(a, 0, 0) * _rot_x(alpha)
        return _rot_x(alpha) * _trans(a, 0, 0) * _rot_z(theta) * _trans(0, 0, d)

    def link_transforms(self, simplify: bool = True) -> list[sp.Matrix]:
        """All link transforms ``ⁱ⁻¹Tᵢ``, i = 1..n.

        Parameters
        ----------
        simplify : bool, optional
            Simplify each one (default True).

        Returns
        -------
        list of sympy.Matrix, (4, 4)
            One per joint.

        Examples
        --------
        >>> [T[0, 3] for T in arm.link_transforms()]
        [l1*cos(q1), l2*cos(q2)]
        """
        level = "full" if simplify else "none"
        return [_simplify_matrix(self.link_transform(i), level) for i in range(1, self.n + 1)]

    def _frames(self) -> list[sp.Matrix]:
        """Poses of DH frames {0..n} in the base (unsimplified products)."""
        if self._frames_cache is None:
            frames = [self.base]
            for i in range(1, self.n + 1):
                frames.append(frames[-1] * self.link_transform(i))
            self._frames_cache = frames
        return self._frames_cache

    def fk(self, simplify: bool | str = "auto", tool: bool = True) -> sp.Matrix:
        """Forward kinematics ``⁰Tₙ`` (with the base, and the tool unless ``tool=False``).

        Parameters
        ----------
        simplify : bool or "auto", optional
            True, False or "auto" (full up to 3 joints, trigsimp beyond: ~10 s for a 6-joint arm
            with symbolic lengths).
        tool : bool, optional
            Include the tool transform (default True).

        Returns
        -------
        sympy.Matrix, (4, 4)
            The pose of the tool (or frame {n}) in the base, trigonometrically simplified.

        Examples
        --------
        >>> arm.fk()[:2, 3].T
        Matrix([[l1*cos(q1) + l2*cos(q1 + q2), l1*sin(q1) + l2*sin(q1 + q2)]])
        """
        T = self._frames()[-1] * (self.tool if tool else sp.eye(4))
        return _simplify_matrix(T, self._level(simplify))

    def _joint_axes(self) -> list[tuple[sp.Matrix, sp.Matrix]]:
        """(z, p) of every joint axis in the base frame: z the unit axis, p a point on it."""
        frames = self._frames()
        axes = []
        for i in range(1, self.n + 1):
            # standard: joint i moves about z of frame {i-1}; modified: about z of frame {i}.
            F = frames[i - 1] if self.convention == "standard" else frames[i]
            axes.append((F[:3, 2], F[:3, 3]))
        return axes

    def jacobian(self, reference: Frame | str = DEFAULT_FRAME, simplify: bool | str = "auto") -> sp.Matrix:
        """The 6×n Jacobian of the tool, angular rows first (Lecture 6).

        Parameters
        ----------
        reference : Frame or str, default Frame.LOCAL_WORLD_ALIGNED
            A :class:`robokit.Frame` (the *Conventions* page): ``LOCAL_WORLD_ALIGNED`` (the lecture's
            ⁰J, formerly "base") — twist (ω, v) of the tool origin in base coordinates, columns
            ``[zᵢ; zᵢ × (p_tool − pᵢ)]`` (revolute) or ``[0; zᵢ]`` (prismatic); ``LOCAL`` (formerly
            "tool"/"body") — the same twist in tool-frame axes (``blockdiag(Rᵀ, Rᵀ) J_base``, the body
            Jacobian); ``WORLD`` (formerly "space") — the space Jacobian, columns ``[zᵢ; pᵢ × zᵢ]``.
        simplify : bool or "auto"
            True, False or "auto" (full up to 3 joints; beyond, trigsimp for the base frame and no
            simplification for the tool frame, which would take minutes).

        Returns
        -------
        sympy.Matrix, (6, n)
            Rows ω (rad/s per unit joint rate) then v (m/s).

        Examples
        --------
        The lecture's v rows of the planar arm:

        >>> arm.jacobian()[3:5, :]
        Matrix([
        [-l1*sin(q1) - l2*sin(q1 + q2), -l2*sin(q1 + q2)],
        [ l1*cos(q1) + l2*cos(q1 + q2),  l2*cos(q1 + q2)]])
        """
        ref = check_reference(reference)
        cols = []
        if ref == "world":  # space Jacobian: v of the point at the base origin, columns [zᵢ; pᵢ × zᵢ]
            for (z, p), jt in zip(self._joint_axes(), self.joint_types):
                rev = jt == "R"
                cols.append(sp.Matrix.vstack(z, p.cross(z)) if rev else sp.Matrix.vstack(sp.zeros(3, 1), z))
        elif ref == "local_world_aligned":
            p_e = (self._frames()[-1] * self.tool)[:3, 3]
            for (z, p), jt in zip(self._joint_axes(), self.joint_types):
                if jt == "R":
                    cols.append(sp.Matrix.vstack(z, z.cross(p_e - p)))
                else:
                    cols.append(sp.Matrix.vstack(sp.zeros(3, 1), z))
        else:
            # Body Jacobian from the transforms *after* each joint axis (shorter expressions):
            # with T_ae the tool pose in the axis frame, z_tool = R_aeᵀ ẑ and v = z_tool × (R_aeᵀ p_ae).
            n = self.n
            T_after = self.tool
            afters: list[Any] = [None] * n  # every entry is set below
            for i in range(n, 0, -1):
                if self.convention == "modified":
                    afters[i - 1] = T_after  # axis i is z of frame {i}
                T_after = self.link_transform(i) * T_after
                if self.convention == "standard":
                    afters[i - 1] = T_after  # axis i is z of frame {i-1}
            for T_ae, jt in zip(afters, self.joint_types):
                Rt = T_ae[:3, :3].T
                z = Rt[:, 2]
                if jt == "R":
                    cols.append(sp.Matrix.vstack(z, z.cross(Rt * T_ae[:3, 3])))
                else:
                    cols.append(sp.Matrix.vstack(sp.zeros(3, 1), z))
        J = sp.Matrix.hstack(*cols)
        return _simplify_matrix(J, self._level(simplify, heavy=(ref == "local")))

    # ------------------------------------------------------------------ dynamics
    def dynamics(self, masses: Sequence[Any], coms: Sequence[Any], inertias: Sequence[Any] | None = None,
                 gravity: Sequence[Any] = (0, 0, -9.81), allow_slow: bool = False,
                 simplify: bool | str = "auto") -> SymbolicDynamics:
        """Lagrangian dynamics for link masses, centres of mass and inertias (Lecture 7).

        ``M = Σ mᵢ Jᵥᵢᵀ Jᵥᵢ + J_ωᵢᵀ Rᵢ Iᵢ Rᵢᵀ J_ωᵢ``; ``Cₖⱼ = Σᵢ Γᵢⱼₖ q̇ᵢ`` with the Christoffel
        symbols ``Γᵢⱼₖ = ½(∂Mₖⱼ/∂qᵢ + ∂Mₖᵢ/∂qⱼ − ∂Mᵢⱼ/∂qₖ)``; ``G = ∂P/∂q`` with
        ``P = −Σ mᵢ gᵀ p_cᵢ``.

        Parameters
        ----------
        masses : sequence of n numbers or symbols
            Link masses (kg).
        coms : sequence of n 3-vectors
            Centres of mass in DH frame {i} (m).
        inertias : sequence of n 3×3, optional
            About the centre of mass, frame-{i} axes (kg·m²); None for point masses.
        gravity : 3-vector, optional
            The gravity acceleration in the base frame (m/s²; numbers or symbols).
        allow_slow : bool, optional
            Allow more than ``MAX_SYMBOLIC_DYNAMICS_JOINTS`` joints (minutes of simplification).
        simplify : bool or "auto", optional
            As for :meth:`fk`.

        Returns
        -------
        SymbolicDynamics
            ``M``, ``C``, ``V``, ``G``, ``B``, ``Ccf`` and :meth:`SymbolicDynamics.tau`.

        Examples
        --------
        Point masses at the ends of the links (frame {i}'s origin), gravity −g along y:

        >>> m1, m2, g = sp.symbols("m1 m2 g", positive=True)
        >>> dyn = arm.dynamics([m1, m2], [(0, 0, 0), (0, 0, 0)], gravity=(0, -g, 0))
        >>> dyn.G[1], dyn.M[1, 1]
        (g*l2*m2*cos(q1 + q2), l2**2*m2)
        """
        n = self.n
        if n > MAX_SYMBOLIC_DYNAMICS_JOINTS and not allow_slow:
            raise InputError(
                f"dynamics: {n} joints is more than the {MAX_SYMBOLIC_DYNAMICS_JOINTS} that simplify in seconds; "
                "use the numeric dynamics (robokit.dynamics) or pass allow_slow=True"
            )
        if len(masses) != n or len(coms) != n:
            raise InputError(f"masses, coms: expected {n} entries each, got {len(masses)} and {len(coms)}")
        if inertias is not None and len(inertias) != n:
            raise InputError(f"inertias: expected {n} 3×3 entries or None, got {len(inertias)}")
        level = self._level(simplify)
        g = sp.Matrix([_sym(x) for x in gravity])
        frames = self._frames()
        axes = self._joint_axes()
        M = sp.zeros(n, n)
        P = sp.Integer(0)
        for i in range(1, n + 1):
            F = frames[i]
            R = F[:3, :3]
            pc = F[:3, 3] + R * sp.Matrix([_sym(x) for x in coms[i - 1]])
            m = _sym(masses[i - 1])
            Jv = pc.jacobian(self.q)
            M += m * (Jv.T * Jv)
            P += -m * (g.T * pc)[0, 0]
            if inertias is not None:
                I = sp.Matrix(inertias[i - 1]).applyfunc(_sym)
                if I.shape != (3, 3):
                    raise InputError(f"inertias[{i - 1}]: expected a 3×3 matrix, got shape {I.shape}")
                Jw = sp.zeros(3, n)
                for j in range(i):
                    # the moving body of link i turns about the axes of joints 1..i
                    if self.joint_types[j] == "R":
                        Jw[:, j] = axes[j][0]
                M += Jw.T * R * I * R.T * Jw
        M = _simplify_matrix(M, level)
        G = sp.Matrix([sp.diff(P, qk) for qk in self.q])
        G = _simplify_matrix(G, level)
        dM = [M.diff(qi) for qi in self.q]
        # Christoffel symbols Γ[i][j][k] = ½(∂Mkj/∂qi + ∂Mki/∂qj − ∂Mij/∂qk), symmetric in i, j.
        gam = [[[sp.Rational(1, 2) * (dM[i][k, j] + dM[j][k, i] - dM[k][i, j]) for k in range(n)]
                for j in range(n)] for i in range(n)]
        C = sp.zeros(n, n)
        for k in range(n):
            for j in range(n):
                C[k, j] = sum(gam[i][j][k] * self.dq[i] for i in range(n))
        C = _simplify_matrix(C, level)
        # configuration-space form (Lecture 7): V_k = Σ_i Γ_iik q̇_i² + Σ_{i<j} 2Γ_ijk q̇_i q̇_j.
        pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
        B = sp.Matrix(n, len(pairs), lambda k, c: 2 * gam[pairs[c][0]][pairs[c][1]][k])
        Ccf = sp.Matrix(n, n, lambda k, i: gam[i][i][k])
        B = _simplify_matrix(B, level)
        Ccf = _simplify_matrix(Ccf, level)
        dq2 = sp.Matrix([self.dq[i] ** 2 for i in range(n)])
        dqdq = sp.Matrix([self.dq[i] * self.dq[j] for i, j in pairs]) if pairs else sp.zeros(0, 1)
        V = Ccf * dq2 + (B * dqdq if pairs else sp.zeros(n, 1))
        return SymbolicDynamics(self.q, self.dq, M, C, V, G, B, Ccf)

    # -------------------------------------------------------------- conversions
    def lambdify(self, expr: Any, extra_symbols: Sequence[sp.Symbol] = ()) -> Callable[..., np.ndarray]:
        """A numpy function of ``(q, *extra)`` (and ``dq`` if the expression uses it).

        Parameters
        ----------
        expr : sympy expression or matrix
            In the joint symbols (and rates), plus ``extra_symbols``.
        extra_symbols : sequence of sympy.Symbol, optional
            Symbols whose values are passed after q (and dq), in order.

        Returns
        -------
        callable
            ``f(q, [dq,] *extra) -> numpy.ndarray`` of the expression's shape (floats).

        Examples
        --------
        The tool position at q = (0, 90°) for l₁ = 1, l₂ = 0.8:

        >>> p = arm.lambdify(arm.fk()[:2, 3], [l1, l2])
        >>> p([0.0, np.pi / 2], 1.0, 0.8).round(4).ravel().tolist()
        [1.0, 0.8]
        """
        expr = sp.Matrix(expr) if not isinstance(expr, sp.MatrixBase) else expr
        uses_dq = bool(expr.free_symbols & set(self.dq))
        args = [list(self.q)] + ([list(self.dq)] if uses_dq else []) + list(extra_symbols)
        free = expr.free_symbols - set(self.q) - set(self.dq) - set(extra_symbols)
        if free:
            raise InputError(f"expr: symbols {sorted(map(str, free))} have no value; pass them as extra_symbols")
        f = sp.lambdify(args, expr, modules="numpy")

        def numeric(*values: ArrayLike) -> np.ndarray:
            return np.array(f(*values), dtype=float).reshape(expr.shape)

        numeric.__doc__ = f"Numeric form of a symbolic expression; arguments: {', '.join(map(str, ['q'] + (['dq'] if uses_dq else []) + list(extra_symbols)))}"
        return numeric


def shorthand(expr: Any, q: Sequence[sp.Symbol] | None = None) -> Any:
    """Replace ``cos(q1 + q2)`` by the symbol ``c₁₂`` (``c_{12}``), ``sin(q1)`` by ``s₁``, as the lectures write them.

    Parameters
    ----------
    expr : sympy expression or Matrix
        What to rewrite.
    q : sequence of sympy.Symbol, optional
        The joint symbols (default: every symbol named ``q<digits>``).

    Returns
    -------
    sympy expression or Matrix
        A new object with the shorthand symbols ``c_{…}``, ``s_{…}`` (for display, not for computing).

    Examples
    --------
    >>> import sympy as sp
    >>> q1, q2 = sp.symbols("q1 q2")
    >>> shorthand(sp.cos(q1) + sp.sin(q1 + q2))
    c_{1} + s_{12}
    """
    def joint_index(sym: sp.Basic) -> int | None:
        name = str(sym)
        if q is not None:
            return list(q).index(sym) + 1 if sym in q else None
        return int(name[1:]) if name.startswith("q") and name[1:].isdigit() else None

    def rewrite(fn: Any, letter: str) -> tuple[Any, Callable[[sp.Basic], sp.Symbol | None]]:
        def repl(arg: sp.Basic) -> sp.Symbol | None:
            terms = sp.Add.make_args(sp.expand(arg))
            idx = []
            for t in terms:
                if not t.is_Symbol:
                    return None
                k = joint_index(t)
                if k is None:
                    return None
                idx.append(k)
            return sp.Symbol(f"{letter}_{{{''.join(str(k) for k in sorted(idx))}}}")

        return fn, repl

    out = expr
    for fn, letter in ((sp.cos, "c"), (sp.sin, "s")):
        f, repl = rewrite(fn, letter)
        out = out.replace(lambda e: isinstance(e, f) and repl(e.args[0]) is not None, lambda e: repl(e.args[0]))
    return out


def to_latex(expr: Any, use_shorthand: bool = True) -> str:
    """LaTeX of an expression or matrix, with the lectures' cᵢ/sᵢⱼ shorthand by default.

    Parameters
    ----------
    expr : sympy expression or Matrix
        What to typeset.
    use_shorthand : bool
        Apply :func:`shorthand` first.

    Returns
    -------
    str
        The LaTeX source (``sympy.latex``).

    Examples
    --------
    >>> import sympy as sp
    >>> q1, l1 = sp.symbols("q1 l1")
    >>> to_latex(l1 * sp.cos(q1))
    'c_{1} l_{1}'
    """
    return sp.latex(shorthand(expr) if use_shorthand else expr)
