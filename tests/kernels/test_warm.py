"""``python -m robokit.kernels``: what it would compile, and its argument check (the compiling
itself is what every other kernel test exercises)."""
import pytest

from robokit.kernels import _jit
from robokit.kernels.warm import MODULES, kernels, main


def test_lists_every_signatured_kernel_of_a_module():
    listed = kernels(["poe", "dynamics"])
    assert ("poe", "fkin_space") in listed and ("dynamics", "forward_dynamics_crba_batch") in listed
    assert len(listed) == len(_jit._KERNELS["poe"]) + len(_jit._KERNELS["dynamics"])
    assert all(m in MODULES for m, _ in listed)
    assert ("poe", "exp_screw") not in listed  # helpers compile inside the kernels that call them


def test_unknown_module_is_refused(capsys):
    with pytest.raises(SystemExit) as info:
        main(["nope"])
    assert info.value.code == 2
    assert "unknown kernel module" in capsys.readouterr().err
