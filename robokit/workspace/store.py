r"""The chunk store of a capability map: a folder that is robokit's own.

``capability_map(..., store=FOLDER)`` (``robokit workspace`` uses ``MAP.npz.chunks``) keeps
each finished chunk there as ``chunk_00042.npz`` so that an interrupted run resumes. The
folder holds nothing else than:

* the marker :data:`MARKER` (``robokit-store.json``), written when robokit creates the
  folder, holding the run's fingerprint (every parameter that affects the map);
* chunk files ``chunk_NNNNN.npz`` and, at most, the hidden temporary files of a write that
  was killed (``.chunk_NNNNN.npz.*.tmp``).

Rules:

* the folder is created by robokit (built under a temporary name, with its marker, then
  renamed into place) and opened with ``O_NOFOLLOW | O_DIRECTORY``; every file in it is
  read, written, renamed and removed relative to that open folder (``dir_fd``), never
  through a path that a symbolic link could redirect; a symbolic link named like the store
  is refused;
* an existing folder without the marker, or holding any other file, is not robokit's:
  :class:`robokit.errors.InputError` saying so, and nothing in it is touched;
* while a run uses the store it holds an exclusive ``flock`` on the marker: a second run
  with the same store is refused ("another run holds it");
* a marker with another fingerprint (other parameters): the chunk files are removed and the
  marker rewritten; a chunk whose contents fail the checks (shape, dtype, counts in
  [0, K], its centres and fingerprint) is recomputed, with a note naming it;
* :func:`remove_store` deletes the store only if it holds nothing but the marker and chunk
  files.
"""
from __future__ import annotations

import errno
import fcntl
import io
import json
import os
import re
import secrets
import stat
import warnings
from pathlib import Path

import numpy as np

from robokit.errors import InputError, RobokitWarning

__all__ = ["MARKER", "ChunkStore", "remove_store"]

#: The marker file of a chunk store.
MARKER = "robokit-store.json"
#: Largest chunk file read back (bytes).
MAX_CHUNK_BYTES = 256 * 1024**2
_CHUNK = re.compile(r"chunk_\d{5}\.npz\Z")
_TMP = re.compile(r"\.(chunk_\d{5}\.npz|robokit-store\.json)\.[0-9a-f]{8}\.tmp\Z")
_DIR_FLAGS = os.O_RDONLY | getattr(os, "O_DIRECTORY", 0) | getattr(os, "O_NOFOLLOW", 0)
_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)


def _label(path: Path) -> str:
    return f"store: {str(path)!r}"


def _umask_mode(mode: int) -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mode & ~mask


def _open_dir(path: Path) -> int:
    """The folder ``path`` opened without following a link; InputError if it is not a folder."""
    try:
        st = os.lstat(path)
    except FileNotFoundError:
        raise
    if stat.S_ISLNK(st.st_mode):
        raise InputError(f"{_label(path)} is a symbolic link; robokit keeps its chunks only in a folder of its own "
                         "(remove the link or choose another -o)")
    if not stat.S_ISDIR(st.st_mode):
        raise InputError(f"{_label(path)} exists and is not a folder")
    try:
        return os.open(path, _DIR_FLAGS)
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            raise InputError(f"{_label(path)} is a symbolic link; robokit keeps its chunks only in a folder of its own") from None
        raise InputError(f"{_label(path)}: cannot open the folder ({exc.strerror})") from None


def _write_at(dir_fd: int, name: str, data: bytes) -> None:
    """Write ``name`` in the open folder atomically (hidden temporary file, fsync, rename)."""
    tmp = f".{name}.{secrets.token_hex(4)}.tmp"
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | _NOFOLLOW, _umask_mode(0o666), dir_fd=dir_fd)
    try:
        try:
            view = memoryview(data)
            while view:
                view = view[os.write(fd, view):]
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, name, src_dir_fd=dir_fd, dst_dir_fd=dir_fd)
    except BaseException:
        try:
            os.unlink(tmp, dir_fd=dir_fd)
        except OSError:
            pass
        raise


def _foreign(dir_fd: int) -> list[str]:
    """Entries of the open folder that robokit's store does not write."""
    out = []
    for name in os.listdir(dir_fd):
        if name == MARKER or _TMP.match(name):
            continue
        if _CHUNK.match(name):
            st = os.stat(name, dir_fd=dir_fd, follow_symlinks=False)
            if stat.S_ISREG(st.st_mode):
                continue
        out.append(name)
    return sorted(out)


def _lock(fd: int, path: Path) -> None:
    try:
        fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except OSError as exc:
        if exc.errno in (errno.EAGAIN, errno.EACCES, errno.EWOULDBLOCK):
            raise InputError(f"{_label(path)}: another robokit run holds this chunk store (same -o); "
                             "wait for it to finish or choose another -o") from None
        raise


def _open_marker(dir_fd: int, path: Path) -> int:
    try:
        fd = os.open(MARKER, os.O_RDWR | _NOFOLLOW, dir_fd=dir_fd)
    except FileNotFoundError:
        raise InputError(f"{_label(path)} exists and is not a robokit chunk store (no {MARKER}); "
                         "robokit leaves it alone: remove it or choose another -o") from None
    except OSError as exc:
        raise InputError(f"{_label(path)}: {MARKER} cannot be opened ({exc.strerror}); robokit leaves the folder alone") from None
    if not stat.S_ISREG(os.fstat(fd).st_mode):
        os.close(fd)
        raise InputError(f"{_label(path)}: {MARKER} is not a regular file; robokit leaves the folder alone")
    return fd


class ChunkStore:
    """An open, locked chunk store (see the module docstring); close it (or use ``with``).

    Opening checks the folder and takes the lock (errors before any work);
    :meth:`begin` then sets the run's fingerprint and K.

    Parameters
    ----------
    path : path
        The store folder; created if it does not exist (its parent must).

    Examples
    --------
    >>> import tempfile, os, numpy as np
    >>> folder = os.path.join(tempfile.mkdtemp(), "m.chunks")
    >>> with ChunkStore(folder) as st:
    ...     st.begin("f00d", {}, K=4)
    ...     st.write(0, np.zeros((2, 3)), np.array([4, 1]))
    ...     st.read(0, np.zeros((2, 3))).tolist()
    [4, 1]
    """

    def __init__(self, path: str | os.PathLike[str]) -> None:
        self.path = Path(path)
        self.fp = ""
        self.K = 0
        self.dir_fd = -1
        self.marker_fd = -1
        self.created = False  # made by this object (removed again if it ends holding no chunk)
        marker = json.dumps({"robokit_chunk_store": 1, "fingerprint": None}).encode("utf-8")
        for _ in range(3):
            try:
                self.dir_fd = _open_dir(self.path)
            except FileNotFoundError:
                if self._create(marker):
                    return
                continue  # another run made it meanwhile: open it
            self._adopt()
            return
        raise InputError(f"{_label(self.path)}: the folder keeps appearing and disappearing; is another program using it?")

    def _adopt(self) -> None:
        """Use the existing folder ``self.dir_fd`` if it is a robokit store nobody else holds."""
        try:
            self.marker_fd = _open_marker(self.dir_fd, self.path)
            _lock(self.marker_fd, self.path)
            foreign = _foreign(self.dir_fd)
            if foreign:
                raise InputError(f"{_label(self.path)} holds files robokit did not write ({', '.join(map(repr, foreign[:3]))}"
                                 f"{', …' if len(foreign) > 3 else ''}); robokit leaves the folder alone: "
                                 "move them or choose another -o")
        except BaseException:
            self.close()
            raise

    def begin(self, fingerprint: str, params: dict, K: int) -> None:
        """Start a run: chunks of another fingerprint are removed, those of this one kept.

        Parameters
        ----------
        fingerprint : str
            The run's fingerprint (a digest of everything that determines the counts).
        params : dict
            The parameters, written to the marker file for the reader's information.
        K : int
            Orientations per voxel (the largest valid count).

        Returns
        -------
        None
        """
        self.fp, self.K = str(fingerprint), int(K)
        old = self._marker_fingerprint()
        for name in os.listdir(self.dir_fd):
            if _TMP.match(name) or (old != self.fp and _CHUNK.match(name)):
                os.unlink(name, dir_fd=self.dir_fd)
        if old != self.fp:
            marker = json.dumps({"robokit_chunk_store": 1, "fingerprint": self.fp, "parameters": params},
                                indent=1, sort_keys=True, default=str).encode("utf-8")
            os.ftruncate(self.marker_fd, 0)
            os.pwrite(self.marker_fd, marker, 0)
            os.fsync(self.marker_fd)

    def _create(self, marker: bytes) -> bool:
        """Make the store: a hidden folder with the locked marker, renamed into place.
        False if the name was taken meanwhile."""
        parent = self.path.parent if str(self.path.parent) else Path(".")
        if not parent.is_dir():
            raise InputError(f"store: folder {str(parent)!r} does not exist")
        tmp = parent / f".{self.path.name}.{secrets.token_hex(4)}.tmp"
        os.mkdir(tmp, 0o777)
        dfd = mfd = -1
        try:
            dfd = os.open(tmp, _DIR_FLAGS)
            mfd = os.open(MARKER, os.O_RDWR | os.O_CREAT | os.O_EXCL | _NOFOLLOW, _umask_mode(0o666), dir_fd=dfd)
            fcntl.flock(mfd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            os.write(mfd, marker)
            os.fsync(mfd)
            os.rename(tmp, self.path)  # onto nothing (or an empty folder, which robokit then owns)
        except BaseException as exc:
            for fd in (mfd, dfd):
                if fd >= 0:
                    os.close(fd)
            try:
                os.unlink(tmp / MARKER)
            except OSError:
                pass
            try:
                os.rmdir(tmp)
            except OSError:
                pass
            if isinstance(exc, OSError) and exc.errno in (errno.ENOTEMPTY, errno.EEXIST, errno.ENOTDIR, errno.EISDIR):
                return False
            raise
        self.dir_fd, self.marker_fd = dfd, mfd
        self.created = True
        return True

    def _marker_fingerprint(self) -> str | None:
        try:
            raw = os.pread(self.marker_fd, 1 << 20, 0)
            value = json.loads(raw.decode("utf-8")).get("fingerprint")
            return value if isinstance(value, str) else None
        except (OSError, ValueError, AttributeError):
            return None

    @staticmethod
    def _name(chunk: int) -> str:
        return f"chunk_{int(chunk):05d}.npz"

    def read(self, chunk: int, centres: np.ndarray) -> np.ndarray | None:
        """The counts of a finished chunk, or None if it is to be (re)computed.

        A chunk file that exists but fails a check (not an npz, wrong members, dtype or
        shape, other centres or fingerprint, counts outside [0, K]) gives a note naming it.

        Parameters
        ----------
        chunk : int
            The chunk number.
        centres : ndarray, shape (m, 3)
            The chunk's voxel centres (m); the file must hold the same.

        Returns
        -------
        ndarray of int64, shape (m,), or None
        """
        from robokit.workspace.mapfile import CHUNK_MEMBERS, read_npz_members

        name = self._name(chunk)
        try:
            fd = os.open(name, os.O_RDONLY | _NOFOLLOW | getattr(os, "O_NONBLOCK", 0), dir_fd=self.dir_fd)
        except FileNotFoundError:
            return None
        except OSError as exc:
            self._bad(name, f"cannot be opened ({exc.strerror})")
            return None
        with os.fdopen(fd, "rb") as f:
            st = os.fstat(f.fileno())
            if not stat.S_ISREG(st.st_mode) or st.st_size > MAX_CHUNK_BYTES:
                self._bad(name, "is not a regular file of at most 256 MiB")
                return None
            data = f.read(MAX_CHUNK_BYTES + 1)
        try:
            z = read_npz_members(io.BytesIO(data), name, CHUNK_MEMBERS)
        except InputError as exc:
            self._bad(name, str(exc).removeprefix(f"{name}: "))
            return None
        counts = z["counts"]
        if str(z["fingerprint"]) != self.fp:
            self._bad(name, "belongs to another run (fingerprint)")
            return None
        if z["centres"].shape != np.shape(centres) or not np.array_equal(z["centres"], centres):
            self._bad(name, "holds other voxel centres")
            return None
        if counts.shape != (len(centres),) or counts.min(initial=0) < 0 or counts.max(initial=0) > self.K:
            self._bad(name, f"has counts outside [0, {self.K}]")
            return None
        return counts.astype(np.int64)

    def _bad(self, name: str, why: str) -> None:
        warnings.warn(f"store: chunk {name} in {str(self.path)!r} {why}; recomputing it", RobokitWarning, stacklevel=3)
        return None

    def write(self, chunk: int, centres: np.ndarray, counts: np.ndarray) -> None:
        """Write a finished chunk atomically inside the open store folder.

        Parameters
        ----------
        chunk : int
            The chunk number.
        centres : ndarray, shape (m, 3)
            Its voxel centres (m).
        counts : ndarray of int, shape (m,)
            Orientations reached per voxel, in [0, K].

        Returns
        -------
        None
        """
        buf = io.BytesIO()
        np.savez(buf, counts=np.asarray(counts, dtype=np.int64), centres=np.asarray(centres, dtype=float),
                 fingerprint=np.str_(self.fp))
        _write_at(self.dir_fd, self._name(chunk), buf.getvalue())

    def close(self) -> None:
        """Release the lock and the folder; a store this object created that holds no chunk
        (the run failed before finishing one) is removed."""
        if self.created and self.dir_fd >= 0:
            try:
                if not any(_CHUNK.match(n) for n in os.listdir(self.dir_fd)):
                    for name in os.listdir(self.dir_fd):
                        if name == MARKER or _TMP.match(name):
                            os.unlink(name, dir_fd=self.dir_fd)
                    os.rmdir(self.path)
            except OSError:
                pass
        for attr in ("marker_fd", "dir_fd"):
            fd = getattr(self, attr)
            if fd >= 0:
                try:
                    os.close(fd)
                except OSError:
                    pass
                setattr(self, attr, -1)

    def __enter__(self) -> ChunkStore:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def remove_store(path: str | os.PathLike[str]) -> bool:
    """Delete the chunk store ``path`` if it holds only robokit's marker and chunk files.

    Parameters
    ----------
    path : path
        The store folder.

    Returns
    -------
    bool
        True if it was removed; False (and nothing touched) if it does not exist, is a link,
        is not a store, holds other files or is held by another run.

    Examples
    --------
    >>> remove_store("/nonexistent/robokit.chunks")
    False
    """
    p = Path(path)
    try:
        dir_fd = _open_dir(p)
    except (FileNotFoundError, InputError):
        return False
    try:
        try:
            marker_fd = _open_marker(dir_fd, p)
        except InputError:
            return False
        try:
            try:
                _lock(marker_fd, p)
            except InputError:
                return False
            if _foreign(dir_fd):
                return False
            for name in os.listdir(dir_fd):
                os.unlink(name, dir_fd=dir_fd)
            try:
                os.rmdir(p)
            except OSError:
                return False
            return True
        finally:
            os.close(marker_fd)
    finally:
        os.close(dir_fd)
