"""clang's strictest warnings on the generated files: `clang -std=c99 -Weverything -Werror` with the
one `-Wno-` flag docs/codegen.md justifies (C99 declarations after statements, the generated code's
`const` intermediates), on the files of several arms and methods, double and float32."""
import subprocess

import numpy as np
import pytest

import robokit
from shared_robots import gen3_lite, robot as shared_robot
from robokit.codegen import generate_c, write_c
from robokit.description.dh import DHLink, DHTable

from .test_codegen import calibrated_arm, jaco2_table

#: The flags docs/codegen.md ("Warnings") documents; at most three -Wno- flags, each justified there.
CLANG_FLAGS = ("-std=c99", "-Weverything", "-Werror", "-Wno-declaration-after-statement")


def quartic_arm():
    """A spherical wrist with a1 != 0 and sin(alpha1) != 0: Pieper's quartic and its numerical fallback."""
    a, alpha, d = [0.1, 0.35, 0.05, 0, 0, 0], [1.2, 0.3, -np.pi / 2, np.pi / 2, -np.pi / 2, 0], [0.3, 0.1, 0.05,
                                                                                               0.4, 0, 0.1]
    return DHTable("quartic", "standard", tuple(DHLink("R", a=a[i], alpha=alpha[i], d=d[i]) for i in range(6)))


def prismatic_arm():
    """A Stanford-type arm (joint 3 prismatic) with a spherical wrist."""
    kinds = "RRPRRR"
    alpha, d = [-np.pi / 2, np.pi / 2, 0, -np.pi / 2, np.pi / 2, 0], [0.4, 0.15, 0.0, 0, 0, 0.1]
    return DHTable("stanford", "standard", tuple(
        DHLink(kinds[i], a=0.0, alpha=alpha[i], d=d[i], qlim=np.array([0.1, 1.0]) if kinds[i] == "P" else None)
        for i in range(6)))


ARMS = ["twolink", "rrr", "puma560", "ur5", "panda", "kinova", "jaco2", "quartic", "stanford", "calibrated_puma560",
        "calibrated_ur5", "gen3_lite"]


def _load(name):
    if name.startswith("calibrated_"):  # the polished closed form of robokit.ik.calibrated (both structures)
        return calibrated_arm(name[len("calibrated_"):], {"puma560": 1, "ur5": 2}[name[len("calibrated_"):]])
    if name == "gen3_lite":  # the general 6R method finished on the arm (NAME_g6_arm_finish, NAME_cal_polish)
        return gen3_lite()
    table = {"jaco2": jaco2_table, "quartic": quartic_arm, "stanford": prismatic_arm}.get(name)
    return robokit.load(table()) if table else shared_robot(name)


@pytest.mark.parametrize("float32", [False, True], ids=["double", "float"])
def test_clang_weverything(clang, tmp_path, float32):
    failures = []
    for name in ARMS:
        src = generate_c(_load(name), float32=float32)
        folder = tmp_path / name
        _, c_path = write_c(src, folder)
        res = subprocess.run([clang, *CLANG_FLAGS, "-fsyntax-only", str(c_path)], capture_output=True, text=True)
        if res.returncode != 0:
            failures.append(f"{name}: {res.stderr[:1500]}")
    assert not failures, "\n".join(failures)


def test_clang_flags_are_the_documented_ones():
    from pathlib import Path

    doc = (Path(__file__).resolve().parents[2] / "docs" / "codegen.md").read_text()
    no = [f for f in CLANG_FLAGS if f.startswith("-Wno-")]
    assert len(no) <= 3
    assert " ".join(CLANG_FLAGS) in doc and all(f"`{f}`" in doc for f in no)
