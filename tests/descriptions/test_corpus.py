"""The description corpus (tests/descriptions/corpus.py): every vendored description, every
example-robot-data robot robokit loads and the arms of pybullet_data, through load → FK, J, RNEA,
M, against the format's own engine, to 1e-9 relative. The table is printed at the end of the run.

Each robot is one test (``test_robot_agrees_with_its_engine``), so that the two xdist workers share
the corpus (a few minutes in one test before); each robot's rows are computed once per run and
kept in a folder the workers share (:class:`SharedRows`), where the tests over the whole corpus
read them — the rows ``corpus.run()`` gives, robot by robot, in the same order.
"""
import os
import pickle
import time

import pytest

from tests.descriptions import corpus

pytest.importorskip("pybullet")

CASES = corpus.all_cases()


class SharedRows:
    """``corpus.run_case`` of each case, computed once per test run by whichever process needs it
    first and read from ``folder`` by the others: a process claims a case (a file created
    exclusively) before computing it, another one needing that case waits for the rows file (and
    computes it itself if none comes within ``patience`` seconds: a claimer that died)."""

    def __init__(self, folder, patience=600.0):
        self.folder, self.patience = folder, patience

    def get(self, i):
        done = self.folder / f"{i}.pickle"
        try:
            os.close(os.open(self.folder / f"{i}.claim", os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            deadline = time.monotonic() + self.patience
            while time.monotonic() < deadline:
                if done.exists():
                    return pickle.loads(done.read_bytes())
                time.sleep(0.05)
        rows = corpus.run_case(CASES[i])
        tmp = done.with_suffix(f".{os.getpid()}")
        tmp.write_bytes(pickle.dumps(rows))
        os.replace(tmp, done)
        return rows


@pytest.fixture(scope="session")
def shared_rows(tmp_path_factory):
    """This run's :class:`SharedRows`: under xdist in the folder above the workers' own temporary
    folders (one per run, made by the controller), otherwise in the run's temporary folder."""
    base = tmp_path_factory.getbasetemp()
    folder = (base.parent if os.environ.get("PYTEST_XDIST_WORKER") else base) / "corpus-rows"
    folder.mkdir(exist_ok=True)
    return SharedRows(folder)


def _bad(rows):
    return [f"{r.source} vs {r.engine}: {r.problem or r.errors}" for r in rows
            if not r.ok and not r.known and not r.problem.startswith("skipped")]


@pytest.mark.parametrize("i", range(len(CASES)), ids=[f"{c.fmt}-{c.label}" for c in CASES])
def test_robot_agrees_with_its_engine(shared_rows, i):
    bad = _bad(shared_rows.get(i))
    assert not bad, "\n".join(bad)


@pytest.fixture(scope="module")
def rows(shared_rows):
    rows = [r for i in range(len(CASES)) for r in shared_rows.get(i)]  # = corpus.run()
    text = corpus.header() + "\n" + corpus.table(rows)
    tmp = corpus.TABLE_FILE.with_suffix(f".{os.getpid()}")
    tmp.write_text(text + "\n")
    os.replace(tmp, corpus.TABLE_FILE)
    return rows


def test_every_robot_agrees_with_its_engine(rows):
    bad = _bad(rows)
    assert not bad, "\n".join(bad)
    assert sum(r.ok for r in rows) >= 60  # the corpus is not empty by accident


def test_known_disagreements_are_still_open(rows):
    """A KNOWN entry that agrees now is stale: delete it from corpus.KNOWN."""
    stale = [f"{r.source} vs {r.engine}" for r in rows if r.known and r.ok]
    assert not stale, stale
    sources = {(r.source, r.engine.rstrip("*")) for r in rows}
    assert set(corpus.KNOWN) <= sources


def test_pybullet_zeroes_exactly_the_links_robokit_warns_about(rows):
    """PyBullet's importer replaces an inertia breaking the triangle inequality by zero; robokit keeps
    the file's numbers and warns (PhysicalityWarning) — on the same links, when they move."""
    seen = 0
    for r in rows:
        zeroed = {c.rsplit(": ", 1)[0] for c in r.note.split("; ") if "triangle" in c}
        if zeroed:
            assert zeroed <= set(r.warned), (r.source, zeroed, r.warned)
            seen += 1
    assert seen >= 3  # xArm6 (twice), the two TwoJointRobots


def test_discovery_by_suffix(tmp_path):
    """Files added under tests/data later join by their suffix; macro-only xacro files do not."""
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "arm.urdf").write_text("<robot name='a'/>")
    (tmp_path / "pkg" / "arm.urdf.xacro").write_text("<robot name='a'/>")
    (tmp_path / "pkg" / "macros.xacro").write_text("<robot name='m'/>")
    (tmp_path / "pkg" / "typed.xacro").write_text("<robot name='t'/>")
    (tmp_path / "pkg" / "typed.xacro.corpus.yaml").write_text("- {ur_type: ur5e}\n- {ur_type: ur10e}\n")
    (tmp_path / "pkg" / "scene.xml").write_text("<mujoco/>")
    (tmp_path / "pkg" / "package.xml").write_text("<package><name>pkg</name></package>")
    (tmp_path / "pkg" / "model.sdf").write_text("<sdf/>")
    cases = corpus.vendored_cases(tmp_path)
    got = sorted((c.fmt, c.label) for c in cases)
    assert got == [("MJCF", "scene"), ("SDF", "model"), ("URDF", "arm"), ("xacro", "arm"),
                   ("xacro", "typed ur_type:=ur10e"), ("xacro", "typed ur_type:=ur5e")]
    sdf = [c for c in cases if c.fmt == "SDF"][0]
    assert bool(sdf.skip) is (".sdf" not in __import__("robokit").description.loading.FILE_LOADERS)


def test_a_xacro_package_through_the_xacro_program(tmp_path, monkeypatch):
    """A xacro robot in a package, with an argument and a ``$(find pkg)`` include: robokit's
    expansion against Pinocchio and PyBullet on the xacro program's."""
    pytest.importorskip("xacro")
    pkg = tmp_path / "tiny_description"
    (pkg / "urdf").mkdir(parents=True)
    (pkg / "package.xml").write_text("<package format='3'><name>tiny_description</name></package>")
    (pkg / "urdf" / "link.xacro").write_text(
        '<robot xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:macro name="arm_link" params="name mass length">'
        '<link name="${name}"><inertial><origin xyz="${length/2} 0 0"/><mass value="${mass}"/>'
        '<inertia ixx="${mass*0.001}" iyy="${mass*length*length/12}" izz="${mass*length*length/12}" '
        'ixy="0" ixz="0" iyz="0"/></inertial></link></xacro:macro></robot>')
    (pkg / "urdf" / "tiny.urdf.xacro").write_text(
        '<robot name="tiny" xmlns:xacro="http://www.ros.org/wiki/xacro">'
        '<xacro:arg name="reach" default="0.5"/>'
        '<xacro:include filename="$(find tiny_description)/urdf/link.xacro"/>'
        '<link name="base"/><xacro:arm_link name="l1" mass="2.0" length="$(arg reach)"/>'
        '<xacro:arm_link name="l2" mass="1.0" length="0.4"/><link name="tool"/>'
        '<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><axis xyz="0 0 1"/>'
        '<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
        '<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="$(arg reach) 0 0.1" rpy="0.3 0 0"/>'
        '<axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="1" velocity="1"/></joint>'
        '<joint name="tool_joint" type="fixed"><parent link="l2"/><child link="tool"/><origin xyz="0.4 0 0"/></joint>'
        '</robot>')
    (pkg / "urdf" / "tiny.urdf.xacro.corpus.yaml").write_text("- {}\n- {reach: 0.7}\n")
    monkeypatch.setattr(corpus, "PACKAGE_ROOTS", [tmp_path])
    cases = corpus.vendored_cases(tmp_path)
    assert [c.label for c in cases] == ["tiny", "tiny reach:=0.7"]
    rows = corpus.run(cases)
    assert [r.engine for r in rows] == ["Pinocchio", "PyBullet*"] * 2
    assert rows[1].note == "tool: no <inertial>, 1 kg"  # PyBullet's importer; the world-fixed base is left out
    assert all(r.ok for r in rows), [(r.problem, r.errors) for r in rows]


SDF = """<sdf version='1.6'><model name='arm'><pose>0.5 -1 0.2 0 0 0.7</pose>
<link name='base'><inertial><mass>0</mass><inertia><ixx>0</ixx><iyy>0</iyy><izz>0</izz></inertia></inertial></link>
<link name='l1'><pose>0 0 0.3 0 0 0</pose><inertial><pose>0.1 0.02 0.05 0.1 0.2 0.3</pose><mass>2</mass>
<inertia><ixx>0.02</ixx><ixy>IXY</ixy><ixz>0</ixz><iyy>0.03</iyy><iyz>0</iyz><izz>0.025</izz></inertia></inertial></link>
<joint name='j1' type='revolute'><parent>base</parent><child>l1</child><axis><xyz>0 0 1</xyz>
<limit><lower>-3</lower><upper>3</upper></limit><use_parent_model_frame>0</use_parent_model_frame></axis></joint>
<link name='l2'><pose>0.4 0 0.3 0 0 0</pose><inertial><pose>0.15 0 0 0 0 0</pose><mass>1</mass>
<inertia><ixx>0.004</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial></link>
<joint name='j2' type='revolute'><parent>l1</parent><child>l2</child><axis><xyz>0 1 0</xyz>
<limit><lower>-3</lower><upper>3</upper></limit><use_parent_model_frame>0</use_parent_model_frame></axis></joint>
</model></sdf>"""

URDF_TWIN = """<robot name="arm"><link name="base"/>
<link name="l1"><inertial><origin xyz="0.1 0.02 0.05" rpy="0.1 0.2 0.3"/><mass value="2"/>
<inertia ixx="0.02" ixy="IXY" ixz="0" iyy="0.03" iyz="0" izz="0.025"/></inertial></link>
<link name="l2"><inertial><origin xyz="0.15 0 0"/><mass value="1"/><inertia ixx="0.004" ixy="0" ixz="0" iyy="0.01" iyz="0"
izz="0.01"/></inertial></link>
<joint name="j1" type="revolute"><parent link="base"/><child link="l1"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/><origin xyz="0.4 0 0"/><axis xyz="0 1 0"/>
<limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>"""


@pytest.mark.parametrize("ixy", ["0", "0.001"])
def test_the_sdf_engine_on_a_urdf_twin(tmp_path, ixy):
    """The PyBullet engine of the SDF rows (loadSDF, a model pose turned 0.7 rad, inertial frames
    turned) against robokit on the same arm written as URDF: kinematics always, dynamics when each
    inertia tensor is diagonal in its inertial frame (loadSDF drops tensors; the engine puts the
    file's moments back, which a product of inertia makes impossible)."""
    import warnings

    import robokit

    (tmp_path / "arm.sdf").write_text(SDF.replace("IXY", ixy))
    (tmp_path / "arm.urdf").write_text(URDF_TWIN.replace("IXY", ixy))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        robot = robokit.load(tmp_path / "arm.urdf", "l2")
    engine = corpus.PyBulletEngine(tmp_path / "arm.sdf", robot, sdf=True, in_base=True)  # the twin has no model pose
    try:
        errors = corpus.compare(robot, engine)
    finally:
        engine.close()
    assert set(errors) == ({"FK", "J", "RNEA", "M"} if ixy == "0" else {"FK", "J"})
    assert max(errors.values()) < 1e-12, errors


def test_the_table_and_the_script(capsys):
    """The table names the engine, marks a PyBullet reading with * and a footnote; the script
    (``python -m tests.descriptions.corpus``) prints the header, the table and the count — here on
    one small robot, to keep it quick."""
    only = [c for c in corpus.pybullet_data_cases() if c.source.endswith("TwoJointRobot_wo_fixedJoints.urdf")]
    text = corpus.table(corpus.run(only))
    assert "Pinocchio" in text and "PyBullet*" in text and "[1] pybullet_data/TwoJointRobot" in text
    markdown = corpus.table(corpus.run(only), markdown=True)
    assert markdown.startswith("| robot | format |") and "- [1] " in markdown
    from unittest import mock

    with mock.patch.object(corpus, "all_cases", lambda: only):
        assert corpus.main([]) == 0
    out = capsys.readouterr().out
    assert out.startswith("robokit description corpus, ") and "2 rows, 0 failed" in out


TREE = """<robot name="tree"><link name="base"/>
<link name="a"><inertial><origin xyz="0.1 0 0"/><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.02" iyz="0"
izz="0.02"/></inertial></link>
<link name="b"><inertial><origin xyz="0 0.1 0"/><mass value="2"/><inertia ixx="0.02" ixy="0" ixz="0" iyy="0.01" iyz="0"
izz="0.02"/></inertial></link>
<joint name="ja" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
<limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
<joint name="jb" type="revolute"><parent link="base"/><child link="b"/><origin xyz="0 0 0.2"/><axis xyz="1 0 0"/>
<limit lower="-3" upper="3" effort="1" velocity="1"/></joint></robot>"""


def test_sidecars_choose_tips_and_skip_with_a_reason(tmp_path):
    """A tree without a sidecar fails (discovery drops no robot silently); a sidecar's tips make one row
    each; ``skip:`` shows its reason; an unknown key is refused."""
    for name in ("bare", "tipped", "part"):
        (tmp_path / f"{name}.urdf").write_text(TREE)
    (tmp_path / "tipped.urdf.corpus.yaml").write_text("tip: [a, b]\n")
    (tmp_path / "part.urdf.corpus.yaml").write_text("skip: a part of another robot\n")
    cases = corpus.vendored_cases(tmp_path)
    assert [c.label for c in cases] == ["bare", "part", "tipped → a", "tipped → b"]
    rows = corpus.run(cases, samples=2)
    bare = [r for r in rows if r.label == "bare"]
    assert len(bare) == 1 and "no single longest chain" in bare[0].problem and not bare[0].ok
    assert [r.problem for r in rows if r.label == "part"] == ["skipped: a part of another robot"]
    tipped = [r for r in rows if r.label.startswith("tipped")]
    assert [r.engine for r in tipped] == ["Pinocchio", "PyBullet"] * 2 and all(r.ok for r in tipped)
    (tmp_path / "part.urdf.corpus.yaml").write_text("skipp: typo\n")
    with pytest.raises(ValueError, match="unknown keys"):
        corpus.vendored_cases(tmp_path)


DRAKE_SDF = """<sdf version='1.9' xmlns:drake='http://drake.mit.edu'><model name='arm'>
<link name='base'/>
<link name='l1'><pose relative_to='j1'/><inertial><pose>0.1 0.02 0.05 0.1 0.2 0.3</pose><mass>2</mass>
<inertia><ixx>0.02</ixx><ixy>0.001</ixy><ixz>0</ixz><iyy>0.03</iyy><iyz>0</iyz><izz>0.025</izz></inertia></inertial></link>
<joint name='j1' type='revolute'><pose relative_to='base'>0 0 0.3 0 0 0</pose><parent>base</parent><child>l1</child>
<axis><xyz>0 0 1</xyz><limit><lower>-3</lower><upper>3</upper><effort>10</effort></limit></axis>
<drake:rotor_inertia>0.0002</drake:rotor_inertia><drake:gear_ratio>50</drake:gear_ratio></joint>
<link name='l2'><pose relative_to='j2'/><inertial><pose>0.15 0 0 0 0 0</pose><mass>1</mass>
<inertia><ixx>0.004</ixx><iyy>0.01</iyy><izz>0.01</izz></inertia></inertial></link>
<joint name='j2' type='revolute'><pose relative_to='l1'>0.4 0 0 0 0 0</pose><parent>l1</parent><child>l2</child>
<axis><xyz>0 1 0</xyz><limit><lower>-3</lower><upper>3</upper><effort>EFFORT</effort></limit></axis>
<drake:rotor_inertia>0.0001</drake:rotor_inertia><drake:gear_ratio>100</drake:gear_ratio></joint>
</model></sdf>"""


@pytest.mark.parametrize("effort", ["5", "0"])
def test_an_sdf_against_its_urdf_twin_with_drakes_reflected_inertia(tmp_path, effort):
    """An SDF whose sidecar names a URDF twin: Pinocchio on the twin, plus rotor_inertia · gear_ratio² on
    each joint Drake gives an actuator (none where <effort> is 0), agrees with robokit on the SDF; without
    that armature it would not (the comparison sees it). PyBullet is skipped with the sidecar's reason."""
    (tmp_path / "arm.sdf").write_text(DRAKE_SDF.replace("EFFORT", effort))
    (tmp_path / "arm.urdf").write_text(URDF_TWIN.replace("IXY", "0.001"))
    (tmp_path / "arm.sdf.corpus.yaml").write_text("twin: arm.urdf\nno_pybullet: not this one\n")
    assert corpus.drake_reflected_inertia(tmp_path / "arm.sdf") == pytest.approx(
        {"j1": 0.0002 * 50 ** 2, **({"j2": 0.0001 * 100 ** 2} if effort != "0" else {})})
    cases = [c for c in corpus.vendored_cases(tmp_path) if c.fmt == "SDF"]
    rows = corpus.run(cases, samples=2)
    assert [(r.engine, r.problem) for r in rows] == [("Pinocchio (URDF twin)", ""),
                                                     ("PyBullet", "skipped: not this one")]
    assert rows[0].ok, rows[0].errors
    robot = cases[0].load()
    import pinocchio as pin

    bare = corpus.PinocchioEngine(pin.buildModelFromUrdf(str(tmp_path / "arm.urdf")), robot)
    assert corpus.compare(robot, bare, samples=2)["M"] > 1e-2  # the armature is what makes them agree
