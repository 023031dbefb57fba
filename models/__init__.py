"""The robot models robokit ships: ``<name>.yaml`` (a DH table) and its generated ``<name>.urdf``.

This folder is installed as the package ``robokit.models``; robokit finds the files with
``importlib.resources``, the same way from a wheel, an sdist or an editable install.
"""

import sys as _sys
import types as _types


class _CallableModels(_types.ModuleType):
    """``robokit.models`` is this folder (the shipped files) and, called, ``robokit.models()``: the
    catalogue of names ``robokit.load`` knows (:func:`robokit.description.loading.models`). Importing
    this package replaces the attribute ``robokit.models`` with the package, so the package answers
    the call too."""

    def __call__(self):  # type: ignore[no-untyped-def]
        from robokit.description.loading import models

        return models()


_sys.modules[__name__].__class__ = _CallableModels
