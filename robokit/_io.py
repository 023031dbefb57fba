"""Atomic file writes: a failure or a kill never leaves a half-written file behind.

The data are written to an unnamed file in the target's folder (Linux ``O_TMPFILE``: if the
process is killed, even by SIGKILL, the kernel discards it), then linked under a hidden
temporary name and renamed over the target in one step. Where ``O_TMPFILE`` is not
available a named temporary file is used and removed on any exception (SIGINT/SIGTERM
included: the command line turns both into exceptions). A new file gets the permissions of
any file opened for writing: ``0666`` less the user's umask. A file that replaces an existing
regular file keeps that file's permission bits (``0600`` stays ``0600``; set-user-ID and
set-group-ID bits are not carried over) and, where the system permits it, its owner and group;
a symbolic link at the path is replaced, never written through, and the new file follows the
umask.
"""
from __future__ import annotations

import os
import secrets
from pathlib import Path

from robokit.errors import InputError

__all__ = ["atomic_write", "decode_utf8", "read_input_bytes", "read_input_text", "check_output_file",
           "check_not_an_input", "check_output_folder", "make_output_folder"]


def _folder_of(path: Path) -> Path:
    """The folder a file ``path`` lives in (``.`` for a bare name)."""
    return path.parent if str(path.parent) else Path(".")


def check_output_file(path: str | os.PathLike[str], what: str = "output") -> Path:
    """An output file that can be written: its folder exists and the path is not a folder.

    Checked before any work (so that a bad output path fails at once) and again by
    :func:`atomic_write` when it writes.

    Parameters
    ----------
    path : str or path-like
        The file to write.
    what : str
        The argument named in the messages (``output``, ``-o``).

    Returns
    -------
    Path
        ``path`` as a :class:`~pathlib.Path`.

    Raises
    ------
    InputError
        ``WHAT: folder 'FOLDER' does not exist`` or ``WHAT: 'PATH' is a folder``.

    Examples
    --------
    >>> check_output_file("arm.urdf").name
    'arm.urdf'
    """
    out = Path(path)
    folder = _folder_of(out)
    if not folder.is_dir():
        raise InputError(f"{what}: folder {str(folder)!r} does not exist")
    if out.is_dir():
        raise InputError(f"{what}: {str(out)!r} is a folder")
    return out


def check_not_an_input(output: str | os.PathLike[str], *inputs: object, what: str = "output") -> None:
    """Refuse an output file that is one of the command's input files (the same file by any name:
    ``arm.yaml``, ``./arm.yaml``, a link to it): writing it would replace what was read.

    Parameters
    ----------
    output : str or path-like
        The file to write.
    *inputs
        The inputs; those that are not paths of existing files (a model name, a Robot) are skipped.
    what : str
        The argument named in the message.

    Raises
    ------
    InputError
        ``WHAT: 'PATH' is the input file INPUT; write the result to another file``.

    Examples
    --------
    >>> check_not_an_input("arm.urdf", "puma560")   # a model name is no file: nothing to refuse
    """
    out = Path(output)
    for item in inputs:
        if not isinstance(item, (str, os.PathLike)):
            continue
        try:
            same = os.path.samefile(out, item)
        except (OSError, ValueError):  # either does not exist (or is no path): no clash
            continue
        if same:
            raise InputError(f"{what}: {str(out)!r} is the input file {os.fspath(item)!r}; write the result to "
                             f"another file")


def check_output_folder(folder: str | os.PathLike[str], what: str = "-o") -> Path:
    """An output folder that exists or can be created: neither it nor an ancestor is a file.

    Checked before any work, so that a bad ``-o`` fails at once; :func:`make_output_folder` creates
    it (parents too) once there is something to write.
    """
    out = Path(folder)
    for p in (out, *out.parents):
        if p.exists():
            if not p.is_dir():
                raise InputError(f"{what}: {str(p)!r} is a file, not a folder")
            break
    return out


def make_output_folder(folder: str | os.PathLike[str], what: str = "-o") -> Path:
    """Create an output folder and its missing parents (nothing when it exists); one-line errors."""
    out = check_output_folder(folder, what)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise InputError(f"{what}: cannot create folder {str(out)!r}: {e.strerror or e}") from None
    return out


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

    Raises :class:`robokit.InputError` naming the folder if it does not exist, and naming
    ``path`` (never the temporary file beside it) when the folder cannot be written (no
    permission, a read-only file system, a full disk).
    """
    path = check_output_file(path)
    try:
        return _atomic_write(path, data)
    except OSError as exc:
        raise InputError(f"output: cannot write {str(path)!r} ({exc.strerror or exc})") from None


def _atomic_write(path: Path, data: str | bytes) -> Path:
    folder = _folder_of(path)
    raw = data if isinstance(data, bytes) else data.encode("utf-8")
    mode = 0o666 & ~_umask()
    keep = _existing_file(path)
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
            _keep_mode(fd, keep)
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
                _keep_mode(fd, keep)
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


def _existing_file(path: Path) -> os.stat_result | None:
    """The status of the regular file ``path`` replaces (not following a symbolic link), or None."""
    import stat

    try:
        st = os.lstat(path)
    except OSError:
        return None
    return st if stat.S_ISREG(st.st_mode) else None


def _keep_mode(fd: int, old: os.stat_result | None) -> None:
    """Give the new file ``fd`` the permission bits of the file it replaces, and its owner and group
    where permitted (an unprivileged user can only keep a group they belong to)."""
    if old is None:
        return
    os.fchmod(fd, old.st_mode & 0o777)
    st = os.fstat(fd)
    if (st.st_uid, st.st_gid) != (old.st_uid, old.st_gid):
        try:
            os.fchown(fd, old.st_uid, old.st_gid)
        except OSError:
            try:
                os.fchown(fd, -1, old.st_gid)
            except OSError:
                pass
        os.fchmod(fd, old.st_mode & 0o777)  # chown clears set-ID bits only; the mode stays the old one


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


def read_input_bytes(path: str | os.PathLike[str], max_bytes: int, kind: str) -> bytes:
    """The bytes of an input file robokit was pointed at, read from a **regular file only** and
    never more than ``max_bytes`` of them.

    The file is opened with ``O_NONBLOCK`` (a FIFO does not block the open) and checked with
    ``fstat`` on the open descriptor (no race with a rename): FIFOs, devices, sockets and
    folders are refused. The size cap is enforced on the bytes actually read (at most
    ``max_bytes + 1`` are read), so a symlink to ``/dev/zero`` or a file that grows while it is
    read cannot defeat it.

    Parameters
    ----------
    path : str or Path
        The file (a symlink is followed; what it points to must be a regular file).
    max_bytes : int
        Largest size accepted, in bytes.
    kind : str
        What the file should be ("a URDF file"), used in the messages.

    Returns
    -------
    bytes
        The file's content (at most ``max_bytes`` bytes).

    Raises
    ------
    InputError
        Naming the file: missing, unreadable, a folder, not a regular file, larger than
        ``max_bytes``.

    Examples
    --------
    >>> read_input_bytes("arm.urdf", 1 << 20, "a URDF file")[:5]   # doctest: +SKIP
    b'<?xml'
    """
    import stat

    path = Path(path)
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        raise InputError(f"{path}: file not found") from None
    except IsADirectoryError:
        raise InputError(f"{path}: is a folder, not {kind}") from None
    except OSError as exc:
        raise InputError(f"{path}: cannot read ({exc.strerror})") from None
    try:
        st = os.fstat(fd)
        if stat.S_ISDIR(st.st_mode):
            raise InputError(f"{path}: is a folder, not {kind}")
        if not stat.S_ISREG(st.st_mode):
            what = ("a FIFO" if stat.S_ISFIFO(st.st_mode) else "a device" if stat.S_ISCHR(st.st_mode)
                    or stat.S_ISBLK(st.st_mode) else "a socket" if stat.S_ISSOCK(st.st_mode) else "not a regular file")
            raise InputError(f"{path}: is {what}, not {kind} (only regular files are read)")
        if st.st_size > max_bytes:
            raise InputError(f"{path}: file too large ({st.st_size} bytes; at most {max_bytes})")
        chunks, total = [], 0
        while total <= max_bytes:
            try:
                chunk = os.read(fd, min(1 << 20, max_bytes + 1 - total))
            except BlockingIOError:  # pragma: no cover - regular files never block
                continue
            except OSError as exc:
                raise InputError(f"{path}: cannot read ({exc.strerror})") from None
            if not chunk:
                break
            chunks.append(chunk)
            total += len(chunk)
        if total > max_bytes:
            raise InputError(f"{path}: file too large (more than {max_bytes} bytes read; at most {max_bytes})")
        return b"".join(chunks)
    finally:
        os.close(fd)


def decode_utf8(raw: bytes, source: str | os.PathLike[str]) -> str:
    """``raw`` decoded as UTF-8.

    Parameters
    ----------
    raw : bytes
        What was read.
    source : str or Path
        The file it came from, named in the message.

    Returns
    -------
    str
        The decoded text (a byte-order mark, if any, kept as ``"\\ufeff"``).

    Raises
    ------
    InputError
        ``SOURCE: not UTF-8 text (byte 0xe9 at offset 12)``.

    Examples
    --------
    >>> decode_utf8("é".encode(), "a.urdf")
    'é'
    """
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        raise InputError(f"{source}: not UTF-8 text (byte 0x{raw[exc.start]:02x} at offset {exc.start})") from None


def read_input_text(path: str | os.PathLike[str], max_bytes: int, kind: str) -> str:
    """The UTF-8 text of an input file robokit was pointed at (a DH YAML, a URDF).

    Parameters
    ----------
    path : str or Path
        The file; read with :func:`read_input_bytes` (regular files only, at most
        ``max_bytes`` bytes read).
    max_bytes : int
        Largest size accepted, in bytes.
    kind : str
        The expected file in the messages ("a YAML file").

    Returns
    -------
    str
        The whole file's text, as :func:`decode_utf8` decodes it.

    Raises
    ------
    InputError
        Naming the file: missing, unreadable, a folder, a FIFO or device, too large, or not
        UTF-8 (with the byte and its offset).

    Examples
    --------
    >>> text = read_input_text("arm.yaml", 1 << 20, "a YAML file")   # doctest: +SKIP
    """
    return decode_utf8(read_input_bytes(path, max_bytes, kind), path)
