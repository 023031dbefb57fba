r"""Reading ``.npz`` files robokit did not necessarily write: capability maps and chunk files.

An ``.npz`` file is a zip archive of ``.npy`` members. Before any array is allocated, every
member robokit reads is checked from the archive's directory and the member's ``.npy``
header (``numpy.lib.format.read_magic`` / ``read_array_header_*`` on the member's stream):

* the file is a regular file (never a symbolic link, a FIFO or a device) of at most
  :data:`MAX_FILE_BYTES`;
* member names are unique plain names (no folder part, no ``..``), stored or deflated;
* a member's declared uncompressed size is at most :data:`MAX_MEMBER_BYTES`, and a
  deflated member expands at most :data:`MAX_RATIO` times (a "deflate bomb" is refused
  from its directory entry, before anything is decompressed);
* the header's dtype is one the member may have (no object dtype: nothing is unpickled;
  no complex numbers), its shape is the member's shape, and header plus data are exactly
  the member's size.

The members are described by a table (:data:`MAP_MEMBERS`, :data:`CHUNK_MEMBERS`) of
:class:`Member` entries; a caller passes extra entries for other keys (e.g. what a map
stores about its robot), and the map's value checks run after loading
(:func:`read_map_arrays`). Every refusal is an :class:`robokit.errors.InputError` naming
the file and the member.
"""
from __future__ import annotations

import os
import stat
import zipfile
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Mapping

import numpy as np

from robokit.errors import InputError

__all__ = ["Member", "MAP_MEMBERS", "CHUNK_MEMBERS", "MAX_FILE_BYTES", "MAX_MEMBER_BYTES", "MAX_RATIO",
           "read_npz_members", "read_npz_file", "check_map_arrays", "read_map_arrays"]

#: Largest ``.npz`` file read (bytes).
MAX_FILE_BYTES = 2 * 1024**3
#: Largest declared uncompressed size of one member (bytes).
MAX_MEMBER_BYTES = 1024**3
#: Largest expansion of a deflated member (uncompressed / compressed size), above 1 MiB.
MAX_RATIO = 200
#: Longest string member (characters), e.g. a robot name.
MAX_TEXT = 10_000


@dataclass(frozen=True)
class Member:
    """One array member of an ``.npz`` file: its shape pattern and allowed dtype kinds.

    Attributes
    ----------
    shape : tuple of int or None
        The length of each axis, None for any length, e.g. ``(None, 3)``.
    kinds : str
        The numpy dtype kinds allowed (``"f"`` float, ``"i"``/``"u"`` integers, ``"U"`` text,
        ``"b"`` bool); default ``"fiu"``.
    required : bool
        Whether the file must have it (default True).
    max_text : int
        Longest text (characters) of a ``"U"`` member.

    Examples
    --------
    >>> Member((None, 3)).kinds
    'fiu'
    """

    shape: tuple[int | None, ...]
    kinds: str = "fiu"
    required: bool = True
    max_text: int = MAX_TEXT


#: The members of a capability map (``robokit workspace`` / :meth:`CapabilityMap.save`).
MAP_MEMBERS: dict[str, Member] = {
    "centres": Member((None, 3)),
    "index": Member((None,)),
    "orientations": Member((None, 3, 3)),
    "resolution": Member(()),
    "robot": Member((), "U", required=False),
}

#: The members of a chunk file of the capability map's chunk store.
CHUNK_MEMBERS: dict[str, Member] = {
    "counts": Member((None,), "iu"),
    "centres": Member((None, 3), "f"),
    "fingerprint": Member((), "U"),
}


def _fail(label: str, msg: str) -> InputError:
    return InputError(f"{label}: {msg}")


def _check_header(f: IO[bytes], label: str, key: str, spec: Member, size: int) -> None:
    try:
        version = np.lib.format.read_magic(f)
        if version == (1, 0):
            shape, fortran, dtype = np.lib.format.read_array_header_1_0(f, max_header_size=10_000)
        elif version in ((2, 0), (3, 0)):
            shape, fortran, dtype = np.lib.format.read_array_header_2_0(f, max_header_size=10_000)
        else:
            raise InputError(f"unknown .npy version {version}")
    except (ValueError, OSError, EOFError, SyntaxError, zipfile.BadZipFile) as exc:
        raise _fail(label, f"member {key!r} is not a valid .npy array ({exc})") from None
    if dtype.hasobject or dtype.kind not in spec.kinds or dtype.fields is not None or dtype.subdtype is not None:
        raise _fail(label, f"member {key!r} has dtype {dtype.str!r}; expected "
                           f"{'/'.join({'f': 'float', 'i': 'int', 'u': 'unsigned', 'U': 'text', 'b': 'bool'}[k] for k in spec.kinds)}")
    if len(shape) != len(spec.shape) or any(w is not None and s != w for s, w in zip(shape, spec.shape)):
        want = "(" + ", ".join("N" if w is None else str(w) for w in spec.shape) + ("," if len(spec.shape) == 1 else "") + ")"
        raise _fail(label, f"member {key!r} has shape {tuple(shape)}; expected {want}")
    if dtype.kind == "U" and dtype.itemsize > 4 * spec.max_text:
        raise _fail(label, f"member {key!r} is text of {dtype.itemsize // 4} characters (at most {spec.max_text})")
    nbytes = int(np.prod(shape, dtype=object)) * dtype.itemsize
    if nbytes > MAX_MEMBER_BYTES or f.tell() + nbytes != size:
        raise _fail(label, f"member {key!r} declares {nbytes} bytes of data in a member of {size} bytes")
    del fortran


def read_npz_members(data: IO[bytes], label: str, members: Mapping[str, Member]) -> dict[str, np.ndarray]:
    """The arrays of ``members`` from the ``.npz`` archive ``data`` (a binary file object).

    Parameters
    ----------
    data : binary file object
        The archive, positioned anywhere (zipfile seeks).
    label : str
        How errors name the file (``"map: 'x.npz'"``).
    members : mapping of name to :class:`Member`
        The members to read (``name`` without ``.npy``); other members are not read.

    Returns
    -------
    dict of ndarray
        One array per member present; InputError naming the file and the member for every
        check of the module docstring.

    Examples
    --------
    >>> import io, numpy as np
    >>> buf = io.BytesIO(); np.savez(buf, counts=np.arange(3), centres=np.zeros((3, 3)), fingerprint=np.str_("x"))
    >>> read_npz_members(buf, "chunk", CHUNK_MEMBERS)["counts"].tolist()
    [0, 1, 2]
    """
    try:
        zf = zipfile.ZipFile(data)
    except (zipfile.BadZipFile, OSError, ValueError, EOFError) as exc:
        raise _fail(label, f"not an .npz (zip) file ({exc})") from None
    with zf:
        infos = zf.infolist()
        names = [i.filename for i in infos]
        if len(set(names)) != len(names):
            dup = sorted({n for n in names if names.count(n) > 1})[0]
            raise _fail(label, f"the archive has two members named {dup!r}")
        for info in infos:
            n = info.filename
            if "/" in n or "\\" in n or n.startswith(".") or ".." in n or "\x00" in n:
                raise _fail(label, f"member name {n[:80]!r} is not a plain file name")
        out: dict[str, np.ndarray] = {}
        by_name = {i.filename: i for i in infos}
        for key, spec in members.items():
            zi = by_name.get(key + ".npy")
            if zi is None:
                if spec.required:
                    raise _fail(label, f"member {key!r} is missing")
                continue
            if zi.compress_type not in (zipfile.ZIP_STORED, zipfile.ZIP_DEFLATED):
                raise _fail(label, f"member {key!r} uses zip compression method {zi.compress_type} "
                                   "(only stored or deflated)")
            if zi.file_size > MAX_MEMBER_BYTES:
                raise _fail(label, f"member {key!r} declares {zi.file_size} bytes (at most {MAX_MEMBER_BYTES})")
            if (zi.compress_type == zipfile.ZIP_DEFLATED and zi.file_size > 2**20
                    and zi.file_size > MAX_RATIO * max(zi.compress_size, 1)):
                raise _fail(label, f"member {key!r} expands {zi.file_size / max(zi.compress_size, 1):.0f} times "
                                   f"(a compression bomb; at most {MAX_RATIO})")
            try:
                with zf.open(zi) as f:
                    _check_header(f, label, key, spec, zi.file_size)
                with zf.open(zi) as f:
                    arr = np.lib.format.read_array(f, allow_pickle=False)
            except InputError:
                raise
            except (ValueError, OSError, EOFError, zipfile.BadZipFile, RuntimeError) as exc:
                raise _fail(label, f"member {key!r} cannot be read ({exc})") from None
            out[key] = arr
        return out


def read_npz_file(path: str | os.PathLike[str], label: str, members: Mapping[str, Member]) -> dict[str, np.ndarray]:
    """:func:`read_npz_members` of the file ``path``: a regular file, not a link, opened without following one.

    Parameters
    ----------
    path : path
        The ``.npz`` file.
    label : str
        How errors name the file.
    members : mapping of name to :class:`Member`

    Returns
    -------
    dict of ndarray

    Examples
    --------
    >>> import tempfile, numpy as np, os
    >>> p = os.path.join(tempfile.mkdtemp(), "c.npz")
    >>> np.savez(p, counts=np.arange(2), centres=np.zeros((2, 3)), fingerprint=np.str_("x"))
    >>> read_npz_file(p, "chunk", CHUNK_MEMBERS)["centres"].shape
    (2, 3)
    """
    p = Path(path)
    try:
        st = os.lstat(p)
    except FileNotFoundError:
        raise _fail(label, "file not found") from None
    except OSError as exc:
        raise _fail(label, f"cannot read it ({exc.strerror})") from None
    if stat.S_ISLNK(st.st_mode):
        raise _fail(label, "is a symbolic link; give the file itself")
    if not stat.S_ISREG(st.st_mode):
        raise _fail(label, "is not a regular file")
    try:
        fd = os.open(p, os.O_RDONLY | getattr(os, "O_NOFOLLOW", 0) | getattr(os, "O_NONBLOCK", 0))
    except OSError as exc:
        raise _fail(label, f"cannot read it ({exc.strerror})") from None
    with os.fdopen(fd, "rb") as f:
        st = os.fstat(f.fileno())
        if not stat.S_ISREG(st.st_mode):
            raise _fail(label, "is not a regular file")
        if st.st_size > MAX_FILE_BYTES:
            raise _fail(label, f"is {st.st_size} bytes (at most {MAX_FILE_BYTES})")
        return read_npz_members(f, label, members)


def check_map_arrays(arrays: Mapping[str, np.ndarray], label: str) -> dict[str, np.ndarray]:
    """The value checks of a capability map's arrays (their shapes and dtypes already checked).

    Parameters
    ----------
    arrays : mapping
        ``centres`` (M, 3), ``index`` (M,), ``orientations`` (K, 3, 3), ``resolution`` ().
    label : str
        How errors name the map.

    Returns
    -------
    dict
        The arrays as float64 (and the others unchanged). InputError unless the centres are
        finite, the index is in [0, 1] with one value per centre, the orientations are K ≥ 1
        rotations (‖RRᵀ − I‖ ≤ 1e-6, det R > 0) and the resolution a positive finite number.

    Examples
    --------
    >>> import numpy as np
    >>> a = check_map_arrays(dict(centres=np.zeros((1, 3)), index=np.ones(1), orientations=np.eye(3)[None],
    ...                           resolution=np.float64(0.1)), "map")
    >>> float(a["resolution"])
    0.1
    """
    out = dict(arrays)
    C = np.asarray(arrays["centres"], dtype=float)
    D = np.asarray(arrays["index"], dtype=float)
    R = np.asarray(arrays["orientations"], dtype=float)
    r = float(np.asarray(arrays["resolution"], dtype=float))
    if not np.isfinite(C).all():
        raise _fail(label, "centres contain NaN or infinite values")
    if D.shape != (len(C),):
        raise _fail(label, f"index has {D.size} values for {len(C)} centres")
    if not (np.isfinite(D).all() and (D >= 0).all() and (D <= 1).all()):
        raise _fail(label, "index: expected values in [0, 1]")
    if len(R) == 0:
        raise _fail(label, "orientations: expected at least one rotation")
    if not np.isfinite(R).all():
        raise _fail(label, "orientations contain NaN or infinite values")
    err = np.abs(R @ np.transpose(R, (0, 2, 1)) - np.eye(3)).max(axis=(1, 2))
    det = np.linalg.det(R)
    if np.any(err > 1e-6) or np.any(det <= 0):
        k = int(np.argmax(err)) if np.any(err > 1e-6) else int(np.argmin(det))
        raise _fail(label, f"orientations: matrix {k} is not a rotation (‖RRᵀ − I‖ = {err[k]:.2g}, det = {det[k]:.3g})")
    if not (np.isfinite(r) and r > 0):
        raise _fail(label, f"resolution: expected a positive voxel size in m, got {r!r}")
    out.update(centres=C, index=D, orientations=R, resolution=np.float64(r))
    return out


def read_map_arrays(path: str | os.PathLike[str], extra: Mapping[str, Member] | None = None) -> dict[str, np.ndarray]:
    """The checked arrays of a capability map file (every check of the module docstring and
    :func:`check_map_arrays`).

    Parameters
    ----------
    path : path
        The ``.npz`` file.
    extra : mapping of name to :class:`Member`, optional
        Further members to read (and check for shape/dtype) besides :data:`MAP_MEMBERS`.

    Returns
    -------
    dict of ndarray
        ``centres``, ``index``, ``orientations``, ``resolution`` (float64), ``robot`` (text)
        when present, and the ``extra`` members present.

    Examples
    --------
    >>> import tempfile, os, numpy as np
    >>> p = os.path.join(tempfile.mkdtemp(), "m.npz")
    >>> np.savez(p, centres=np.zeros((1, 3)), index=np.ones(1), orientations=np.eye(3)[None],
    ...          resolution=np.float64(0.1))
    >>> read_map_arrays(p)["index"].tolist()
    [1.0]
    """
    label = f"map: {str(path)!r}"
    members = dict(MAP_MEMBERS)
    if extra:
        members.update(extra)
    arrays = read_npz_file(path, label, members)
    return check_map_arrays(arrays, label)

