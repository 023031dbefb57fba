r"""Drake's reflected rotor inertia, one rule for its SDFormat and URDF dialects.

Drake gives a joint actuator a rotor inertia ``I_r`` (kg·m²) and a gear ratio ``G`` and adds the
reflected inertia ``I_r · G²`` to that joint's diagonal entry of the mass matrix and to inverse
dynamics (τ += I_r G² q̈). Its SDFormat parser reads them from a joint's ``<drake:rotor_inertia>``
and ``<drake:gear_ratio>``, its URDF parser from the ``<actuator>`` of a ``<transmission>``
(:mod:`robokit.description.urdf_check`); either way Drake creates the actuator only on a joint it
actuates — not a fixed joint, not one whose effort limit is 0 — so the other joints get none.
robokit puts the reflected inertia in Pinocchio's ``model.armature``, which ``crba``, ``rnea`` and
``aba`` add on the joint's diagonal, and says so in one note; ``reflected_inertia=False`` leaves it
out (noted too).
"""
from __future__ import annotations

import os
from dataclasses import dataclass
from typing import Sequence

from robokit.errors import InputError

__all__ = ["DrakeRotor", "drake_reflected_inertia", "drake_transmission", "DRAKE_XMLNS"]

#: The ``xmlns:drake`` a URDF written with :func:`drake_transmission` declares (Drake's own files do;
#: Drake's parser, urdfdom and robokit read the prefix as written, declared or not).
DRAKE_XMLNS = 'xmlns:drake="http://drake.mit.edu"'



@dataclass(frozen=True)
class DrakeRotor:
    """A joint's rotor parameters as a Drake file gives them.

    Attributes
    ----------
    joint : str
        The joint's name (scoped, for SDFormat's nested models).
    kind : str
        ``"revolute"``, ``"continuous"``, ``"prismatic"`` or ``"fixed"``.
    effort : float
        The effort limit Drake gives the actuator (``inf`` when the file gives none; 0: Drake adds no
        actuator, and so no reflected inertia).
    rotor : float or None
        ``drake:rotor_inertia`` (None: not given, Drake's default 0).
    gear : float or None
        ``drake:gear_ratio`` (None: not given, Drake's default 1).
    """

    joint: str
    kind: str
    effort: float
    rotor: float | None = None
    gear: float | None = None

    @property
    def actuated(self) -> bool:
        """Whether Drake creates an actuator on the joint (not fixed, effort limit not 0)."""
        return self.kind != "fixed" and self.effort != 0.0

    @property
    def value(self) -> float:
        """``rotor_inertia · gear_ratio²`` with Drake's defaults (0 and 1)."""
        return (self.rotor or 0.0) * (1.0 if self.gear is None else self.gear) ** 2


def drake_reflected_inertia(rotors: Sequence[DrakeRotor], enabled: bool,
                            source: str | os.PathLike[str]) -> tuple[dict[str, float], list[str]]:
    """The armature Drake's reflected inertia gives each joint, and the notes saying so.

    Parameters
    ----------
    rotors : sequence of DrakeRotor
        The joints the file gives rotor parameters (rotor inertia, gear ratio or both).
    enabled : bool
        ``reflected_inertia``: False leaves the inertia out (one note says it was read).
    source : str or path-like
        Names the file in the notes.

    Returns
    -------
    armature : dict of str to float
        Joint name → ``rotor_inertia · gear_ratio²`` for the joints Drake actuates (empty when not
        ``enabled``).
    notes : list of str
        At most one note on what was added (or left out) and one on the joints Drake does not actuate.

    Examples
    --------
    >>> arm, notes = drake_reflected_inertia([DrakeRotor("j1", "revolute", 320.0, 1e-4, 160.0),
    ...                                       DrakeRotor("j2", "fixed", 1.0, 1e-4, 100.0)], True, "arm.urdf")
    >>> round(arm["j1"], 12), len(notes)
    (2.56, 2)
    """
    armature: dict[str, float] = {}
    added, ignored = [], []
    for r in rotors:
        if not r.actuated:
            ignored.append(r.joint)
        elif enabled:
            armature[r.joint] = r.value
            added.append(f"{r.joint} {r.value:.6g}")
    notes = []
    if added:
        notes.append(f"{source}: reflected rotor inertia drake:rotor_inertia × drake:gear_ratio² added to M and "
                     f"inverse dynamics as Drake adds it (kg·m²): {', '.join(added)}; load with "
                     "reflected_inertia=False (--no-reflected-inertia) to leave it out")
    elif not enabled and any(r.actuated for r in rotors):
        notes.append(f"{source}: drake:rotor_inertia / drake:gear_ratio read but left out (reflected_inertia=False)")
    if ignored:
        notes.append(f"{source}: drake:rotor_inertia ignored on joints Drake does not actuate (fixed or <effort>0): "
                     f"{', '.join(ignored)}")
    return armature, notes


def drake_transmission(joint: str, armature: float) -> str:
    """A URDF ``<transmission>`` giving ``joint`` the reflected inertia ``armature`` as Drake reads it.

    ``drake:rotor_inertia`` is the armature and ``drake:gear_ratio`` 1, so Drake's URDF parser (and
    robokit's) computes ``armature · 1²`` — exactly the number written (``repr``: every digit). Drake
    creates the actuator only on a joint with a nonzero effort limit: the joint the text is written for
    must have one (or none, unlimited).

    Parameters
    ----------
    joint : str
        The joint's name (a name robokit wrote: no quoting needed beyond XML's).
    armature : float
        The reflected inertia, kg·m² (kg for a prismatic joint), finite and >= 0.

    Returns
    -------
    str
        One line of URDF.

    Examples
    --------
    >>> text = drake_transmission("joint_1", 2.56)
    >>> '<drake:rotor_inertia value="2.56"/><drake:gear_ratio value="1"/>' in text
    True
    """
    from xml.sax.saxutils import quoteattr

    value = float(armature)
    if not (value >= 0.0 and value != float("inf")):
        raise InputError(f"armature of {joint!r}: expected a finite number >= 0, got {armature!r}")
    return (f"<transmission name={quoteattr(joint + '_transmission')}>"
            "<type>transmission_interface/SimpleTransmission</type>"
            f"<joint name={quoteattr(joint)}/><actuator name={quoteattr(joint + '_motor')}>"
            f'<drake:rotor_inertia value="{value!r}"/><drake:gear_ratio value="1"/></actuator></transmission>')
