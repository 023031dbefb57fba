"""Rewrite ``raise ValueError(`` → ``raise InputError(`` and ``raise TypeError(`` →
``raise InputTypeError(`` in robokit/ (outside robokit/kernels/, whose compiled code can raise
only builtin exceptions), adding the ``from robokit.errors import ...`` line where needed.

Run from the repository root: ``python .ci/convert_plain_raises.py`` (for code merged in after
``tests/hardening/test_error_types.py`` started banning plain raises). Idempotent.
"""
import ast
import pathlib

changed = 0
for f in sorted(pathlib.Path("robokit").rglob("*.py")):
    if "kernels" in f.parts:
        continue
    s = f.read_text(encoding="utf-8")
    if "raise ValueError(" not in s and "raise TypeError(" not in s:
        continue
    need = ({"InputError"} if "raise ValueError(" in s else set()) | (
        {"InputTypeError"} if "raise TypeError(" in s else set())
    s = s.replace("raise ValueError(", "raise InputError(").replace("raise TypeError(", "raise InputTypeError(")
    tree = ast.parse(s)
    have, imp = set(), None
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.module == "robokit.errors":
            have |= {a.name for a in node.names}
            imp = node
    missing = need - have
    if missing:
        lines = s.splitlines(keepends=True)
        if imp is not None and imp.lineno == imp.end_lineno:
            names = sorted({a.name for a in imp.names} | missing)
            lines[imp.lineno - 1] = f"from robokit.errors import {', '.join(names)}\n"
        else:
            last = None
            for node in tree.body:
                if isinstance(node, (ast.Import, ast.ImportFrom)):
                    last = node
                elif last is not None and not isinstance(node, ast.If):
                    break
            lines.insert(last.end_lineno if last else 0, f"from robokit.errors import {', '.join(sorted(missing))}\n")
        s = "".join(lines)
    f.write_text(s, encoding="utf-8")
    changed += 1
print(f"{changed} files rewritten")
