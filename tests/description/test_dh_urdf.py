"""DH tables, the DH → URDF generator and the shipped models, against Pinocchio.

Independent references: Pinocchio's FK/CRBA/gravity on the generated URDF versus the DH
product, a Lagrangian mass matrix assembled directly from the DH table's link-frame
inertias (finite-difference Jacobians), and the Lecture 7 closed form for the 2-link arm.
"""
import logging

import numpy as np
import pinocchio as pin
import pytest

import robokit
from robokit.description.dh import DHTable, dh_transform
from robokit.description.models import model_path, models_dir
from robokit.description.urdf_gen import urdf_from_dh



def pin_model(table):
    model = pin.buildModelFromXML(urdf_from_dh(table))
    model.gravity.linear = np.asarray(table.gravity, float)
    return model, model.createData()


def fk_errors(table, n_samples, rng):
    model, data = pin_model(table)
    ids = [model.getFrameId(f"dh_{i}") for i in range(table.n + 1)]
    tool = model.getFrameId("tool")
    worst = 0.0
    for _ in range(n_samples):
        q = rng.uniform(table.qlim[:, 0], table.qlim[:, 1])
        pin.framesForwardKinematics(model, data, q)
        F = table.frames(q)
        for i, fid in enumerate(ids):
            worst = max(worst, np.abs(data.oMf[fid].homogeneous - F[i]).max())
        worst = max(worst, np.abs(data.oMf[tool].homogeneous - table.fk(q)).max())
    return worst


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_shipped_fk_matches_pinocchio(name):
    table = DHTable.from_yaml(model_path(name))
    assert fk_errors(table, 200, np.random.default_rng(0)) < 1e-12


@pytest.mark.parametrize("convention", ["standard", "modified"])
def test_random_tables_with_prismatic_joints(convention, random_dh_table):
    rng = np.random.default_rng(1 if convention == "standard" else 2)
    for k in range(4):
        table = random_dh_table(rng, 6, convention, prismatic=(2,) if k % 2 else (0, 4))
        assert fk_errors(table, 200, rng) < 1e-12


def lagrangian_M_and_g(table, q, h=1e-6):
    """M(q) = Σ mᵢ Jvᵢᵀ Jvᵢ + Jωᵢᵀ Rᵢ Iᵢ Rᵢᵀ Jωᵢ and g(q) = ∂V/∂q, from the DH table alone.

    Jacobians by central differences of the link-frame poses (DH products), so this is an
    independent computation of the dynamics the URDF should encode.
    """
    n = table.n
    grav = np.asarray(table.gravity)

    def bodies(qq):
        F = table.frames(qq)
        out = []
        for i, l in enumerate(table.links):
            T = F[i + 1]
            out.append((T[:3, :3], T[:3, :3] @ l.com + T[:3, 3]))
        return out

    def potential(qq):
        return -sum(l.mass * grav @ pc for l, (_, pc) in zip(table.links, bodies(qq)))

    M = np.zeros((n, n))
    base = bodies(q)
    Jv = [np.zeros((3, n)) for _ in range(n)]
    Jw = [np.zeros((3, n)) for _ in range(n)]
    for j in range(n):
        dq = np.zeros(n)
        dq[j] = h
        plus, minus = bodies(q + dq), bodies(q - dq)
        for i in range(n):
            Jv[i][:, j] = (plus[i][1] - minus[i][1]) / (2 * h)
            dR = (plus[i][0] - minus[i][0]) / (2 * h)
            W = dR @ base[i][0].T  # [ω] for unit rate of joint j
            Jw[i][:, j] = [W[2, 1], W[0, 2], W[1, 0]]
    for i, l in enumerate(table.links):
        R = base[i][0]
        M += l.mass * Jv[i].T @ Jv[i] + Jw[i].T @ R @ l.inertia_matrix @ R.T @ Jw[i]
    g = np.array([(potential(q + h * e) - potential(q - h * e)) / (2 * h) for e in np.eye(n)])
    return M, g


@pytest.mark.parametrize("which", ["puma560", "rrr", "random_standard", "random_modified"])
def test_inertia_transfer_against_lagrangian(which, random_dh_table):
    rng = np.random.default_rng(5)
    if which.startswith("random"):
        table = random_dh_table(rng, 5, which.split("_")[1], prismatic=(1,))
    else:
        table = DHTable.from_yaml(model_path(which))
    model, data = pin_model(table)
    for _ in range(10):
        q = rng.uniform(table.qlim[:, 0], table.qlim[:, 1])
        M_ref, g_ref = lagrangian_M_and_g(table, q)
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        g = pin.computeGeneralizedGravity(model, data, q)
        assert np.abs(M - M_ref).max() < 1e-7 * max(1.0, np.abs(M_ref).max())
        assert np.abs(g - g_ref).max() < 1e-6 * max(1.0, np.abs(g_ref).max())


def test_twolink_closed_form_lecture7():
    table = DHTable.from_yaml(model_path("twolink"))
    l1, l2 = table.links[0].a, table.links[1].a
    m1, m2 = table.links[0].mass, table.links[1].mass
    g0 = 9.81
    model, data = pin_model(table)
    rng = np.random.default_rng(6)
    for _ in range(50):
        q1, q2 = q = rng.uniform(-np.pi, np.pi, 2)
        c1, c2, c12 = np.cos(q1), np.cos(q2), np.cos(q1 + q2)
        M_ref = np.array([[l2**2 * m2 + 2 * l1 * l2 * m2 * c2 + l1**2 * (m1 + m2), l2**2 * m2 + l1 * l2 * m2 * c2],
                          [l2**2 * m2 + l1 * l2 * m2 * c2, l2**2 * m2]])
        G_ref = np.array([m2 * l2 * g0 * c12 + (m1 + m2) * l1 * g0 * c1, m2 * l2 * g0 * c12])
        M = pin.crba(model, data, q)
        M = np.triu(M) + np.triu(M, 1).T
        # tolerances relative to the quantity's scale (G is tens of N·m)
        assert np.abs(M - M_ref).max() <= 1e-12 * max(1.0, np.abs(M_ref).max())
        assert np.abs(pin.computeGeneralizedGravity(model, data, q) - G_ref).max() <= 1e-12 * max(1.0, np.abs(G_ref).max())


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_committed_urdf_is_regenerated_exactly(name):
    table = DHTable.from_yaml(model_path(name))
    assert (models_dir() / f"{name}.urdf").read_text() == urdf_from_dh(table)


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_yourdfpy_loads_without_warnings(name, caplog):
    import yourdfpy

    with caplog.at_level(logging.WARNING):
        urdf = yourdfpy.URDF.load(str(models_dir() / f"{name}.urdf"))
    assert not [r for r in caplog.records if r.levelno >= logging.WARNING]
    assert urdf.validate()
    assert {f"dh_{i}" for i in range(DHTable.from_yaml(model_path(name)).n + 1)} <= set(urdf.link_map)
    assert "tool" in urdf.link_map and "base_link" in urdf.link_map


@pytest.mark.parametrize("name", ["twolink", "rrr", "puma560"])
def test_yaml_round_trip(name, tmp_path):
    table = DHTable.from_yaml(model_path(name))
    for unit in ("deg", "rad"):
        path = tmp_path / f"{name}_{unit}.yaml"
        table.save(path, angle_unit=unit)
        again = DHTable.from_yaml(path)
        q = np.random.default_rng(0).uniform(-1, 1, table.n)
        assert np.allclose(again.frames(q), table.frames(q), atol=1e-14, rtol=0)
        for a, b in zip(again.links, table.links):
            assert a.joint == b.joint and np.isclose(a.mass, b.mass) and np.allclose(a.inertia, b.inertia)
            assert np.allclose(a.com, b.com) and np.isclose(a.G, b.G) and np.allclose(a.Tc, b.Tc)


def test_dh_transform_definitions():
    a, al, d, th = 0.3, 0.7, 0.2, -1.1

    def rz(t):
        T = np.eye(4)
        T[:2, :2] = [[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]
        return T

    def rx(t):
        T = np.eye(4)
        T[1:3, 1:3] = [[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]
        return T

    def tr(x, y, z):
        T = np.eye(4)
        T[:3, 3] = [x, y, z]
        return T

    assert np.allclose(dh_transform(a, al, d, th, "standard"), rz(th) @ tr(0, 0, d) @ tr(a, 0, 0) @ rx(al))
    assert np.allclose(dh_transform(a, al, d, th, "modified"), rx(al) @ tr(a, 0, 0) @ rz(th) @ tr(0, 0, d))
    with pytest.raises(ValueError, match="convention"):
        dh_transform(a, al, d, th, "craig")


BASE = """name: bad
convention: standard
angle_unit: deg
links:
  - {joint: R, a: 0.1, alpha: 90, d: 0.2, theta: 0, mass: 1.0, com: [0, 0, 0], inertia: [0.1, 0.1, 0.1, 0, 0, 0]}
  - LINK2
"""
GOOD2 = "{joint: R, a: 0.3, alpha: 0, d: 0, theta: 0}"
BAD_FILES = [
    ("missing key", BASE.replace("LINK2", "{joint: R, a: 0.3, alpha: 0, d: 0}"), ["link 2", "theta"]),
    ("unknown key", BASE.replace("LINK2", "{joint: R, a: 0.3, alpha: 0, d: 0, theta: 0, lenght: 2}"), ["link 2", "lenght"]),
    ("unknown top key", BASE.replace("LINK2", GOOD2) + "gravitty: [0, 0, -9.81]\n", ["gravitty"]),
    ("wrong joint type", BASE.replace("LINK2", "{joint: S, a: 0.3, alpha: 0, d: 0, theta: 0}"), ["link 2", "joint"]),
    ("negative mass", BASE.replace("LINK2", "{joint: R, a: 0.3, alpha: 0, d: 0, theta: 0, mass: -1}"), ["link 2", "mass"]),
    ("non-PD inertia", BASE.replace("LINK2", "{joint: R, a: 0.3, alpha: 0, d: 0, theta: 0, mass: 1, inertia: [1, -2, 1, 0, 0, 0]}"),
     ["link 2", "inertia"]),
    ("wrong list length", BASE.replace("LINK2", "{joint: R, a: 0.3, alpha: 0, d: 0, theta: 0, com: [0, 0]}"), ["link 2", "com"]),
    ("bad qlim", BASE.replace("LINK2", "{joint: R, a: 0.3, alpha: 0, d: 0, theta: 0, qlim: [10, -10]}"), ["link 2", "qlim"]),
    ("non-number", BASE.replace("LINK2", "{joint: R, a: abc, alpha: 0, d: 0, theta: 0}"), ["link 2", "'a'"]),
    ("bad convention", BASE.replace("LINK2", GOOD2).replace("standard", "craig"), ["convention"]),
    ("bad unit", BASE.replace("LINK2", GOOD2).replace("deg", "grad"), ["angle_unit"]),
    ("not yaml", "name: [unclosed\n", ["not valid YAML"]),
    ("no links", "name: x\nlinks: []\n", ["links"]),
]


@pytest.mark.parametrize("label,text,needles", BAD_FILES, ids=[b[0] for b in BAD_FILES])
def test_bad_files_name_file_link_and_key(label, text, needles, tmp_path):
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(robokit.InputError) as info:
        DHTable.from_yaml(path)
    msg = str(info.value)
    assert str(path) in msg
    for needle in needles:
        assert needle in msg, msg
    assert "\n" not in msg


def test_good_base_file_loads(tmp_path):
    path = tmp_path / "ok.yaml"
    path.write_text(BASE.replace("LINK2", GOOD2))
    t = DHTable.from_yaml(path)
    assert t.n == 2 and np.isclose(t.links[0].alpha, np.pi / 2)
