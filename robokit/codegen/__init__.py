"""Generated C99 for a robot's controller (``robokit codegen``).

:func:`generate_c` writes, for any robot :func:`robokit.load` returns, the text of ``NAME.h``
and ``NAME.c``: ``NAME_fk`` (tool pose), ``NAME_jacobian`` (geometric Jacobian, rows (ω; v)),
``NAME_ik`` (every closed-form solution, as :func:`robokit.ik_analytic`), ``NAME_gravity`` and
``NAME_rnea`` (inverse dynamics, as Pinocchio's ``rnea``), with the robot's constants folded in;
:func:`write_c` writes both files (all or nothing). :mod:`robokit.codegen.build` compiles them
and calls them through ``ctypes``.

Modules: :mod:`~robokit.codegen.generate` (files, names, header), :mod:`~robokit.codegen.kinematics`
(product of exponentials, Jacobian), :mod:`~robokit.codegen.dynamics` (Newton–Euler),
:mod:`~robokit.codegen.ik` (Pieper, three parallel axes), :mod:`~robokit.codegen.build`,
:mod:`~robokit.codegen.wasm` (the same C as WebAssembly, for the teach page).

Example::

    >>> import robokit
    >>> from robokit.codegen import generate_c
    >>> src = generate_c(robokit.load("puma560"))
    >>> src.name, src.has_ik
    ('puma560', True)
"""
from robokit.codegen.generate import C_KEYWORDS, STANDARD_HEADERS, CSource, c_name, generate_c, write_c

__all__ = ["CSource", "generate_c", "write_c", "c_name", "C_KEYWORDS", "STANDARD_HEADERS"]
