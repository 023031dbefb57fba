"""Atomic file writes: a failure or a kill never leaves a half-written file behind.

The data are written to an unnamed file in the target's folder (Linux ``O_TMPFILE``: if the
process is killed, even by SIGKILL, the kernel discards it), then linked under a hidden
temporary name and renamed over the target in one step. Where ``O_TMPFILE`` is not
available a named temporary file is used and removed on any exception (SIGINT/SIGTERM
included: the command line turns both into exceptions). The file gets the permissions of
any file opened for writing: ``0666`` less the user's umask.
"""
from __future__ import annotations

import os
import secrets
from pathlib import Path

from robokit.errors import InputError

__all__ = ["atomic_write", "read_input_text"]


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _write_all(fd: int, data: bytes) -> None:
    view = memoryview(data)
    while view:
        n = os.write(fd, view)
        view = view[n:]


def atomic_write(path: str | os.PathLike[str], data: str | bytes) -> Path:
    """Write ``data`` to ``path`` atomically; ``path`` is untouched unless the write completes.

    Raises ``ValueError`` naming the folder if it does not exist.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise ValueError(f"output: folder {str(folder)!r} does not exist")
    if path.is_dir():
        raise ValueError(f"output: {str(path)!r} is a folder")
    raw = data if isinstance(data, bytes) else data.encode("utf-8")
    mode = 0o666 & ~_umask()
    tmp = folder / f".{path.name}.{secrets.token_hex(4)}.tmp"
    o_tmpfile = getattr(os, "O_TMPFILE", None)
    fd = None
    if o_tmpfile is not None:
        try:
            fd = os.open(folder, o_tmpfile | os.O_WRONLY, mode)
        except OSError:  # file system without O_TMPFILE support
            fd = None
    if fd is not None:
        try:
            _write_all(fd, raw)
            os.fsync(fd)
            linked = _link_fd(fd, tmp)
        finally:
            os.close(fd)
        if not linked:  # no linkat: write the named way below
            fd = None
    if fd is None:
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL, mode)
        try:
            try:
                _write_all(fd, raw)
                os.fsync(fd)
            finally:
                os.close(fd)
        except BaseException:
            _unlink(tmp)
            raise
    try:
        os.replace(tmp, path)
    except BaseException:
        _unlink(tmp)
        raise
    return path


def _link_fd(fd: int, target: str | os.PathLike[str]) -> bool:
    """Give the unnamed file ``fd`` the name ``target`` (linkat with AT_SYMLINK_FOLLOW on
    /proc/self/fd, as open(2) describes for O_TMPFILE); False if that is not possible."""
    import ctypes

    try:
        libc = ctypes.CDLL(None, use_errno=True)
        linkat = libc.linkat
    except (OSError, AttributeError):
        return False
    at_fdcwd, at_symlink_follow = -100, 0x400
    rc = linkat(at_fdcwd, f"/proc/self/fd/{fd}".encode(), at_fdcwd, os.fsencode(str(target)), at_symlink_follow)
    if rc != 0:
        err = ctypes.get_errno()
        if err in (2, 18, 22, 38, 95):  # ENOENT (no /proc), EXDEV, EINVAL, ENOSYS, EOPNOTSUPP
            return False
        raise OSError(err, os.strerror(err), str(target))
    return True


def _unlink(p: str | os.PathLike[str]) -> None:
    try:
        os.unlink(p)
    except FileNotFoundError:
        pass


def read_input_text(path: str | os.PathLike[str], max_bytes: int, kind: str) -> str:
    """The UTF-8 text of an input file robokit was pointed at (a DH YAML, a URDF), refusing with
    :class:`robokit.InputError` naming the file: missing, unreadable, a folder, larger than
    ``max_bytes`` (checked before reading), or not UTF-8 (with the byte and its offset).
    ``kind`` names the expected file in the folder message ("a YAML file")."""
    path = Path(path)
    try:
        size = path.stat().st_size
    except FileNotFoundError:
        raise InputError(f"{path}: file not found") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    if path.is_dir():
        raise InputError(f"{path}: is a folder, not {kind}")
    if size > max_bytes:
        raise InputError(f"{path}: file too large ({size} bytes; at most {max_bytes})")
    try:
        raw = path.read_bytes()
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{path}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start})") from None
