r"""C for the forward kinematics and the geometric Jacobian, written out from the PoE parameters.

The product of exponentials (Lecture 4, Modern Robotics ch. 4),
``T(q) = e^{[S₁]q₁} ⋯ e^{[Sₙ]qₙ} M``, is unrolled joint by joint with the robot's screw
axes ``Slist`` and home pose ``M`` folded in as constants. For a revolute joint with unit
axis ω and ``v = −ω × p`` (Rodrigues): ``R = I + sin q [ω] + (1 − cos q)[ω]²`` and
``p = sin q · v + (1 − cos q) ω × v + (q − sin q)(ω·v) ω``; for a prismatic joint
``R = I``, ``p = v q``.

The Jacobian is the geometric one of the course (Pinocchio's LOCAL_WORLD_ALIGNED), rows
``(ω; v)`` in base axes, v the velocity of the tool origin: with ``T₀,ᵢ₋₁ = (R, p)`` the
product of the first i − 1 exponentials, column i is ``ωᵢ = R ωᵢ⁰``,
``vᵢ = R vᵢ⁰ + ωᵢ × (p_tool − p)`` (revolute) or ``(0, R vᵢ⁰)`` (prismatic).

The joint frames' poses (``NAME_joint_poses``) are the partial products carried to each joint's
own frame: ``T₀,ₖ(q) = e^{[S₁]q₁} ⋯ e^{[Sₖ]qₖ} Hₖ``, ``Hₖ`` the pose of joint k's frame at q = 0 —
Pinocchio's ``data.oMi[k]``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robokit.codegen._c import CWriter, Val, cross, dot, lin, snap, sub

__all__ = ["emit_fk", "emit_jacobian", "emit_joint_poses", "Pose"]


@dataclass
class Pose:
    """A pose ``[R | p]`` whose entries are folded values (a float constant or a C expression).

    Attributes
    ----------
    R : list of 3 lists of 3 values
        Rotation, row-major.
    p : list of 3 values
        Position (m).

    Examples
    --------
    >>> Pose.identity().p
    [0.0, 0.0, 0.0]
    """

    R: list[list[Val]]
    p: list[Val]

    @staticmethod
    def const(T: np.ndarray) -> "Pose":
        """The constant pose of a 4×4 array T (round-off near 0 and ±1 folded, see ``SNAP``).

        Parameters
        ----------
        T : ndarray, shape (4, 4)
            A rigid transform.

        Returns
        -------
        Pose
            Its rotation entries (snapped) and translation, all constants.
        """
        return Pose([[snap(T[i, j]) for j in range(3)] for i in range(3)], [float(T[i, 3]) for i in range(3)])

    @staticmethod
    def identity() -> "Pose":
        """The identity pose (all constants).

        Returns
        -------
        Pose
            Rotation I, translation 0.
        """
        return Pose.const(np.eye(4))


def compose(w: CWriter, A: Pose, B: Pose, name: str) -> Pose:
    """Emit the product of two poses, ``A·B = [R_A R_B | R_A p_B + p_A]``.

    Parameters
    ----------
    w : CWriter
        Where the temporaries are written.
    A, B : Pose
        The factors (constants are folded: a product with a constant pose costs only the
        non-zero terms).
    name : str
        Prefix of the temporaries: entry (r, c) is ``name_rc`` (c = 3 the position).

    Returns
    -------
    Pose
        The product, its entries the temporaries' names (or constants).

    Examples
    --------
    >>> w = CWriter()
    >>> compose(w, Pose.identity(), Pose.identity(), "T").R[0][0]
    1.0
    """
    R: list[list[Val]] = [[0.0] * 3 for _ in range(3)]
    p: list[Val] = [0.0] * 3
    for i in range(3):
        for j in range(3):
            R[i][j] = w.let(f"{name}_{i}{j}", dot(A.R[i], [B.R[0][j], B.R[1][j], B.R[2][j]]))
    for i in range(3):
        p[i] = w.let(f"{name}_{i}3", lin([(1.0, dot(A.R[i], B.p)), (1.0, A.p[i])]))
    return Pose(R, p)


def joint_exp(w: CWriter, S: np.ndarray, kind: str, i: int, qname: str, sign: float = 1.0) -> Pose:
    """Emit the screw motion ``e^{[S]·sign·q}`` of one joint (Lecture 4, Rodrigues' formula).

    Parameters
    ----------
    w : CWriter
        Where the temporaries ``e{i+1}_rc`` are written.
    S : (6,) array
        Unit screw axis ``(ω, v)``; ω = 0 for a prismatic joint.
    kind : {"R", "P"}
        Joint type.
    i : int
        Joint index (0-based); the revolute joint's ``cos q``, ``sin q``, ``1 − cos q`` must
        be bound to ``c{i+1}``, ``s{i+1}``, ``v{i+1}`` (see :func:`trig`).
    qname : str
        C expression of the joint value (``"q[0]"``).
    sign : float
        +1, or −1 for the inverse motion used by the Newton–Euler link transforms (the sine
        and the linear term change sign, the cosine does not).

    Returns
    -------
    Pose
        ``R = I + s[ω] + (1 − c)[ω]²`` (or ``c I + s[ω] + (1 − c)ωωᵀ``, whichever has fewer
        terms per entry), ``p = s v + (1 − c) ω × v (+ (q − s)(ω·v) ω)``; ``R = I, p = v q``
        for a prismatic joint.

    Examples
    --------
    >>> w = CWriter()
    >>> joint_exp(w, np.array([0, 0, 1.0, 0, 0, 0]), "R", 0, "q[0]").R[2][2]
    1.0
    """
    k = i + 1
    om = [snap(x) for x in S[:3]]
    v = [snap(x) for x in S[3:]]
    if kind == "P":
        return Pose(Pose.identity().R, [w.let(f"e{k}_p{j}", lin([(sign * v[j], qname)])) if v[j] != 0.0 else 0.0
                        for j in range(3)])
    c, s, vers = f"c{k}", f"s{k}", f"v{k}"
    W = np.array([[0.0, -om[2], om[1]], [om[2], 0.0, -om[0]], [-om[1], om[0], 0.0]])
    W2 = W @ W
    R: list[list[Val]] = [[0.0] * 3 for _ in range(3)]
    wwT = np.outer(om, om)
    for a in range(3):
        for b in range(3):
            # Rodrigues, in whichever of its two forms has fewer terms for this entry:
            # R = I + s[w] + (1 - c)[w]^2  or  R = c I + s[w] + (1 - c) w w^T
            form_a = [(sign * snap(W[a, b]), s), (snap(W2[a, b]), vers)]
            form_b = [(1.0 if a == b else 0.0, c), (sign * snap(W[a, b]), s), (snap(wwT[a, b]), vers)]
            n_a = sum(1 for t in form_a if t[0] != 0.0) + (a == b)
            n_b = sum(1 for t in form_b if t[0] != 0.0)
            value = lin(form_b) if n_b < n_a else lin(form_a, 1.0 if a == b else 0.0)
            R[a][b] = w.let(f"e{k}_{a}{b}", value)
    wxv = np.cross(om, v)
    h = snap(float(np.dot(om, v)))
    p: list[Val] = []
    for a in range(3):
        terms: list[tuple[float, Val]] = [(sign * v[a], s), (snap(wxv[a]), vers)]
        if h != 0.0:  # a screw with pitch (not met for revolute joints; kept for the general formula)
            terms += [(sign * h * om[a], qname), (-sign * h * om[a], s)]
        p.append(w.let(f"e{k}_p{a}", lin(terms)))
    return Pose(R, p)


def trig(w: CWriter, kinds: list[str], qnames: list[str]) -> None:
    """Emit ``c_k = cos q_k``, ``s_k = sin q_k``, ``v_k = 1 − c_k`` for every revolute joint k.

    Parameters
    ----------
    w : CWriter
        Where the temporaries go (unused ones are pruned later).
    kinds : list of {"R", "P"}
        Joint types.
    qnames : list of str
        C expressions of the joint values.

    Returns
    -------
    None

    Examples
    --------
    >>> w = CWriter(); trig(w, ["R"], ["q[0]"]); w.lines[0].strip()
    'const double c1 = cos(q[0]);'
    """
    for i, (kind, qn) in enumerate(zip(kinds, qnames)):
        if kind == "R":
            k = i + 1
            w.let(f"c{k}", f"cos({qn})")
            w.let(f"s{k}", f"sin({qn})")
            w.let(f"v{k}", f"1.0 - c{k}")


def fk_chain(w: CWriter, Slist: np.ndarray, kinds: list[str], names: list[str]) -> list[Pose]:
    """Emit the partial products of exponentials ``T₀,ᵢ = e^{[S₁]q₁} ⋯ e^{[Sᵢ]qᵢ}`` (Lecture 4).

    Parameters
    ----------
    w : CWriter
        Where the code goes (in a function with the argument ``q``).
    Slist : (6, n) array
        Space screw axes, columns ``(ω, v)`` (``robot.poe.Slist``).
    kinds : list of {"R", "P"}
        Joint types.
    names : list of str
        Joint names (for the comments).

    Returns
    -------
    list of Pose
        ``T₀,₀ = I``, ``T₀,₁``, …, ``T₀,ₙ`` (n + 1 poses).

    Examples
    --------
    >>> len(fk_chain(CWriter(), np.array([[0, 0, 1.0, 0, 0, 0]]).T, ["R"], ["j1"]))
    2
    """
    n = Slist.shape[1]
    qn = [f"q[{i}]" for i in range(n)]
    w.comment("Lecture 4, product of exponentials: T(q) = e^[S1]q1 ... e^[Sn]qn M")
    trig(w, kinds, qn)
    chain = [Pose.identity()]
    for i in range(n):
        S = Slist[:, i]
        w.comment(f"joint {i + 1} ({'revolute' if kinds[i] == 'R' else 'prismatic'}, {names[i]}): "
                  f"S = ({', '.join(f'{x:.6g}' for x in S)})")
        E = joint_exp(w, S, kinds[i], i, qn[i])
        chain.append(E if i == 0 else compose(w, chain[-1], E, f"T{i + 1}"))
    return chain


def emit_fk(w: CWriter, Slist: np.ndarray, M: np.ndarray, kinds: list[str], names: list[str]) -> None:
    """Emit the body of ``NAME_fk(q, T)``: ``T = e^{[S₁]q₁} ⋯ e^{[Sₙ]qₙ} M`` (Lecture 4).

    Parameters
    ----------
    w : CWriter
        Where the body goes.
    Slist : (6, n) array
        Space screw axes (``robot.poe.Slist``), base frame.
    M : (4, 4) array
        Tool pose at q = 0 in the base frame (``robot.poe.M``, m).
    kinds, names : lists of n str
        Joint types ("R"/"P") and names.

    Returns
    -------
    None
        The body writes ``T[16]``, the tool pose in the base frame, row-major.

    Examples
    --------
    >>> w = CWriter()
    >>> emit_fk(w, np.array([[0, 0, 1.0, 0, 0, 0]]).T, np.eye(4), ["R"], ["j1"])
    >>> "T[15] = 1.0;" in w.text()
    True
    """
    chain = fk_chain(w, Slist, kinds, names)
    w.comment("the home pose M of the tool (pose at q = 0)")
    _store(w, compose(w, chain[-1], Pose.const(M), "Tt"), 0)


def _store(w: CWriter, T: Pose, offset: int) -> None:
    """Write the pose T into ``T[offset … offset + 15]``, row-major (the last row 0 0 0 1)."""
    for i in range(3):
        for j in range(3):
            w.assign(f"T[{offset + 4 * i + j}]", T.R[i][j])
        w.assign(f"T[{offset + 4 * i + 3}]", T.p[i])
    for j, x in enumerate((0.0, 0.0, 0.0, 1.0)):
        w.assign(f"T[{offset + 12 + j}]", x)


def emit_jacobian(w: CWriter, Slist: np.ndarray, M: np.ndarray, kinds: list[str], names: list[str]) -> None:
    """Emit the body of ``NAME_jacobian(q, J)``: the geometric Jacobian (Lecture 4/6).

    Parameters
    ----------
    w, Slist, M, kinds, names
        As in :func:`emit_fk`: the writer, the space screw axes (6, n), the tool pose at q = 0
        (4, 4), the joint types and names.

    Returns
    -------
    None
        The body writes ``J[6 * n]``, row-major, rows ``(ω; v)`` in base axes, v the velocity
        of the tool origin: column i is ``(R ωᵢ⁰, R vᵢ⁰ + R ωᵢ⁰ × (p_tool − p))`` with
        ``(R, p) = T₀,ᵢ₋₁``.

    Examples
    --------
    One revolute joint about z with the tool 1 m along x: ω = (0, 0, 1) and the tool origin's
    velocity ω × p = (−sin q₁, cos q₁, 0) per unit joint rate:

    >>> M = np.eye(4)
    >>> M[0, 3] = 1.0
    >>> w = CWriter()
    >>> emit_jacobian(w, np.array([[0, 0, 1.0, 0, 0, 0]]).T, M, ["R"], ["j1"])
    >>> [line.strip() for line in w.text().splitlines() if line.strip().startswith("J[")]
    ['J[0] = 0.0;', 'J[3] = -s1;', 'J[1] = 0.0;', 'J[4] = c1;', 'J[2] = 1.0;', 'J[5] = 0.0;']
    """
    n = Slist.shape[1]
    chain = fk_chain(w, Slist, kinds, names)
    w.comment("tool origin: p_tool = R_0n p_M + p_0n")
    last = chain[-1]
    pt = [w.let(f"pt{a}", lin([(1.0, dot(last.R[a], [float(x) for x in M[:3, 3]])), (1.0, last.p[a])]))
          for a in range(3)]
    w.comment("Lecture 4/6: column i = (R w_i, R v_i + (R w_i) x (p_tool - p)) with (R, p) = T_0,i-1")
    for i in range(n):
        A = chain[i]
        om0 = [snap(x) for x in Slist[:3, i]]
        v0 = [snap(x) for x in Slist[3:, i]]
        om = [w.let(f"w{i + 1}_{a}", dot(A.R[a], om0)) for a in range(3)]
        vv = [w.let(f"u{i + 1}_{a}", dot(A.R[a], v0)) for a in range(3)]
        if kinds[i] == "R":
            lever = [w.let(f"r{i + 1}_{a}", sub(pt[a], A.p[a])) for a in range(3)]
            lv = cross(om, lever)
            lin_v = [lin([(1.0, vv[a]), (1.0, lv[a])]) for a in range(3)]
        else:
            lin_v = list(vv)
        for a in range(3):
            w.assign(f"J[{a * n + i}]", om[a])
            w.assign(f"J[{(a + 3) * n + i}]", lin_v[a])


def emit_joint_poses(w: CWriter, Slist: np.ndarray, homes: np.ndarray, kinds: list[str], names: list[str]) -> None:
    """Emit the body of ``NAME_joint_poses(q, T)``: every joint frame's pose in the base frame.

    Parameters
    ----------
    w, Slist, kinds, names
        As in :func:`emit_fk`: the writer, the space screw axes (6, n), the joint types and names.
    homes : (n, 4, 4) array
        ``homes[k - 1]``: the pose of joint k's frame in the base frame at q = 0 (Pinocchio's
        ``data.oMi[k]`` at the neutral configuration, m).

    Returns
    -------
    None
        The body writes ``T[16 * n]``: ``T[16 (k − 1) … 16 k − 1]`` is joint k's frame pose,
        ``e^{[S₁]q₁} ⋯ e^{[Sₖ]qₖ} homes[k − 1]``, row-major — Pinocchio's ``data.oMi[k]``.

    Examples
    --------
    >>> w = CWriter()
    >>> emit_joint_poses(w, np.array([[0, 0, 1.0, 0, 0, 0]]).T, np.eye(4)[None], ["R"], ["j1"])
    >>> "T[15] = 1.0;" in w.text()
    True
    """
    n = Slist.shape[1]
    chain = fk_chain(w, Slist, kinds, names)
    w.comment("joint k's frame: T_0,k(q) = e^[S1]q1 ... e^[Sk]qk H_k, H_k its pose at q = 0 (Pinocchio's oMi[k])")
    for k in range(1, n + 1):
        _store(w, compose(w, chain[k], Pose.const(np.asarray(homes[k - 1], dtype=float)), f"H{k}"), 16 * (k - 1))
