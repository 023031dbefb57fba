r"""Denavit–Hartenberg tables: the type, the YAML format (see the DH file format page of the documentation) and DH forward kinematics.

Lecture 4 and seed 003 §2.1. Two conventions:

* standard (Denavit–Hartenberg as in Spong, Corke): row i holds ``a_i, α_i, d_i, θ_i`` and
  ``ⁱ⁻¹Tᵢ = Rz(θᵢ) Tz(dᵢ) Tx(aᵢ) Rx(αᵢ)``; joint i moves about (along) ``z_{i−1}``;
* modified (Craig): row i holds ``a_{i−1}, α_{i−1}, d_i, θ_i`` and
  ``ⁱ⁻¹Tᵢ = Rx(α_{i−1}) Tx(a_{i−1}) Rz(θᵢ) Tz(dᵢ)``; joint i moves about (along) ``z_i``.

A revolute joint adds its variable ``qᵢ`` to θᵢ (the row's θ is an offset), a prismatic
joint adds it to dᵢ. A *flipped* joint (``flip: true``, as Corke's toolbox models the Kinova
Jaco and Mico, whose joint 1 turns the other way) subtracts it instead: ``θᵢ = θ_offset − qᵢ``
(``dᵢ = d_offset − qᵢ``): its positive direction is about −z. In both conventions the body of link i is rigidly attached to DH frame
{i}; its mass, centre of mass and inertia (about the centre of mass, frame-{i} axes) are
given in that frame. Poses of the frames in ``base_link``: ``T_base_0 = base`` and
``T_base_i = base · ⁰T₁ ⋯ ⁱ⁻¹Tᵢ``; the tool is ``T_base_N · tool``.

Lengths in m, angles in rad inside the type (the YAML may use degrees: ``angle_unit``).
"""
from __future__ import annotations

import math
import os
from typing import Any, NoReturn
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from robokit._io import atomic_write
from robokit.errors import InputError
from numpy.typing import ArrayLike

from robokit.spatial.euler import matrix_from_euler
from robokit.spatial.so3 import matrix_to_euler
from robokit._deprecation import deprecated_alias

__all__ = ["DHLink", "DHTable", "dh_transform", "matrix_from_rpy", "rpy_from_matrix"]

_LINK_KEYS = {"joint", "a", "alpha", "d", "theta", "qlim", "mass", "com", "inertia", "Jm", "G", "B", "Tc", "name",
              "flip"}
#: Largest magnitude of a number in a DH file (SI units): beyond it products in FK and dynamics
#: overflow to inf/NaN (a 1e308 m link is a typo, not a robot).
MAX_MAGNITUDE = 1e12

_TOP_KEYS = {"name", "convention", "angle_unit", "gravity", "base", "tool", "links", "description"}


def dh_transform(a: float, alpha: float, d: float, theta: float, convention: str = "standard") -> np.ndarray:
    """The 4×4 link transform ``ⁱ⁻¹Tᵢ`` of one DH row (m, rad).

    standard: ``Rz(θ) Tz(d) Tx(a) Rx(α)`` (seed 003 eq. 13); modified: ``Rx(α) Tx(a) Rz(θ) Tz(d)``
    with ``a, α`` the row's ``a_{i−1}, α_{i−1}``.

    Example: ``dh_transform(1.0, 0.0, 0.0, np.pi / 2)`` moves 1 m along the rotated x axis (y).
    """
    ct, st = math.cos(theta), math.sin(theta)
    ca, sa = math.cos(alpha), math.sin(alpha)
    if convention == "standard":
        return np.array(
            [
                [ct, -st * ca, st * sa, a * ct],
                [st, ct * ca, -ct * sa, a * st],
                [0.0, sa, ca, d],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )
    if convention == "modified":
        return np.array(
            [
                [ct, -st, 0.0, a],
                [st * ca, ct * ca, -sa, -sa * d],
                [st * sa, ct * sa, ca, ca * d],
                [0.0, 0.0, 0.0, 1.0],
            ]
        )
    raise InputError(f"convention: expected 'standard' or 'modified', got {convention!r}")


def matrix_from_rpy(rpy: ArrayLike) -> np.ndarray:
    """URDF roll-pitch-yaw (rad) to a rotation: ``Rz(yaw) Ry(pitch) Rx(roll)``, ``rpy = [roll, pitch, yaw]``.

    Not a third rotation API: it is :func:`robokit.spatial.matrix_from_euler` with the extrinsic
    XYZ sequence (= the seed's ZYX ``euler_to_matrix`` with the angles reversed), named for the
    files that write rpy (URDF, the DH file's base/tool)."""
    return matrix_from_euler(np.asarray(rpy, dtype=float), "XYZ", extrinsic=True)


def rpy_from_matrix(R: ArrayLike) -> np.ndarray:
    """Inverse of :func:`matrix_from_rpy`: ``[roll, pitch, yaw]`` with pitch ∈ [−π/2, π/2] (roll = 0 at gimbal lock)."""
    y, p, r = matrix_to_euler(R)
    return np.array([r, p, y])


@dataclass(frozen=True)
class DHLink:
    """One row of a DH table and the link's optional inertial and drive parameters.

    joint : "R" (revolute) or "P" (prismatic); a, d : m; alpha, theta : rad (θ the offset
    added to a revolute q, d the offset added to a prismatic q); qlim : (2,) limits of q
    (rad or m) or None; mass : kg; com : (3,) centre of mass in DH frame {i} (m);
    inertia : (6,) ``[Ixx, Iyy, Izz, Ixy, Iyz, Ixz]`` about the centre of mass in frame-{i}
    axes (kg·m²); Jm : motor inertia (kg·m², motor side); G : gear ratio (motor turns per
    joint turn; its sign is the motor's direction); B : viscous friction (N·m·s/rad, motor
    side); Tc : (2,) Coulomb friction for positive and negative motion (N·m, motor side;
    the negative-motion value is usually negative). These drive parameters follow Corke's
    toolbox: referred to the joint they give inertia ``G² Jm``, viscous friction ``G² B``
    and Coulomb friction ``|G| Tc`` (see :func:`robokit.dynamics.friction_torques`). flip : the joint variable
    enters with a minus sign, ``θ = θ_offset − q`` (``d = d_offset − q``): the joint turns
    (slides) about −z (YAML key ``flip: true``; default False).
    """

    joint: str = "R"
    a: float = 0.0
    alpha: float = 0.0
    d: float = 0.0
    theta: float = 0.0
    qlim: np.ndarray | None = None
    mass: float = 0.0
    com: np.ndarray = field(default_factory=lambda: np.zeros(3))
    inertia: np.ndarray = field(default_factory=lambda: np.zeros(6))
    Jm: float = 0.0
    G: float = 1.0
    B: float = 0.0
    Tc: np.ndarray = field(default_factory=lambda: np.zeros(2))
    name: str | None = None
    flip: bool = False

    @property
    def joint_inertia(self) -> float:
        """Motor inertia reflected to the joint, ``G² Jm`` (kg·m²)."""
        return self.G * self.G * self.Jm

    @property
    def inertia_matrix(self) -> np.ndarray:
        """The 3×3 inertia tensor about the centre of mass, frame-{i} axes."""
        xx, yy, zz, xy, yz, xz = self.inertia
        return np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])


@dataclass(frozen=True)
class DHTable:
    """A serial arm described by a DH table (either convention), with base and tool frames.

    name : robot name; convention : "standard" or "modified"; links : tuple of
    :class:`DHLink`; gravity : (3,) gravity acceleration in base_link (m/s²); base : 4×4
    pose of DH frame {0} in base_link; tool : 4×4 pose of the tool in frame {N}.
    """

    name: str
    convention: str
    links: tuple
    gravity: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, -9.81]))
    base: np.ndarray = field(default_factory=lambda: np.eye(4))
    tool: np.ndarray = field(default_factory=lambda: np.eye(4))

    @property
    def n(self) -> int:
        """Number of joints."""
        return len(self.links)

    @property
    def has_inertia(self) -> bool:
        """True if any link has a mass."""
        return any(l.mass > 0 for l in self.links)

    @property
    def qlim(self) -> np.ndarray:
        """(n, 2) joint limits; missing limits are ±π for revolute and ±1 m for prismatic joints."""
        out = np.empty((self.n, 2))
        for i, l in enumerate(self.links):
            out[i] = l.qlim if l.qlim is not None else ((-np.pi, np.pi) if l.joint == "R" else (-1.0, 1.0))
        return out

    # ----------------------------------------------------------------- kinematics
    def link_transform(self, i: int, q_i: float) -> np.ndarray:
        """Pose of frame {i+1} in frame {i} (0-based ``i``) at joint value ``q_i`` (rad or m)
        (``−q_i`` enters for a flipped joint)."""
        l = self.links[i]
        if l.flip:
            q_i = -q_i
        theta, d = (l.theta + q_i, l.d) if l.joint == "R" else (l.theta, l.d + q_i)
        return dh_transform(l.a, l.alpha, d, theta, self.convention)

    def _q(self, q: ArrayLike) -> np.ndarray:
        q = np.asarray(q, dtype=float)
        if q.shape != (self.n,):
            raise InputError(f"q: expected shape ({self.n},) for {self.name}, got {q.shape}")
        if not np.all(np.isfinite(q)):
            raise InputError("q: contains NaN or infinite values")
        return q

    def frames(self, q: ArrayLike) -> np.ndarray:
        """(N+1, 4, 4) poses of DH frames {0..N} in base_link at joint values q (n,)."""
        q = self._q(q)
        out = np.empty((self.n + 1, 4, 4))
        T = np.asarray(self.base, dtype=float)
        out[0] = T
        for i in range(self.n):
            T = T @ self.link_transform(i, q[i])
            out[i + 1] = T
        return out

    def fk(self, q: ArrayLike) -> np.ndarray:
        """4×4 pose of the tool in base_link: ``base · ⁰T₁(q₁) ⋯ ᴺ⁻¹T_N(q_N) · tool``."""
        return self.frames(q)[-1] @ self.tool

    # ------------------------------------------------------------------ YAML I/O
    @classmethod
    def from_yaml(cls, path: str | os.PathLike[str]) -> "DHTable":
        """Load a DH YAML file (see the DH file format page of the documentation); errors name the file, the link and the key."""
        from robokit._yaml import load_yaml_file

        path = Path(path)
        data = load_yaml_file(path)
        return cls.from_dict(data, source=str(path))

    @classmethod
    def from_dict(cls, data: Any, source: str = "<dict>") -> "DHTable":
        """Build from the parsed YAML mapping; see :meth:`from_yaml`."""
        def fail(msg: str) -> NoReturn:
            if len(msg) > 300:  # a value echoed back is never allowed to make a huge line
                msg = msg[:297] + "..."
            raise InputError(f"{source}: {msg}")

        if not isinstance(data, dict):
            fail("expected a mapping with keys name, convention, links, …")
        unknown = set(data) - _TOP_KEYS
        if unknown:
            fail(f"unknown key(s) {sorted(unknown)}; allowed: {sorted(_TOP_KEYS)}")
        for key in ("name", "links"):
            if key not in data:
                fail(f"missing key '{key}'")
        name = data["name"]
        if (not isinstance(name, str) or not name.strip() or any(c.isspace() for c in name)
                or not name.isprintable() or len(name) > 200):
            shown = repr(name) if len(repr(name)) <= 60 else repr(name)[:57] + "..."
            fail(f"key 'name': expected a printable name without spaces (at most 200 characters), got {shown}")
        convention = data.get("convention", "standard")
        if convention not in ("standard", "modified"):
            fail(f"key 'convention': expected 'standard' or 'modified', got {convention!r}")
        unit = data.get("angle_unit", "rad")
        if unit not in ("deg", "rad"):
            fail(f"key 'angle_unit': expected 'deg' or 'rad', got {unit!r}")
        k = math.pi / 180.0 if unit == "deg" else 1.0

        def number(value: Any, where: str) -> float:
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                shown = repr(value) if len(repr(value)) <= 40 else repr(value)[:37] + "..."
                fail(f"{where}: expected a number, got {shown}")
            try:
                v = float(value)
            except OverflowError:
                fail(f"{where}: number too large")
            if not math.isfinite(v):
                fail(f"{where}: expected a finite number, got {value!r}")
            if abs(v) > MAX_MAGNITUDE:  # finite, but FK and dynamics would overflow to inf/NaN
                fail(f"{where}: {v:g} is out of range (at most {MAX_MAGNITUDE:g} in magnitude; SI units)")
            return v

        def vector(value: Any, length: int, where: str) -> np.ndarray:
            if not isinstance(value, (list, tuple)) or len(value) != length:
                got = f"{len(value)} entries" if isinstance(value, (list, tuple)) else repr(value)
                fail(f"{where}: expected a list of {length} numbers, got {got}")
            return np.array([number(v, where) for v in value])

        gravity = vector(data["gravity"], 3, "key 'gravity'") if "gravity" in data else np.array([0.0, 0.0, -9.81])

        def frame(key: str) -> np.ndarray:
            if key not in data:
                return np.eye(4)
            spec = data[key]
            if not isinstance(spec, dict) or set(spec) - {"xyz", "rpy"}:
                fail(f"key '{key}': expected a mapping with 'xyz' and/or 'rpy'")
            T = np.eye(4)
            T[:3, 3] = vector(spec.get("xyz", [0, 0, 0]), 3, f"key '{key}.xyz'")
            T[:3, :3] = matrix_from_rpy(vector(spec.get("rpy", [0, 0, 0]), 3, f"key '{key}.rpy'") * k)
            return T

        base, tool = frame("base"), frame("tool")
        links_data = data["links"]
        if not isinstance(links_data, list) or not links_data:
            fail("key 'links': expected a non-empty list of links")
        from robokit.description.limits import check_joint_count

        check_joint_count(len(links_data), source, "links (joints)")  # before anything is built
        links = []
        for i, ld in enumerate(links_data, start=1):
            where = f"link {i}"
            if not isinstance(ld, dict):
                fail(f"{where}: expected a mapping, got {ld!r}")
            unknown = set(ld) - _LINK_KEYS
            if unknown:
                fail(f"{where}: unknown key(s) {sorted(unknown)}; allowed: {sorted(_LINK_KEYS)}")
            for key in ("a", "alpha", "d", "theta"):
                if key not in ld:
                    fail(f"{where}: missing key '{key}'")
            joint = ld.get("joint", "R")
            if joint not in ("R", "P"):
                fail(f"{where}, key 'joint': expected 'R' or 'P', got {joint!r}")
            a = number(ld["a"], f"{where}, key 'a'")
            d = number(ld["d"], f"{where}, key 'd'")
            alpha = number(ld["alpha"], f"{where}, key 'alpha'") * k
            theta = number(ld["theta"], f"{where}, key 'theta'") * k
            qlim = None
            if "qlim" in ld and ld["qlim"] is not None:
                qlim = vector(ld["qlim"], 2, f"{where}, key 'qlim'") * (k if joint == "R" else 1.0)
                if qlim[0] > qlim[1]:
                    fail(f"{where}, key 'qlim': lower limit {qlim[0]:g} above upper limit {qlim[1]:g}")
            mass = number(ld.get("mass", 0.0), f"{where}, key 'mass'")
            if mass < 0:
                fail(f"{where}, key 'mass': expected a non-negative mass, got {mass:g}")
            com = vector(ld.get("com", [0, 0, 0]), 3, f"{where}, key 'com'")
            inertia = vector(ld.get("inertia", [0, 0, 0, 0, 0, 0]), 6, f"{where}, key 'inertia'")
            I = DHLink(inertia=inertia).inertia_matrix
            ev = np.linalg.eigvalsh(I)
            if np.any(inertia != 0) or mass > 0:
                if ev.min() < -1e-12 * max(1.0, abs(ev).max()):
                    fail(f"{where}, key 'inertia': not positive (semi-)definite (eigenvalues {np.round(ev, 6).tolist()})")
                # (No triangle-inequality check: the published PUMA 560 parameters violate it for
                # links 1 and 3, and Pinocchio only needs a symmetric positive semi-definite tensor.)
            Jm = number(ld.get("Jm", 0.0), f"{where}, key 'Jm'")
            G = number(ld.get("G", 1.0), f"{where}, key 'G'")
            B = number(ld.get("B", 0.0), f"{where}, key 'B'")
            Tc = vector(ld.get("Tc", [0, 0]), 2, f"{where}, key 'Tc'")
            if Jm < 0:
                fail(f"{where}, key 'Jm': expected a non-negative motor inertia, got {Jm:g}")
            if B < 0:
                fail(f"{where}, key 'B': expected a non-negative viscous friction, got {B:g}")
            lname = ld.get("name")
            if lname is not None and (not isinstance(lname, str) or not lname.isprintable() or len(lname) > 200):
                shown = repr(lname) if len(repr(lname)) <= 60 else repr(lname)[:57] + "..."
                fail(f"{where}, key 'name': expected a printable string (at most 200 characters), got {shown}")
            flip = ld.get("flip", False)
            if not isinstance(flip, bool):
                fail(f"{where}, key 'flip': expected true or false, got {flip!r}")
            links.append(DHLink(joint, a, alpha, d, theta, qlim, mass, com, inertia, Jm, G, B, Tc, lname, flip))
        return cls(name, convention, tuple(links), gravity, base, tool)

    def to_dict(self, angle_unit: str = "deg") -> dict:
        """The YAML mapping of the DH file format page of the documentation (angles in ``angle_unit``; numbers round-trip exactly)."""
        if angle_unit not in ("deg", "rad"):
            raise InputError(f"angle_unit: expected 'deg' or 'rad', got {angle_unit!r}")
        k = 180.0 / math.pi if angle_unit == "deg" else 1.0

        def ang(x: float) -> float:
            v = float(x) * k
            r = round(v)
            return float(r) if abs(v - r) < 1e-9 else v

        def num(x: float) -> float:
            return float(x)

        out: dict[str, Any] = {"name": self.name, "convention": self.convention, "angle_unit": angle_unit,
               "gravity": [num(g) for g in self.gravity]}
        for key, T in (("base", self.base), ("tool", self.tool)):
            T = np.asarray(T, dtype=float)
            if not np.allclose(T, np.eye(4), atol=0, rtol=0):
                out[key] = {"xyz": [num(v) for v in T[:3, 3]], "rpy": [ang(v) for v in rpy_from_matrix(T[:3, :3])]}
        links = []
        for l in self.links:
            d = {"joint": l.joint, "a": num(l.a), "alpha": ang(l.alpha), "d": num(l.d), "theta": ang(l.theta)}
            if l.name:
                d["name"] = l.name
            if l.qlim is not None:
                d["qlim"] = [ang(v) for v in l.qlim] if l.joint == "R" else [num(v) for v in l.qlim]
            if l.mass > 0 or np.any(np.asarray(l.inertia) != 0):
                d["mass"] = num(l.mass)
                d["com"] = [num(v) for v in l.com]
                d["inertia"] = [num(v) for v in l.inertia]
            if l.Jm:
                d["Jm"] = num(l.Jm)
            if l.G != 1.0:
                d["G"] = num(l.G)
            if l.B:
                d["B"] = num(l.B)
            if np.any(np.asarray(l.Tc) != 0):
                d["Tc"] = [num(v) for v in l.Tc]
            if l.flip:
                d["flip"] = True
            links.append(d)
        out["links"] = links
        return out

    def to_yaml_str(self, angle_unit: str = "deg") -> str:
        """The table as YAML text (see the DH file format page of the documentation)."""
        import yaml

        return yaml.safe_dump(self.to_dict(angle_unit), sort_keys=False, default_flow_style=None, width=100)

    def save(self, path: str | os.PathLike[str], angle_unit: str = "deg") -> Path:
        """Write the YAML file atomically."""
        return atomic_write(path, self.to_yaml_str(angle_unit))

    def __repr__(self) -> str:
        joints = "".join(l.joint for l in self.links)
        return f"DHTable({self.name!r}, {self.convention}, {self.n} joints {joints})"

    def __str__(self) -> str:
        return self.to_text()

    def to_text(self, digits: int = 5) -> str:
        """The table as the lecture writes it: one row per joint (lengths in m, angles in degrees,
        ``+ q`` on the joint variable), then the base and tool transforms when they are not the
        identity (``xyz`` in m, URDF ``rpy`` in degrees) — without them the table alone does not
        reproduce the robot's tool pose."""
        if self.convention == "standard":
            head = ("i", "joint", "a_i [m]", "alpha_i [deg]", "d_i [m]", "theta_i [deg]")
        else:
            head = ("i", "joint", "a_{i-1} [m]", "alpha_{i-1} [deg]", "d_i [m]", "theta_i [deg]")

        def fmt(x: float, k: int) -> str:
            return f"{round(float(x), k) + 0.0:.{k}f}"  # + 0.0: no "-0.000"

        rows = []
        for i, l in enumerate(self.links, 1):
            th = fmt(np.degrees(l.theta), digits - 2) + (" + q" if l.joint == "R" else "")
            d = fmt(l.d, digits) + (" + q" if l.joint == "P" else "")
            rows.append((str(i), l.joint, fmt(l.a, digits), fmt(np.degrees(l.alpha), digits - 2), d, th))
        w = [max(len(h), *(len(r[k]) for r in rows)) for k, h in enumerate(head)]
        line = lambda cells: "  ".join(c.rjust(wk) for c, wk in zip(cells, w))  # noqa: E731
        out = [f"# {self.name}: {self.convention} DH", line(head), line(tuple("-" * k for k in w))]
        out += [line(r) for r in rows]
        for label, T in (("base (frame {0} in base_link)", self.base), ("tool (tool frame in frame {N})", self.tool)):
            if not np.allclose(T, np.eye(4), atol=10.0 ** -(digits + 1)):
                xyz = ", ".join(fmt(v, digits) for v in T[:3, 3])
                rpy = ", ".join(fmt(v, digits - 2) for v in np.degrees(rpy_from_matrix(T[:3, :3])))
                out.append(f"# {label}: xyz [{xyz}] m, rpy [{rpy}] deg")
        return "\n".join(out) + "\n"

# Former names (before the X_from_Y rule): they warn and call the new function.
rpy_to_matrix = deprecated_alias(matrix_from_rpy, "rpy_to_matrix")
matrix_to_rpy = deprecated_alias(rpy_from_matrix, "matrix_to_rpy")
