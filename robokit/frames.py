"""One frame vocabulary: :class:`Frame`, the frame a Jacobian (or a tip wrench) is expressed in.

Every function and method that chooses such a frame — ``Robot.jacobian``,
``robokit.description.batch_jacobian``, ``robokit.kinematics.dh_jacobian``,
``robokit.kinematics.dh_static_torques``, ``robokit.symbolic.SymbolicArm.jacobian`` — takes a
:class:`Frame` (or one of its documented synonyms) as ``reference=`` and has the same default,
:data:`DEFAULT_FRAME` (``Frame.LOCAL_WORLD_ALIGNED``, the lecture's geometric Jacobian ⁰J).

For a frame F at position p (rows ``(ω; v)``):

* ``Frame.WORLD``: the twist of F taken at the root origin, root axes — Modern Robotics' space
  Jacobian J_s, Pinocchio's ``WORLD``;
* ``Frame.LOCAL``: ω and the velocity of F's origin, in F's own axes — the body Jacobian J_b,
  Pinocchio's ``LOCAL``;
* ``Frame.LOCAL_WORLD_ALIGNED``: ω and the velocity of F's origin, in root axes — the lecture's
  geometric Jacobian ⁰J, Pinocchio's ``LOCAL_WORLD_ALIGNED``.

Synonyms: the lower-case names ``"world"``, ``"local"``, ``"local_world_aligned"`` (the values of
the enum, accepted silently) and Pinocchio's own ``pinocchio.ReferenceFrame`` members. The older
words ``"space"`` (= WORLD), ``"body"`` and ``"tool"`` (= LOCAL) and ``"base"`` (=
LOCAL_WORLD_ALIGNED) keep their exact meaning but are deprecated: each warns once per process
(see :mod:`robokit._deprecation` for the removal version).
"""
from __future__ import annotations

from enum import Enum

from robokit._deprecation import FRAME_SYNONYMS, warn_once
from robokit.errors import InputError

__all__ = ["DEFAULT_FRAME", "Frame", "as_frame", "reference_or_default"]


class Frame(str, Enum):
    """The frame a twist or a wrench is expressed in, named as Pinocchio's ``ReferenceFrame``.

    A ``str`` enum: ``Frame.WORLD == "world"``, so code comparing with the lower-case names keeps
    working; ``Frame("local")`` is ``Frame.LOCAL``.

    Attributes
    ----------
    WORLD : Frame
        ``"world"``: the space Jacobian (twist taken at the root origin, root axes).
    LOCAL : Frame
        ``"local"``: the body Jacobian (the frame's own axes, at its origin).
    LOCAL_WORLD_ALIGNED : Frame
        ``"local_world_aligned"``: ω and the velocity of the frame's origin in root axes (the
        lecture's geometric Jacobian; robokit's default, :data:`DEFAULT_FRAME`).

    Examples
    --------
    >>> from robokit.frames import Frame
    >>> Frame.LOCAL_WORLD_ALIGNED.value, Frame("world") is Frame.WORLD
    ('local_world_aligned', True)
    >>> Frame.LOCAL.pinocchio
    pinocchio.pinocchio_pywrap_default.ReferenceFrame.LOCAL
    """

    WORLD = "world"
    LOCAL = "local"
    LOCAL_WORLD_ALIGNED = "local_world_aligned"

    def __str__(self) -> str:
        return self.value

    @property
    def pinocchio(self) -> object:
        """The matching ``pinocchio.ReferenceFrame`` member.

        Returns
        -------
        pinocchio.ReferenceFrame
            ``WORLD``, ``LOCAL`` or ``LOCAL_WORLD_ALIGNED``.

        Examples
        --------
        >>> import pinocchio
        >>> Frame.WORLD.pinocchio == pinocchio.ReferenceFrame.WORLD
        True
        """
        import pinocchio

        return getattr(pinocchio.ReferenceFrame, self.name)


#: The one default of every ``reference=`` parameter (documented on the *Conventions* page).
DEFAULT_FRAME = Frame.LOCAL_WORLD_ALIGNED

_BY_NAME = {f.value: f for f in Frame}


def as_frame(reference: object, name: str = "reference") -> Frame:
    """The :class:`Frame` named by ``reference``, or :class:`~robokit.errors.InputError`.

    Parameters
    ----------
    reference : Frame, str or pinocchio.ReferenceFrame
        A :class:`Frame`, its lower-case value (``"world"``, ``"local"``,
        ``"local_world_aligned"``), a ``pinocchio.ReferenceFrame`` member, or one of the
        deprecated words ``"space"``, ``"body"``, ``"tool"``, ``"base"`` (each warns once per
        process with a ``DeprecationWarning``).
    name : str, optional
        The argument's name, for the error message.

    Returns
    -------
    Frame
        The frame.

    Examples
    --------
    >>> as_frame("local") is Frame.LOCAL, as_frame(Frame.WORLD) is Frame.WORLD
    (True, True)
    >>> as_frame("spatial")
    Traceback (most recent call last):
    ...
    robokit.errors.InputError: reference: expected a robokit.Frame (WORLD, LOCAL, LOCAL_WORLD_ALIGNED) or one of 'world', 'local', 'local_world_aligned', 'space', 'body', 'tool', 'base', got 'spatial'
    """
    if isinstance(reference, Frame):
        return reference
    if isinstance(reference, str):
        frame = _BY_NAME.get(reference)
        if frame is not None:
            return frame
        canonical = FRAME_SYNONYMS.get(reference)
        if canonical is not None:
            frame = _BY_NAME[canonical]
            warn_once(f"reference={reference!r}")
            return frame
    elif type(reference).__name__ == "ReferenceFrame" and getattr(reference, "name", None) in Frame.__members__:
        return Frame[reference.name]  # type: ignore[attr-defined]
    accepted = ", ".join(repr(k) for k in [*_BY_NAME, *FRAME_SYNONYMS])
    raise InputError(f"{name}: expected a robokit.Frame (WORLD, LOCAL, LOCAL_WORLD_ALIGNED) or one of "
                     f"{accepted}, got {reference!r}")


def reference_or_default(reference: object, where: str, former_default: Frame | None = None) -> Frame:
    """The frame ``reference`` names, or the default when it is ``None`` (not given).

    Parameters
    ----------
    reference : Frame, str, pinocchio.ReferenceFrame or None
        As :func:`as_frame`; ``None`` means the caller did not choose.
    where : str
        The function, e.g. ``"Robot.jacobian"`` (the key of its changing default in
        :data:`robokit._deprecation.DEPRECATIONS`).
    former_default : Frame, optional
        The default the function had before :data:`DEFAULT_FRAME` was the one default. When given
        and ``reference`` is None, the former default is kept until the removal release, with a
        ``FutureWarning`` (once per process) saying how to keep today's result.

    Returns
    -------
    Frame
        The frame to use.

    Examples
    --------
    >>> reference_or_default(None, "dh_jacobian") is DEFAULT_FRAME
    True
    >>> reference_or_default("world", "Robot.jacobian", Frame.WORLD)
    <Frame.WORLD: 'world'>
    """
    if reference is not None:
        return as_frame(reference)
    if former_default is None or former_default is DEFAULT_FRAME:
        return DEFAULT_FRAME
    warn_once(f"{where}(reference omitted)", category=FutureWarning)
    return former_default
