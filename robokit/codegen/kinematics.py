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
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from robokit.codegen._c import CWriter, Val, cross, dot, lin, snap, sub

__all__ = ["emit_fk", "emit_jacobian", "Pose"]


@dataclass
class Pose:
    """A 3×4 pose [R | p] of folded values (R row-major lists, p a list of 3)."""

    R: list[list[Val]]
    p: list[Val]

    @staticmethod
    def const(T: np.ndarray) -> "Pose":
        return Pose([[snap(T[i, j]) for j in range(3)] for i in range(3)], [float(T[i, 3]) for i in range(3)])

    @staticmethod
    def identity() -> "Pose":
        return Pose.const(np.eye(4))


def compose(w: CWriter, A: Pose, B: Pose, name: str) -> Pose:
    """A·B, every non-constant entry bound to ``name_rc`` (rows r, columns c; c = 3 the position)."""
    R: list[list[Val]] = [[0.0] * 3 for _ in range(3)]
    p: list[Val] = [0.0] * 3
    for i in range(3):
        for j in range(3):
            R[i][j] = w.let(f"{name}_{i}{j}", dot(A.R[i], [B.R[0][j], B.R[1][j], B.R[2][j]]))
    for i in range(3):
        p[i] = w.let(f"{name}_{i}3", lin([(1.0, dot(A.R[i], B.p)), (1.0, A.p[i])]))
    return Pose(R, p)


def joint_exp(w: CWriter, S: np.ndarray, kind: str, i: int, qname: str, sign: float = 1.0) -> Pose:
    """``e^{[S]·sign·q}`` of joint i (0-based, q = ``qname``), its trig bound to ``c{i+1}``/``s{i+1}``.

    ``sign = −1`` gives the inverse motion used by the Newton–Euler link transforms; the sine
    (and the linear term) change sign, the cosine does not.
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
    """``c_k = cos q_k``, ``s_k = sin q_k``, ``v_k = 1 − c_k`` for every revolute joint."""
    for i, (kind, qn) in enumerate(zip(kinds, qnames)):
        if kind == "R":
            k = i + 1
            w.let(f"c{k}", f"cos({qn})")
            w.let(f"s{k}", f"sin({qn})")
            w.let(f"v{k}", f"1.0 - c{k}")


def fk_chain(w: CWriter, Slist: np.ndarray, kinds: list[str], names: list[str]) -> list[Pose]:
    """Emit the partial products ``T₀,ᵢ = e^{[S₁]q₁} ⋯ e^{[Sᵢ]qᵢ}``, i = 0..n (T₀,₀ = I)."""
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
    """Body of ``NAME_fk(q, T)``: T = e^{[S₁]q₁} ⋯ e^{[Sₙ]qₙ} M, row-major 4×4."""
    chain = fk_chain(w, Slist, kinds, names)
    w.comment("the home pose M of the tool (pose at q = 0)")
    T = compose(w, chain[-1], Pose.const(M), "Tt")
    for i in range(3):
        for j in range(3):
            w.assign(f"T[{4 * i + j}]", T.R[i][j])
        w.assign(f"T[{4 * i + 3}]", T.p[i])
    for j, x in enumerate((0.0, 0.0, 0.0, 1.0)):
        w.assign(f"T[{12 + j}]", x)


def emit_jacobian(w: CWriter, Slist: np.ndarray, M: np.ndarray, kinds: list[str], names: list[str]) -> None:
    """Body of ``NAME_jacobian(q, J)``: the geometric Jacobian (ω; v), 6×n row-major."""
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
