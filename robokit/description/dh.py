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
    """The 4×4 link transform ``ⁱ⁻¹Tᵢ`` of one DH row: the pose of frame {i} in frame {i−1}.

    standard: ``Rz(θ) Tz(d) Tx(a) Rx(α)`` (seed 003 eq. 13); modified (Craig): ``Rx(α) Tx(a) Rz(θ) Tz(d)``
    with ``a, α`` the row's ``a_{i−1}, α_{i−1}``.

    Parameters
    ----------
    a : float
        Link length, m (standard: along ``x_i``; modified: ``a_{i−1}`` along ``x_{i−1}``).
    alpha : float
        Link twist, rad (standard: about ``x_i``; modified: ``α_{i−1}`` about ``x_{i−1}``).
    d : float
        Link offset along the joint's z axis, m.
    theta : float
        Joint angle about the joint's z axis, rad (the offset plus ``q`` for a revolute joint).
    convention : {"standard", "modified"}, optional
        Which DH convention the row follows (default ``"standard"``); anything else raises
        :class:`~robokit.errors.InputError`.

    Returns
    -------
    numpy.ndarray, shape (4, 4)
        Homogeneous transform of frame {i} in frame {i−1} (translation in m).

    Examples
    --------
    θ = 90° turns the 1 m link onto the y axis of frame {i−1}:

    >>> T = dh_transform(1.0, 0.0, 0.0, np.pi / 2)
    >>> T[:3, 3].round(4).tolist()
    [0.0, 1.0, 0.0]
    """
    if convention not in ("standard", "modified"):
        raise InputError(f"convention: expected 'standard' or 'modified', got {convention!r}")
    # One link's matrix, written out (the lecture's formula) rather than through the DH kernel: this
    # runs while a DH robot is loaded, and loading stays free of numba (tests/test_lazy_import.py).
    # The kernel (robokit.kernels.dh.link_transform) is compared with it in tests/kinematics.
    ct, st = math.cos(theta), math.sin(theta)
    ca, sa = math.cos(alpha), math.sin(alpha)
    if convention == "standard":
        return np.array([[ct, -st * ca, st * sa, a * ct],
                         [st, ct * ca, -ct * sa, a * st],
                         [0.0, sa, ca, d],
                         [0.0, 0.0, 0.0, 1.0]])
    return np.array([[ct, -st, 0.0, a],
                     [st * ca, ct * ca, -sa, -sa * d],
                     [st * sa, ct * sa, ca, ca * d],
                     [0.0, 0.0, 0.0, 1.0]])


def matrix_from_rpy(rpy: ArrayLike) -> np.ndarray:
    """URDF roll-pitch-yaw to a rotation: ``Rz(yaw) Ry(pitch) Rx(roll)``, ``rpy = [roll, pitch, yaw]``.

    Not a third rotation API: it is :func:`robokit.spatial.matrix_from_euler` with the extrinsic
    XYZ sequence (= the seed's ZYX ``euler_to_matrix`` with the angles reversed), named for the
    files that write rpy (URDF, the DH file's base/tool).

    Parameters
    ----------
    rpy : array_like, shape (3,)
        ``[roll, pitch, yaw]`` in rad: rotations about the fixed x, y and z axes, in that order.

    Returns
    -------
    numpy.ndarray, shape (3, 3)
        The rotation matrix (columns: the rotated frame's axes in the fixed frame).

    Examples
    --------
    A yaw of 90° maps x onto y:

    >>> (matrix_from_rpy([0.0, 0.0, np.pi / 2]) @ [1.0, 0.0, 0.0]).round(4).tolist()
    [0.0, 1.0, 0.0]
    """
    return matrix_from_euler(np.asarray(rpy, dtype=float), "XYZ", extrinsic=True)


def rpy_from_matrix(R: ArrayLike) -> np.ndarray:
    """Inverse of :func:`matrix_from_rpy`: ``[roll, pitch, yaw]`` with pitch ∈ [−π/2, π/2].

    At gimbal lock (pitch = ±π/2) only roll ∓ yaw is determined; roll is then set to 0.

    Parameters
    ----------
    R : array_like, shape (3, 3)
        A rotation matrix.

    Returns
    -------
    numpy.ndarray, shape (3,)
        ``[roll, pitch, yaw]`` in rad, roll and yaw in (−π, π].

    Examples
    --------
    >>> rpy = [0.1, -0.2, 0.3]
    >>> np.allclose(rpy_from_matrix(matrix_from_rpy(rpy)), rpy)
    True
    """
    y, p, r = matrix_to_euler(R)
    return np.array([r, p, y])


@dataclass(frozen=True)
class DHLink:
    """One row of a DH table and the link's optional inertial and drive parameters.

    The drive parameters follow Corke's toolbox: referred to the joint they give inertia
    ``G² Jm``, viscous friction ``G² B`` and Coulomb friction ``|G| Tc`` (see
    :func:`robokit.dynamics.friction_torques`).

    Attributes
    ----------
    joint : {"R", "P"}
        Revolute or prismatic.
    a, d : float
        Link length and link offset, m (``d`` is the offset added to a prismatic joint's q).
    alpha, theta : float
        Link twist and joint angle, rad (``theta`` is the offset added to a revolute joint's q).
        In the modified convention ``a, alpha`` are the row's ``a_{i−1}, α_{i−1}``.
    qlim : numpy.ndarray, shape (2,), or None
        Lower and upper limits of q (rad or m); None when the file gives none.
    mass : float
        Link mass, kg.
    com : numpy.ndarray, shape (3,)
        Centre of mass in DH frame {i}, m.
    inertia : numpy.ndarray, shape (6,)
        ``[Ixx, Iyy, Izz, Ixy, Iyz, Ixz]`` about the centre of mass, frame-{i} axes, kg·m².
    Jm : float
        Motor (rotor) inertia, kg·m², motor side.
    G : float
        Gear ratio: motor turns per joint turn; its sign is the motor's direction.
    B : float
        Viscous friction, N·m·s/rad, motor side.
    Tc : numpy.ndarray, shape (2,)
        Coulomb friction for positive and negative motion, N·m, motor side (the negative-motion
        value is usually negative).
    name : str or None
        A label for the link (YAML key ``name``; kept when the table is written back). The
        generated URDF names its joints ``joint_<i>`` whatever the label.
    flip : bool
        The joint variable enters with a minus sign, ``θ = θ_offset − q`` (``d = d_offset − q``):
        the joint turns (slides) about −z (YAML key ``flip: true``; default False).

    Examples
    --------
    >>> link = DHLink(joint="R", a=0.5, G=10.0, Jm=2e-4)
    >>> round(link.joint_inertia, 6)
    0.02
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

    Frame poses in ``base_link``: ``T_base_0 = base``, ``T_base_i = base · ⁰T₁ ⋯ ⁱ⁻¹Tᵢ`` and the
    tool ``T_base_N · tool`` (Lecture 4).

    Attributes
    ----------
    name : str
        Robot name (the URDF's robot name).
    convention : {"standard", "modified"}
        Standard (Spong, Corke) or modified (Craig) DH.
    links : tuple of DHLink
        One row per joint, i = 1..N.
    gravity : numpy.ndarray, shape (3,)
        Gravity acceleration in base_link, m/s² (default ``[0, 0, −9.81]``).
    base : numpy.ndarray, shape (4, 4)
        Pose of DH frame {0} in base_link (default identity).
    tool : numpy.ndarray, shape (4, 4)
        Pose of the tool frame in DH frame {N} (default identity).

    Examples
    --------
    A planar two-link arm (1 m and 0.5 m) stretched along x:

    >>> table = DHTable("arm", "standard", (DHLink(a=1.0), DHLink(a=0.5)))
    >>> table.n, table.frames([0.0, 0.0])[-1][:3, 3].round(4).tolist()
    (2, [1.5, 0.0, 0.0])
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
        """Pose of frame {i+1} in frame {i} (0-based ``i``): the DH transform of row i+1 at ``q_i``.

        Parameters
        ----------
        i : int
            Row index, 0-based (row ``i`` is joint i+1).
        q_i : float
            The joint variable, rad (revolute: added to θ) or m (prismatic: added to d); ``−q_i``
            enters for a flipped joint.

        Returns
        -------
        numpy.ndarray, shape (4, 4)
            ``ⁱTᵢ₊₁`` (:func:`dh_transform` of the row), m.

        Examples
        --------
        >>> rk.load("twolink").dh.link_transform(1, np.pi / 2)[:3, 3].round(4).tolist()   # 0.8 m along y
        [0.0, 0.8, 0.0]
        """
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
        """Poses of DH frames {0..N} in base_link: ``T_base_i = base · ⁰T₁ ⋯ ⁱ⁻¹Tᵢ`` (Lecture 4).

        Parameters
        ----------
        q : array_like, shape (n,)
            Joint values (rad or m), finite, each added to its row's θ or d as
            :meth:`link_transform` adds ``q_i``.

        Returns
        -------
        numpy.ndarray, shape (n + 1, 4, 4)
            Row i is frame {i}'s pose in base_link (m); row 0 is ``base``.

        Examples
        --------
        >>> rk.load("twolink").dh.frames([np.pi / 2, 0.0])[:, :2, 3].round(4).tolist()
        [[0.0, 0.0], [0.0, 1.0], [0.0, 1.8]]
        """
        from robokit.kernels.dh import dh_frames, pack_dh  # the one DH FK: the compiled kernel

        P, modified, base = pack_dh(self)[:3]
        return dh_frames(P, modified, base, self._kernel_q(q))

    def _kernel_q(self, q: ArrayLike) -> np.ndarray:
        """Checked q as the kernels take it: C-contiguous, −qᵢ for a flipped joint."""
        q = self._q(q)
        if any(l.flip for l in self.links):
            q = q * np.array([-1.0 if l.flip else 1.0 for l in self.links])
        return np.ascontiguousarray(q)

    def fk(self, q: ArrayLike) -> np.ndarray:
        """Pose of the tool in base_link: ``base · ⁰T₁(q₁) ⋯ ᴺ⁻¹T_N(q_N) · tool``.

        Parameters
        ----------
        q : array_like, shape (n,)
            As in :meth:`frames`.

        Returns
        -------
        numpy.ndarray, shape (4, 4)
            The tool pose, m (equal to the generated URDF's ``tool`` frame in Pinocchio).

        Examples
        --------
        >>> table = rk.load("puma560").dh
        >>> q = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6]
        >>> np.allclose(table.fk(q), rk.load("puma560").frame_pose(q))
        True
        """
        from robokit.kernels.dh import dh_fk, pack_dh  # the one DH FK: the compiled kernel

        P, modified, base, tool = pack_dh(self)[:4]
        return dh_fk(P, modified, base, tool, self._kernel_q(q))

    # ------------------------------------------------------------------ YAML I/O
    @classmethod
    def from_yaml(cls, path: str | os.PathLike[str]) -> "DHTable":
        """Load a DH YAML file (the DH file format page of the documentation).

        Parameters
        ----------
        path : str or os.PathLike
            The ``.yaml`` file (lengths in m; angles in the file's ``angle_unit``).

        Returns
        -------
        DHTable
            The table, angles in rad; a bad file raises :class:`~robokit.errors.InputError` naming
            the file, the link and the key.

        Examples
        --------
        >>> from robokit.description.models import model_path
        >>> table = DHTable.from_yaml(model_path("puma560"))
        >>> table.n, table.convention, round(float(np.degrees(table.links[0].alpha)), 6)
        (6, 'standard', 90.0)
        """
        from robokit._yaml import load_yaml_file

        path = Path(path)
        data = load_yaml_file(path)
        return cls.from_dict(data, source=str(path))

    @classmethod
    def from_dict(cls, data: Any, source: str = "<dict>") -> "DHTable":
        """Build a table from the parsed YAML mapping (the checks of :meth:`from_yaml`).

        Parameters
        ----------
        data : mapping
            The mapping of the DH file format (keys ``name``, ``convention``, ``angle_unit``,
            ``links``, …).
        source : str, optional
            What to call it in error messages (default ``"<dict>"``).

        Returns
        -------
        DHTable
            The table, angles in rad.

        Examples
        --------
        >>> t = DHTable.from_dict({"name": "arm", "convention": "standard", "angle_unit": "deg",
        ...                        "links": [{"joint": "R", "a": 1.0, "alpha": 90, "d": 0, "theta": 0}]})
        >>> t.n, round(t.links[0].alpha, 6)
        (1, 1.570796)
        """
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
        """The YAML mapping of the DH file format page of the documentation (numbers round-trip exactly).

        Parameters
        ----------
        angle_unit : {"deg", "rad"}, optional
            Unit of the angles written (default ``"deg"``).

        Returns
        -------
        dict
            ``name``, ``convention``, ``angle_unit``, ``gravity``, ``base``/``tool`` when not the
            identity, ``links``; :meth:`from_dict` of it gives the table back.

        Examples
        --------
        >>> table = rk.load("twolink").dh
        >>> d = table.to_dict("deg")
        >>> d["links"][1]["a"], DHTable.from_dict(d).links[1].a
        (0.8, 0.8)
        """
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
        """The table as YAML text (the DH file format page of the documentation).

        Parameters
        ----------
        angle_unit : {"deg", "rad"}, optional
            As in :meth:`to_dict`.

        Returns
        -------
        str
            The YAML document of :meth:`to_dict`.

        Examples
        --------
        >>> print(rk.load("twolink").dh.to_yaml_str().splitlines()[0])
        name: twolink
        """
        import yaml

        return yaml.safe_dump(self.to_dict(angle_unit), sort_keys=False, default_flow_style=None, width=100)

    def save(self, path: str | os.PathLike[str], angle_unit: str = "deg") -> Path:
        """Write the table as a YAML file, atomically (nothing is written on error).

        Parameters
        ----------
        path : str or os.PathLike
            The file to write.
        angle_unit : {"deg", "rad"}, optional
            As in :meth:`to_dict`.

        Returns
        -------
        pathlib.Path
            ``path``: the YAML file, which :meth:`from_yaml` reads back.

        Examples
        --------
        >>> import pathlib, tempfile
        >>> table = rk.load("twolink").dh
        >>> with tempfile.TemporaryDirectory() as tmp:
        ...     back = DHTable.from_yaml(table.save(pathlib.Path(tmp, "twolink.yaml")))
        >>> [l.a for l in back.links]
        [1.0, 0.8]
        """
        return atomic_write(path, self.to_yaml_str(angle_unit))

    def __repr__(self) -> str:
        joints = "".join(l.joint for l in self.links)
        return f"DHTable({self.name!r}, {self.convention}, {self.n} joints {joints})"

    def __str__(self) -> str:
        return self.to_text()

    def to_text(self, digits: int = 5) -> str:
        """The table as the lecture writes it.

        One row per joint (lengths in m, angles in degrees, ``+ q`` on the joint variable), then the
        base and tool transforms when they are not the identity (``xyz`` in m, URDF ``rpy`` in
        degrees) — without them the table alone does not reproduce the robot's tool pose.

        Parameters
        ----------
        digits : int, optional
            Decimals of the lengths (default 5); angles get ``digits − 2``.

        Returns
        -------
        str
            The printable table (also ``str(table)``).

        Examples
        --------
        >>> print(rk.load("rrr").dh.to_text(3).splitlines()[3])
        1      R    0.500            0.0    0.000        0.0 + q
        """
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
