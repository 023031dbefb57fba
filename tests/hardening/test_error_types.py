"""Errors by type. Every deliberate check raises InputError; the CLI maps InputError
(and OSError on a user's file) to exit 2 and everything else to 3, whatever file raised it;
array arguments are never cast silently (complex, strings, booleans, objects refused by name)."""
import ast
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

import hardening_support as hs

ROOT = Path(__file__).resolve().parents[2] / "robokit"


def _plain_raises(path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Raise) and node.exc is not None:
            exc = node.exc.func if isinstance(node.exc, ast.Call) else node.exc
            if isinstance(exc, ast.Name) and exc.id in ("ValueError", "TypeError"):
                yield node.lineno, exc.id


def test_no_plain_value_or_type_error_outside_the_kernels():
    """An AST scan (like tests/test_layers.py): ``raise ValueError``/``raise TypeError`` only in
    robokit/kernels/ (compiled code, which can raise only builtin exceptions)."""
    bad = []
    for path in sorted(ROOT.rglob("*.py")):
        if "kernels" in path.relative_to(ROOT).parts:
            continue
        bad += [f"{path.relative_to(ROOT.parent)}:{line}: raise {name}" for line, name in _plain_raises(path)]
    assert not bad, "\n".join(bad)


def test_the_scan_finds_a_plain_raise(tmp_path):
    """The scan is not vacuous: it sees both spellings."""
    p = tmp_path / "m.py"
    p.write_text("def f():\n    raise ValueError('x')\n\ndef g():\n    raise TypeError\n")
    assert list(_plain_raises(p)) == [(2, "ValueError"), (5, "TypeError")]


def _exceptions():
    from robokit.errors import InputError, InputTypeError

    return {
        "InputError": (lambda: InputError("model: bad"), 2),
        "InputTypeError": (lambda: InputTypeError("q: bad type"), 2),
        "OSError": (lambda: FileNotFoundError(2, "No such file", "x.urdf"), 2),
        "ValueError": (lambda: ValueError("a robokit bug"), 3),
        "TypeError": (lambda: TypeError("a bug"), 3),
        "KeyError": (lambda: KeyError("k"), 3),
        "LinAlgError": (lambda: np.linalg.LinAlgError("singular"), 3),
    }


@pytest.mark.parametrize("kind", sorted(_exceptions()))
def test_cli_exit_status_by_exception_type(kind, monkeypatch, main_cli):
    """The exception is raised from inside robokit's own code (robokit/commands.py): only its
    type decides the status (round 1 looked at the raising file)."""
    import robokit.commands

    make, rc = _exceptions()[kind]

    def boom(*a, **k):
        raise make()

    monkeypatch.setattr(robokit.commands, "convert_command", boom)
    run = main_cli("convert", "puma560")
    if rc == 2:
        hs.assert_one_line_error(run)
    else:
        assert run.rc == 3 and "internal error" in run.err and len(run.err_lines) == 1


def test_input_type_error_is_both():
    from robokit.errors import InputError, InputTypeError

    e = InputTypeError("x")
    assert isinstance(e, InputError) and isinstance(e, ValueError) and isinstance(e, TypeError)


@pytest.fixture(scope="module")
def puma():
    from robokit.description.loading import load

    return load("puma560")


BAD = {
    "complex": lambda n: np.zeros(n) + 1e-3j,
    "complex zero imaginary": lambda n: np.zeros(n, complex),
    "strings": lambda n: ["0"] * n,
    "string array": lambda n: np.array(["0.1"] * n),
    "booleans": lambda n: [True] * n,
    "objects": lambda n: [None] * n,
    "mixed": lambda n: [0.0] * (n - 1) + ["x"],
    "ragged": lambda n: [[0.0] * n, [0.0]],
}


@pytest.mark.parametrize("kind", sorted(BAD))
def test_robot_methods_refuse_non_real_input_by_name(kind, puma):
    from robokit.errors import InputError

    n = puma.n
    bad = BAD[kind](n)
    z = np.zeros(n)
    calls = {
        "q": [lambda: puma.frame_pose(bad), lambda: puma.jacobian(bad), lambda: puma.crba(bad),
              lambda: puma.gravity_torques(bad)],
        "dq": [lambda: puma.rnea(z, bad, z), lambda: puma.nonlinear_effects(z, bad)],
        "tau": [lambda: puma.aba(z, z, bad)],
    }
    for name, fns in calls.items():
        for fn in fns:
            with pytest.raises(InputError, match=rf"^{name}: "):
                fn()


@pytest.mark.parametrize("kind", ["complex", "strings", "booleans", "objects"])
def test_batched_calls_refuse_non_real_rows(kind, puma):
    from robokit.errors import InputError

    rows = np.array([BAD[kind](puma.n)] * 3, dtype=object if kind == "objects" else None)
    with pytest.raises(InputError, match=r"^q: "):
        puma.frame_pose(rows)


@settings(max_examples=60, derandomize=True, deadline=None)
@given(hnp.arrays(dtype=st.sampled_from([np.float64, np.float32, np.int64, np.int32, np.uint8]),
                  shape=hnp.array_shapes(max_dims=3, max_side=4),
                  elements={"allow_nan": False, "allow_infinity": False}))
def test_as_array_equals_numpy_on_real_input(a):
    """Property: real numeric input is returned unchanged in value (numpy's own float cast is the
    reference), whatever its integer or float dtype."""
    from robokit._arrays import as_array

    out = as_array(a, "x")
    assert out.dtype == np.float64 and np.array_equal(out, a.astype(np.float64))
    assert np.array_equal(as_array(a.tolist(), "x"), a.astype(np.float64))


@settings(max_examples=60, derandomize=True, deadline=None)
@given(hnp.arrays(dtype=st.sampled_from([np.complex128, np.bool_, np.str_, object]), shape=st.integers(1, 5)))
def test_as_array_refuses_every_non_real_dtype(a):
    from robokit._arrays import as_array
    from robokit.errors import InputTypeError

    if a.dtype == object:
        a[0] = "s"
    with pytest.raises(InputTypeError, match="^v: expected"):
        as_array(a, "v")


@pytest.mark.parametrize("value,ok", [(3, True), (np.int64(3), True), (True, False), (np.bool_(False), False),
                                      (3.0, False), ("3", False), (None, False), (-1, False)])
def test_as_int(value, ok):
    from robokit._arrays import as_int
    from robokit.errors import InputError

    if ok:
        assert as_int(value, "k", minimum=0) == 3
    else:
        with pytest.raises(InputError, match="^k: expected an integer"):
            as_int(value, "k", minimum=0)


def test_as_joints_names_robot_and_argument():
    from robokit._arrays import as_joints
    from robokit.errors import InputError

    assert as_joints([1, 2], 2, "dq", "arm").tolist() == [1.0, 2.0]
    with pytest.raises(InputError, match=r"^dq: expected shape \(3,\) for arm, got \(2,\)"):
        as_joints([1, 2], 3, "dq", "arm")
    with pytest.raises(InputError, match=r"^q: expected shape \(N, 2\) for arm"):
        as_joints([1, 2], 2, "q", "arm", batch=True)
    with pytest.raises(InputError, match="NaN"):
        as_joints([[1, np.nan]], 2, "q", "arm", batch=True)


@pytest.mark.parametrize("kw,value", [("max_iterations", True), ("max_restarts", 2.0), ("seed", "1")])
def test_compiled_ik_integer_arguments(kw, value, puma):
    from robokit.errors import InputError
    from robokit.kernels.ik import solve_poe_ik

    p = puma.poe
    args = dict(max_iterations=10, max_restarts=0, seed=0)
    args[kw] = value
    with pytest.raises(InputError, match=rf"^{kw}: expected an integer"):
        solve_poe_ik(p.M, p.Slist, np.eye(4), np.zeros(puma.n), puma.qlim, **args)
