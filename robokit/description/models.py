"""The robot models shipped in the repository's top-level ``models/`` folder.

Each ``models/<name>.yaml`` (a DH table, see the DH file format page of the docs) has its
generated ``models/<name>.urdf`` beside it. The folder is installed as the package
``robokit.models``, so the files are found with :mod:`importlib.resources` from a wheel, an
sdist or an editable install alike. Regenerate the URDFs after editing a YAML file with
``python -m robokit.description.models``; a test checks that they are up to date.
"""
from __future__ import annotations

from importlib import resources
from pathlib import Path
from robokit.errors import InputError

__all__ = ["models_dir", "shipped_models", "model_path"]


def models_dir() -> Path:
    """Path of the shipped models folder (the package ``robokit.models``, i.e. ``models/``).

    Returns
    -------
    pathlib.Path
        The installed folder holding ``<name>.yaml`` and ``<name>.urdf``.

    Examples
    --------
    >>> (models_dir() / "puma560.yaml").is_file()
    True
    """
    return Path(str(resources.files("robokit.models")))


def shipped_models() -> list[str]:
    """Names of the shipped DH models (``models/<name>.yaml``), sorted.

    Returns
    -------
    list of str
        The names ``robokit.load`` accepts for the shipped models.

    Examples
    --------
    >>> {"twolink", "rrr", "puma560"} <= set(shipped_models())
    True
    """
    return sorted(p.stem for p in models_dir().glob("*.yaml"))


def model_path(name: str, suffix: str = ".yaml") -> Path:
    """Path of a shipped model file.

    Parameters
    ----------
    name : str
        A shipped model name (see :func:`shipped_models`).
    suffix : str, optional
        ``".yaml"`` (the DH file, default) or ``".urdf"`` (the generated URDF).

    Returns
    -------
    pathlib.Path
        The file; :class:`~robokit.errors.InputError` listing the available names if there is none.

    Examples
    --------
    >>> model_path("rrr", ".urdf").name
    'rrr.urdf'
    """
    p = models_dir() / f"{name}{suffix}"
    if not p.is_file():
        raise InputError(f"model: no shipped model {name!r}; available: {', '.join(shipped_models())}")
    return p


def regenerate() -> list[Path]:
    """Write ``models/<name>.urdf`` for every shipped YAML file; returns the paths written."""
    from robokit._io import atomic_write
    from robokit.description.dh import DHTable
    from robokit.description.urdf_gen import urdf_from_dh

    out = []
    for name in shipped_models():
        table = DHTable.from_yaml(model_path(name))
        out.append(atomic_write(models_dir() / f"{name}.urdf", urdf_from_dh(table)))
    return out


if __name__ == "__main__":
    for p in regenerate():
        print(f"wrote {p}")
