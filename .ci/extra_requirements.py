"""Print the requirements that robokit's extras add (one a line, the core dependencies first).

``make`` installs robokit into .venv once (``pip install -e .``) and adds an extra with
``pip install -r`` of this list, so robokit itself is never uninstalled and reinstalled for an
extra (``pip install -e '.[docs]'`` would). The list is read from the installed robokit's
metadata (the same pyproject.toml: the Makefile reinstalls robokit when pyproject.toml changes);
an extra naming other extras (``all``, ``notebooks``) is expanded.

Usage: ``python .ci/extra_requirements.py EXTRA [EXTRA ...]``
"""
from __future__ import annotations

import importlib.metadata as md
import re
import sys


def requirements(extras: list[str]) -> list[str]:
    reqs = md.requires("robokit") or []
    out = [r.strip() for r in reqs if ";" not in r]
    seen: set[str] = set()
    todo = list(extras)
    while todo:
        extra = todo.pop(0)
        if extra in seen:
            continue
        seen.add(extra)
        found = False
        for r in reqs:
            spec, _, marker = r.partition(";")
            if not marker:
                continue
            m = re.fullmatch(r"""\s*extra\s*==\s*["']([^"']+)["']\s*""", marker)
            if m is None:
                raise SystemExit(f"extra_requirements.py: unsupported marker in {r!r}")
            if m.group(1) != extra:
                continue
            found = True
            name = re.match(r"[A-Za-z0-9._-]+", spec.strip())
            if name is not None and name.group(0).lower() == "robokit":
                inner = re.search(r"\[([^\]]*)\]", spec)
                todo += [e.strip() for e in inner.group(1).split(",")] if inner else []
            else:
                out.append(spec.strip())
        if not found:
            raise SystemExit(f"extra_requirements.py: robokit has no extra {extra!r}")
    return list(dict.fromkeys(out))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        raise SystemExit(__doc__)
    print("\n".join(requirements(sys.argv[1:])))
