r"""C for the recursive Newton–Euler inverse dynamics, written out from the PoE parameters.

The recursion of Lecture 7 (Modern Robotics ch. 8.3, the form of
:mod:`robokit.kernels.dynamics`), with the link constants of ``Mlist``, ``Glist`` and
``Slist`` folded in:

* constants: ``M₀ᵢ = Mlist[0] ⋯ Mlist[i−1]``, ``Aᵢ = Ad_{M₀ᵢ⁻¹} Sᵢ`` (joint i's screw in the
  centre-of-mass frame {i});
* link transforms ``T_{i,i−1} = e^{−[Aᵢ]qᵢ} Mlist[i−1]⁻¹``;
* forward, ``V₀ = 0``, ``V̇₀ = (0, −g)``: ``Vᵢ = Ad_{T_{i,i−1}} V_{i−1} + Aᵢ q̇ᵢ``,
  ``V̇ᵢ = Ad_{T_{i,i−1}} V̇_{i−1} + ad_{Vᵢ} Aᵢ q̇ᵢ + Aᵢ q̈ᵢ``;
* backward, ``F_{n+1} = 0``: ``Fᵢ = Ad_{T_{i+1,i}}ᵀ F_{i+1} + Gᵢ V̇ᵢ − ad_{Vᵢ}ᵀ Gᵢ Vᵢ``,
  ``τᵢ = Fᵢᵀ Aᵢ`` (plus the rotor armature ``aᵢ q̈ᵢ`` when the model has one, as Pinocchio's rnea).

With ``Ad_T V = (Rω, p × Rω + Rv)`` and ``Ad_Tᵀ F = (Rᵀ(m − p × f), Rᵀf)`` for ``T = (R, p)``,
``ad_V X = (ω × ω_X, ω × v_X + v × ω_X)`` and ``−ad_Vᵀ (m, f) = (ω × m + v × f, ω × f)``.
The gravity torques are the same recursion with q̇ = q̈ = 0 folded in (velocity terms vanish).
"""
from __future__ import annotations

import numpy as np

from robokit.codegen._c import CWriter, Val, add, cross, dot, lin, snap
from robokit.codegen.kinematics import Pose, compose, joint_exp, trig

__all__ = ["emit_rnea"]


def _adjoint_inverse_screw(M0i: np.ndarray, S: np.ndarray) -> np.ndarray:
    """``Ad_{M⁻¹} S`` (6,) for a pose M and a screw S = (ω, v)."""
    R, p = M0i[:3, :3], M0i[:3, 3]
    om, v = S[:3], S[3:]
    return np.concatenate([R.T @ om, R.T @ (v - np.cross(p, om))])


def _inv(T: np.ndarray) -> np.ndarray:
    out = np.eye(4)
    out[:3, :3] = T[:3, :3].T
    out[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return out


def _vec(w: CWriter, name: str, vals: list[Val]) -> list[Val]:
    return [w.let(f"{name}_{a}", v) for a, v in enumerate(vals)]


def _rot(R: list[list[Val]], x: list[Val]) -> list[Val]:
    return [dot(R[a], x) for a in range(3)]


def _rot_t(R: list[list[Val]], x: list[Val]) -> list[Val]:
    return [dot([R[0][a], R[1][a], R[2][a]], x) for a in range(3)]


def emit_rnea(w: CWriter, Mlist: np.ndarray, Glist: np.ndarray, Slist: np.ndarray, kinds: list[str],
              gravity: np.ndarray, armature: np.ndarray, velocities: bool = True) -> None:
    """Emit the body of ``NAME_rnea(q, qd, qdd, tau)`` (or of ``NAME_gravity(q, tau)``).

    Parameters
    ----------
    w : CWriter
        Where the body goes.
    Mlist : (n+1, 4, 4) array
        ``Mlist[i]``: pose of link frame {i+1} (centre of mass) in {i} at q = 0 (``robot.poe``).
    Glist : (n, 6, 6) array
        Spatial inertias ``[[I_c, 0], [0, m 1]]`` in the link frames (kg, kg·m²).
    Slist : (6, n) array
        Space screw axes.
    kinds : list of {"R", "P"}
        Joint types.
    gravity : (3,) array
        Gravity in the base frame (m/s²).
    armature : (n,) array
        Rotor inertia added as ``armatureᵢ q̈ᵢ`` (Pinocchio's ``model.armature``).
    velocities : bool
        False for the gravity torques: q̇ = q̈ = 0 folded in.

    Returns
    -------
    None
        The body writes ``tau[n]`` (N·m or N).

    Notes
    -----
    The recursion of the module docstring (Lecture 7, Modern Robotics ch. 8.3).

    Examples
    --------
    >>> import robokit
    >>> p = robokit.load("twolink").poe
    >>> w = CWriter()
    >>> emit_rnea(w, p.Mlist, p.Glist, p.Slist, ["R", "R"], p.gravity, np.zeros(2))
    >>> "tau[1] =" in w.text()
    True
    """
    n = Slist.shape[1]
    qn = [f"q[{i}]" for i in range(n)]
    qd: list[Val] = [f"qd[{i}]" for i in range(n)] if velocities else [0.0] * n
    qdd: list[Val] = [f"qdd[{i}]" for i in range(n)] if velocities else [0.0] * n
    M0 = np.eye(4)
    A = []
    for i in range(n):
        M0 = M0 @ Mlist[i]
        A.append([snap(x) for x in _adjoint_inverse_screw(M0, Slist[:, i])])
    w.comment("Lecture 7, recursive Newton-Euler; A_i = Ad(M_0i^-1) S_i, the screw of joint i in link frame i")
    trig(w, kinds, qn)
    # link transforms T_{i,i-1} = e^{-[A_i] q_i} Mlist[i-1]^-1
    T: list[Pose] = []
    for i in range(n):
        w.comment(f"link {i + 1}: T_{i + 1},{i} = exp(-[A_{i + 1}] q_{i + 1}) Mlist[{i}]^-1, "
                  f"A_{i + 1} = ({', '.join(f'{x:.6g}' for x in A[i])})")
        E = joint_exp(w, np.array(A[i]), kinds[i], i, qn[i], sign=-1.0)
        T.append(compose(w, E, Pose.const(_inv(Mlist[i])), f"L{i + 1}"))
    w.comment("forward pass: twists V_i and accelerations dV_i of the link frames, dV_0 = (0, -g)")
    om: list[Val] = [0.0, 0.0, 0.0]
    v: list[Val] = [0.0, 0.0, 0.0]
    dom: list[Val] = [0.0, 0.0, 0.0]
    dv: list[Val] = [-float(g) for g in gravity]
    Vs, dVs = [], []
    for i in range(n):
        k = i + 1
        R, p = T[i].R, T[i].p
        Aw, Av = A[i][:3], A[i][3:]
        w.comment(f"link {k}: V_{k} = Ad(T_{k},{i}) V_{i} + A_{k} qd_{k}; "
                  f"dV_{k} = Ad(T_{k},{i}) dV_{i} + ad(V_{k}) A_{k} qd_{k} + A_{k} qdd_{k}")
        Rw = _rot(R, om)
        Rw_n = _vec(w, f"Rw{k}", Rw)
        pxRw = cross(p, Rw_n)
        om_k = _vec(w, f"w{k}", [lin([(1.0, Rw_n[a]), (Aw[a], qd[i])]) for a in range(3)])
        v_k = _vec(w, f"v{k}v", [lin([(1.0, pxRw[a]), (1.0, _rot(R, v)[a]), (Av[a], qd[i])]) for a in range(3)])
        Rdw = _vec(w, f"Rdw{k}", _rot(R, dom))
        pxRdw = cross(p, Rdw)
        # ad_{V_k} A_k qd_k = (w_k x Aw, w_k x Av + v_k x Aw) qd_k
        qA_w = [lin([(Aw[a], qd[i])]) for a in range(3)]
        qA_v = [lin([(Av[a], qd[i])]) for a in range(3)]
        qAw_n = _vec(w, f"qAw{k}", qA_w)
        qAv_n = _vec(w, f"qAv{k}", qA_v)
        ad_w = cross(om_k, qAw_n)
        ad_v = [add(x, y) for x, y in zip(cross(om_k, qAv_n), cross(v_k, qAw_n))]
        dom_k = _vec(w, f"dw{k}", [lin([(1.0, Rdw[a]), (1.0, ad_w[a]), (Aw[a], qdd[i])]) for a in range(3)])
        dv_k = _vec(w, f"dv{k}", [lin([(1.0, pxRdw[a]), (1.0, _rot(R, dv)[a]), (1.0, ad_v[a]),
                                       (Av[a], qdd[i])]) for a in range(3)])
        om, v, dom, dv = om_k, v_k, dom_k, dv_k
        Vs.append((om, v))
        dVs.append((dom, dv))
    w.comment("backward pass: wrenches F_i = Ad(T_i+1,i)^T F_i+1 + G_i dV_i - ad(V_i)^T G_i V_i; tau_i = F_i . A_i")
    m_next: list[Val] = [0.0, 0.0, 0.0]
    f_next: list[Val] = [0.0, 0.0, 0.0]
    for i in reversed(range(n)):
        k = i + 1
        G = Glist[i]
        Gs = [[snap(G[a, b]) if abs(G[a, b]) > 1e-300 else 0.0 for b in range(6)] for a in range(6)]
        om_k, v_k = Vs[i]
        dom_k, dv_k = dVs[i]
        w.comment(f"link {k}: mass {G[3, 3]:.6g} kg")
        V6 = list(om_k) + list(v_k)
        dV6 = list(dom_k) + list(dv_k)
        GV = _vec(w, f"GV{k}", [dot(Gs[a], V6) for a in range(6)])
        GdV = [dot(Gs[a], dV6) for a in range(6)]
        # -ad_V^T (m, f) = (w x m + v x f, w x f)
        c1 = cross(om_k, GV[:3])
        c2 = cross(v_k, GV[3:])
        c3 = cross(om_k, GV[3:])
        if i + 1 < n:  # Ad(T_{i+2,i+1})^T F_{i+2}: (R^T (m - p x f), R^T f)
            R, p = T[i + 1].R, T[i + 1].p
            pxf = cross(p, f_next)
            m_in = _rot_t(R, [lin([(1.0, m_next[a]), (-1.0, pxf[a])]) for a in range(3)])
            f_in = _rot_t(R, f_next)
        else:
            m_in, f_in = [0.0] * 3, [0.0] * 3
        m_k = _vec(w, f"m{k}", [add(m_in[a], GdV[a], c1[a], c2[a]) for a in range(3)])
        f_k = _vec(w, f"f{k}", [add(f_in[a], GdV[3 + a], c3[a]) for a in range(3)])
        tau = dot(list(m_k) + list(f_k), A[i])
        if armature[i] != 0.0:
            tau = lin([(1.0, tau), (float(armature[i]), qdd[i])])
        w.assign(f"tau[{i}]", tau)
        m_next, f_next = m_k, f_k
