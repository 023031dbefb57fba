"""numba's on-disk cache, kept fresh across the kernel files.

numba keys a cached kernel on its own source file only (its modification stamp, or in recent
versions the SHA-256 of its text): a kernel that calls or inlines a function of *another* file is
loaded from the cache unchanged after that other file changed. Here the kernels of
``robokit/kernels`` call one another across files (the calibrated IK runs the closed form's
steps, the general 6R method's polish the calibrated one's), so after an upgrade that changed one
file and not the other — or a ``git pull`` in a checkout, whose ``__pycache__`` keeps the old
machine code — the unchanged file's kernels would run the old code of the changed one, silently.

:class:`KernelCacheLocator` is put in front of numba's own cache locators. For a function defined
in one of :data:`FOLDERS` it takes the place numba would pick (the same folder, file names and
order: ``$NUMBA_CACHE_DIR``, the ``__pycache__`` beside the source, the per-user cache) and adds to
numba's stamp the SHA-256 of every ``.py`` file in the function's folder: any change to any kernel
file makes every cached kernel of that folder stale, and numba compiles them again (once). Other
packages' functions are left to numba's locators as they are.
"""
from __future__ import annotations

import hashlib
import os
from typing import Any

from numba.core import caching

#: Folders whose functions are cached with the stamp of the whole folder (absolute paths).
FOLDERS: list[str] = [os.path.dirname(os.path.abspath(__file__))]

_DIGESTS: dict[str, bytes] = {}

#: numba's cache implementation class holding the locator list (``CacheImpl`` in recent versions,
#: ``_CacheImpl`` before).
_IMPL: Any = getattr(caching, "CacheImpl", None) or getattr(caching, "_CacheImpl")


def sources_digest(folder: str) -> bytes:
    """The SHA-256 of the names and contents of the ``.py`` files in ``folder`` (sorted by name),
    computed once per process and folder.

    Parameters
    ----------
    folder : str
        An absolute path.

    Returns
    -------
    bytes
        32 bytes.
    """
    digest = _DIGESTS.get(folder)
    if digest is None:
        h = hashlib.sha256()
        for name in sorted(n for n in os.listdir(folder) if n.endswith(".py")):
            with open(os.path.join(folder, name), "rb") as f:
                text = f.read()
            h.update(name.encode() + b"\0" + len(text).to_bytes(8, "little") + text)
        digest = _DIGESTS[folder] = h.digest()
    return digest


class KernelCacheLocator(caching._CacheLocator):
    """numba's locator for a function, with the digest of its folder's sources in the stamp."""

    def __init__(self, inner: Any, folder: str) -> None:
        self._inner, self._folder = inner, folder

    def ensure_cache_path(self) -> None:
        self._inner.ensure_cache_path()

    def get_cache_path(self) -> str:
        return str(self._inner.get_cache_path())

    def get_source_stamp(self) -> Any:
        return self._inner.get_source_stamp(), sources_digest(self._folder)

    def get_disambiguator(self) -> str:
        return str(self._inner.get_disambiguator())

    @classmethod
    def from_function(cls, py_func: Any, py_file: str) -> KernelCacheLocator | None:
        folder = os.path.dirname(os.path.abspath(py_file))
        if folder not in FOLDERS:
            return None
        for other in _IMPL._locator_classes:
            if other is not cls:
                inner = other.from_function(py_func, py_file)
                if inner is not None:
                    return cls(inner, folder)
        return None


def install(folder: str | None = None) -> None:
    """Put :class:`KernelCacheLocator` first among numba's cache locators (once), and add ``folder``
    (absolute) to :data:`FOLDERS`. Must run before the functions are decorated: numba picks a
    function's locator when ``cache=True`` is applied.

    Parameters
    ----------
    folder : str, optional
        Another folder of kernels (the tests use one of their own).
    """
    if folder is not None and os.path.abspath(folder) not in FOLDERS:
        FOLDERS.append(os.path.abspath(folder))
    classes = _IMPL._locator_classes
    if KernelCacheLocator not in classes:
        classes.insert(0, KernelCacheLocator)
