"""Crashes, unbounded work and unclear messages: every hostile file gets one ``robokit:`` line."""
import tracemalloc

import pytest
from hardening_support import (
    PENDULUM_YAML,
    assert_one_line_error,
    joint,
    link,
    pendulum_urdf,
    run_cli,
    tmp_leftovers,
    urdf_text,
)

import robokit
import robokit.cli
from robokit._yaml import MAX_BYTES, MAX_DEPTH


# ----------------------------------------------------------------------------- unbounded work
def test_yaml_400_digit_integer_refused(write, tmp_path, main_cli):
    src = write("digits.yaml", PENDULUM_YAML.replace("a: 0.5,", "a: " + "9" * 400 + ","))
    with pytest.raises(robokit.InputError, match="digits"):
        robokit.DHTable.from_yaml(src)
    out = tmp_path / "out.urdf"
    assert_one_line_error(main_cli("convert", src, "-o", out), "digits.yaml", "line 6")
    assert not out.exists()


def test_yaml_10000_deep_nested_list_refused(write, tmp_path, main_cli):
    src = write("deep.yaml", PENDULUM_YAML + "description: " + "[" * 10000 + "]" * 10000 + "\n")
    with pytest.raises(robokit.InputError, match=f"deeper than {MAX_DEPTH}"):
        robokit.DHTable.from_yaml(src)
    out = tmp_path / "out.urdf"
    assert_one_line_error(main_cli("convert", src, "-o", out), "deep.yaml", "nested")
    assert not out.exists()


def _alias_bomb() -> str:
    """The "billion laughs" in YAML: ten levels of nine aliases each — 9¹⁰ ≈ 3.5e9 strings."""
    lines = ['a0: &a0 ["lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol", "lol"]']
    for i in range(1, 10):
        refs = ", ".join([f"*a{i - 1}"] * 9)
        lines.append(f"a{i}: &a{i} [{refs}]")
    return "\n".join(lines) + "\n"


def test_yaml_alias_bomb_refused_without_expanding(write, tmp_path):
    text = _alias_bomb()
    assert len(text) < 1200
    src = write("bomb.yaml", text)
    tracemalloc.start()
    try:
        with pytest.raises(robokit.InputError, match="alias"):
            robokit.DHTable.from_yaml(src)
        _, peak = tracemalloc.get_traced_memory()
    finally:
        tracemalloc.stop()
    assert peak < 5_000_000  # bytes: the document is never expanded (expanded it is gigabytes)
    out = tmp_path / "out.urdf"
    assert_one_line_error(run_cli("convert", src, "-o", out, timeout=30), "bomb.yaml", "alias")  # 30 s: a hang guard
    assert not out.exists()


def test_yaml_over_the_size_cap_refused(write, tmp_path, main_cli):
    src = write("big.yaml", PENDULUM_YAML + "# " + "x" * MAX_BYTES + "\n")
    with pytest.raises(robokit.InputError, match="too large"):
        robokit.DHTable.from_yaml(src)
    out = tmp_path / "out.urdf"
    assert_one_line_error(main_cli("convert", src, "-o", out), "big.yaml", "too large")
    assert not out.exists()


@pytest.mark.parametrize("kind", ["no_joint", "fixed_only"])
def test_zero_joint_urdf_refused_on_load_and_dh_conversion(kind, write, tmp_path, main_cli):
    if kind == "no_joint":
        text = urdf_text(links=[link("base", mass=1.0)], name="rock")
    else:
        text = urdf_text(links=[link("base"), link("top", mass=1.0)], joints=[joint("bolt", "base", "top", "fixed")],
                         name="rock")
    src = write(f"{kind}.urdf", text)
    with pytest.raises(robokit.InputError, match="no moving joint"):
        robokit.load(src)
    for out in (None, tmp_path / "rock.yaml", tmp_path / "rock.json"):
        args = ["convert", src] + (["-o", out] if out else [])
        assert_one_line_error(main_cli(*args), f"{kind}.urdf", "no moving joint")
    assert sorted(p.name for p in tmp_path.iterdir()) == [f"{kind}.urdf"]


@pytest.mark.parametrize("exc_type", [TypeError, KeyError, AttributeError])
def test_bug_in_robokit_reported_as_internal_error_exit_3(exc_type, monkeypatch, write, tmp_path, main_cli):
    from robokit.description.dh import DHTable

    def broken(*args, **kwargs):
        raise exc_type("a bug planted by the test")

    monkeypatch.setattr(DHTable, "from_yaml", classmethod(lambda cls, *a, **k: broken()))
    src = write("pendulum.yaml", PENDULUM_YAML)
    out = tmp_path / "out.urdf"
    r = main_cli("convert", src, "-o", out)
    line = assert_one_line_error(r, exc_type.__name__, rc=3)
    assert "internal error" in line and "please report" in line and "--debug" in line
    assert not out.exists()
    r = main_cli("--debug", "convert", src, "-o", out)
    assert r.rc == 3
    assert "Traceback" in r.err and "a bug planted by the test" in r.err
    assert not out.exists()


def test_value_error_from_a_dependency_is_internal_not_bad_input(monkeypatch, write, tmp_path, main_cli):
    # a ValueError raised inside numpy (not a robokit check) is robokit's bug to report
    import numpy as np

    from robokit.description import urdf_gen

    monkeypatch.setattr(urdf_gen, "urdf_from_dh", lambda table: str(np.array([1, 2]).reshape(3)))
    src = write("pendulum.yaml", PENDULUM_YAML)
    r = main_cli("convert", src, "-o", tmp_path / "out.urdf")
    assert_one_line_error(r, "ValueError", rc=3)


# ----------------------------------------------------------------------------- messages
MALFORMED_URDF = {
    "missing_parent": (lambda t: t.replace('<parent link="base"/>', '<parent link="nowhere"/>'), ["'nowhere'"]),
    "bad_xml": (lambda t: t.replace("</robot>", ""), ["XML"]),
    "unknown_joint_type": (lambda t: t.replace('type="revolute"', 'type="hinge"'), ["'shoulder'", "'hinge'"]),
    # these once passed robokit's checks and failed inside urdfdom; robokit's URDF reader names them now
    "bad_effort_on_continuous": (lambda t: t.replace('type="revolute"', 'type="continuous"').replace(
        'lower="-3" upper="3" effort="10"', 'effort="abc"'), ["'shoulder'", "effort", "expected a finite number"]),
    "bad_damping": (lambda t: t.replace("</joint>", '<dynamics damping="xyz"/></joint>', 1),
                    ["'shoulder'", "damping", "expected a finite number"]),
    "not_a_robot": (lambda t: "<sdf><model/></sdf>", ["<robot>"]),
    "empty_file": (lambda t: "", ["XML"]),
}


@pytest.mark.parametrize("case", sorted(MALFORMED_URDF))
def test_malformed_urdf_gives_exactly_one_stderr_line(case, write, tmp_path):
    mutate, names = MALFORMED_URDF[case]
    src = write(f"{case}.urdf", mutate(pendulum_urdf()))
    out = tmp_path / "out.json"
    r = run_cli("convert", src, "-o", out)
    assert_one_line_error(r, f"{case}.urdf", *names)
    assert len(r.err.splitlines()) == 1, r.err  # urdfdom's own "Error:" lines never reach stderr
    assert r.out == ""
    assert not out.exists() and tmp_leftovers(tmp_path) == []


@pytest.mark.parametrize("suffix", ["urdf", "yaml"])
def test_non_utf8_file_error_names_the_file(suffix, write, tmp_path, main_cli):
    text = pendulum_urdf() if suffix == "urdf" else PENDULUM_YAML
    src = write(f"latin1.{suffix}", text.replace("pendulum", "pend\u00fclum").encode("latin-1"))
    out = tmp_path / ("out.json" if suffix == "urdf" else "out.urdf")
    assert_one_line_error(main_cli("convert", src, "-o", out), f"latin1.{suffix}", "UTF-8")
    assert not out.exists()


def test_duplicate_yaml_key_refused_with_its_line(write, main_cli):
    src = write("dup.yaml", PENDULUM_YAML + "gravity: [0, 0, 9.81]\n")
    with pytest.raises(robokit.InputError) as ei:
        robokit.DHTable.from_yaml(src)
    msg = str(ei.value)
    assert "dup.yaml" in msg and "duplicate key 'gravity'" in msg and "line 3" in msg and "line 8" in msg
    assert_one_line_error(main_cli("convert", src, "-o", src.with_suffix(".urdf")), "dup.yaml", "'gravity'")


def test_duplicate_yaml_key_inside_a_link_refused(write):
    src = write("dup_link.yaml", PENDULUM_YAML.replace("joint: R,", "joint: R, a: 1,"))
    with pytest.raises(robokit.InputError, match=r"duplicate key 'a'.*line 6"):
        robokit.DHTable.from_yaml(src)


@pytest.mark.parametrize("what", ["link", "joint"])
def test_duplicate_urdf_link_or_joint_name_refused(what, write, tmp_path, main_cli):
    if what == "link":
        text = pendulum_urdf().replace('<link name="tip"></link>', '<link name="tip"></link><link name="tip"></link>')
    else:
        text = urdf_text(links=[link("base"), link("a", mass=1.0), link("b", mass=1.0)],
                         joints=[joint("hinge", "base", "a"), joint("hinge", "a", "b", xyz="1 0 0")])
    src = write(f"dup_{what}.urdf", text)
    out = tmp_path / "out.json"
    line = assert_one_line_error(main_cli("convert", src, "-o", out), f"dup_{what}.urdf",
                                 "'tip'" if what == "link" else "'hinge'")
    assert "twice" in line
    assert not out.exists()


# a NUL cannot be written in XML 1.0 at all (&#0; is not well-formed); DEL, C1 and escaped
# whitespace can, and are refused as names
URDF_NAMES = {"nul": "sh&#0;oulder", "escape": "sh&#x1b;oulder", "delete": "sh&#x7f;oulder",
              "c1_control": "sh&#x85;oulder", "tab": "sh&#9;oulder", "newline": "sh&#10;oulder"}


@pytest.mark.parametrize("case", sorted(URDF_NAMES))
def test_control_character_in_urdf_name_refused(case, write, tmp_path, main_cli):
    src = write(f"name_{case}.urdf", pendulum_urdf().replace('name="shoulder"', f'name="{URDF_NAMES[case]}"'))
    out = tmp_path / "out.json"
    line = assert_one_line_error(main_cli("convert", src, "-o", out), f"name_{case}.urdf")
    assert ("printable name" in line) or ("not well-formed XML" in line and case in ("nul", "escape"))
    assert not out.exists()


@pytest.mark.parametrize("where,text", [
    ("robot", PENDULUM_YAML.replace("name: pendulum", 'name: "pen\\0dulum"')),
    ("robot", PENDULUM_YAML.replace("name: pendulum", 'name: "pen\\x1bdulum"')),
    ("link", PENDULUM_YAML.replace("joint: R,", 'joint: R, name: "elbow\\0",')),
    ("link", PENDULUM_YAML.replace("joint: R,", 'joint: R, name: "elbow\\u0085",')),
])
def test_control_character_in_yaml_name_refused(where, text, write, tmp_path, main_cli):
    src = write("names.yaml", text)
    with pytest.raises(robokit.InputError, match="printable"):
        robokit.DHTable.from_yaml(src)
    out = tmp_path / "out.urdf"
    assert_one_line_error(main_cli("convert", src, "-o", out), "names.yaml", "'name'",
                          *(["link 1"] if where == "link" else []))
    assert not out.exists()


def test_unicode_names_are_fine(write):
    src = write("unicode.urdf", pendulum_urdf().replace('name="shoulder"', 'name="schulter_ü_肩"'))
    robot = robokit.load(src)
    assert list(robot.joint_names) == ["schulter_ü_肩"]
