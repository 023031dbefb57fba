"""Every robot file is read bounded — regular files only, bytes counted as read, no DTD or entities,
bounded nesting and element count, at most 128 joints — before anything recursive or Pinocchio
sees it. Each case runs the CLI in a subprocess with a 3 GB address-space limit and a hang guard
(a safety net, not a timing)."""
import os

import numpy as np
import pytest

import hardening_support as hs
import limited_cli as r2


SUFFIXES = [".urdf", ".yaml", ".urdf.xacro", ".xml"]


def test_endless_device_is_refused_by_bytes_read(tmp_path):
    """/dev/zero has stat size 0: the cap must hold on the bytes read (every format)."""
    srcs = []
    for suffix in SUFFIXES:
        src = tmp_path / f"zero{suffix}"
        src.symlink_to("/dev/zero")
        srcs.append(src)
    runs = r2.run_many([["view", src, "-o", tmp_path / "o.html"] for src in srcs])
    for src, run in zip(srcs, runs):
        hs.assert_one_line_error(run, src.name, "device")


def test_fifo_does_not_block(tmp_path):
    srcs = []
    for suffix in SUFFIXES:
        src = tmp_path / f"f{suffix}"
        os.mkfifo(src)
        srcs.append(src)
    runs = r2.run_many([["view", src, "-o", tmp_path / "o.html"] for src in srcs], timeout=60)
    for src, run in zip(srcs, runs):
        hs.assert_one_line_error(run, src.name, "FIFO")


def test_growing_file_cap_holds_on_bytes_read(tmp_path):
    """The bounded reader stops at max_bytes + 1 bytes whatever stat says (a sparse 30 MB URDF)."""
    from robokit._io import read_input_bytes
    from robokit.errors import InputError

    big = tmp_path / "big.urdf"
    with open(big, "wb") as f:
        f.truncate(30 << 20)
    with pytest.raises(InputError, match="too large"):
        read_input_bytes(big, 20 << 20, "a URDF file")
    assert read_input_bytes(big, 40 << 20, "a URDF file") == b"\0" * (30 << 20)


BOMB_DTD = ('<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY a "aaaaaaaaaa"><!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">'
            '<!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;&b;&b;"><!ENTITY d "&c;&c;&c;&c;&c;&c;&c;&c;&c;&c;">'
            '<!ENTITY e "&d;&d;&d;&d;&d;&d;&d;&d;&d;&d;"><!ENTITY f "&e;&e;&e;&e;&e;&e;&e;&e;&e;&e;">'
            '<!ENTITY g "&f;&f;&f;&f;&f;&f;&f;&f;&f;&f;"><!ENTITY h "&g;&g;&g;&g;&g;&g;&g;&g;&g;&g;">]>\n')


EXTERNAL = '<?xml version="1.0"?>\n<!DOCTYPE r [<!ENTITY x SYSTEM "file:///etc/passwd">]>\n'


ROOTS = {".urdf": '<robot name="&h;"><link name="a"/></robot>',
         ".urdf.xacro": '<robot name="&h;"><link name="a"/></robot>',
         ".xml": '<mujoco model="&h;"><worldbody><body name="b"><joint name="j"/><geom size="0.1"/></body></worldbody>'
                 '</mujoco>'}


def test_dtd_and_entities_are_refused(tmp_path):
    cases = []
    for suffix, root in ROOTS.items():
        for prolog in ("bomb", "external"):
            text = BOMB_DTD + root if prolog == "bomb" else EXTERNAL + root.replace("&h;", "&x;")
            src = tmp_path / f"e_{prolog}{suffix}"
            src.write_text(text)
            cases.append(src)
    runs = r2.run_many([["convert", src, "-o", tmp_path / "o.json"] for src in cases])
    for src, run in zip(cases, runs):
        hs.assert_one_line_error(run, src.name, "DOCTYPE")
        assert "root:" not in run.out + run.err  # /etc/passwd never echoed


def _deep_mjcf(depth):
    opens = "".join(f'<body name="b{i}">' for i in range(depth))
    return f'<mujoco><worldbody>{opens}<geom size="0.1"/>{"</body>" * depth}</worldbody></mujoco>'


def _nested_visuals(depth):
    return (f'<robot name="r"><link name="a">{"<visual>" * depth}{"</visual>" * depth}</link></robot>')


def test_deep_nesting_and_size_are_refused_before_any_recursive_parser(tmp_path):
    cases = {"deep.xml": (_deep_mjcf(20_000), "nested deeper than 512"),
             "vis.urdf": (_nested_visuals(50_000), "nested deeper than 512"),
             "vis.urdf.xacro": (_nested_visuals(30_000), "nested deeper than 512"),
             "many.urdf": ('<robot name="r"><link name="a">' + "<x/>" * 250_000 + "</link></robot>",
                           "more than 200000 elements")}
    for name, (text, _) in cases.items():
        (tmp_path / name).write_text(text)
    runs = r2.run_many([["view", tmp_path / name, "-o", tmp_path / "v.html"] for name in cases])
    for (name, (_, want)), run in zip(cases.items(), runs):
        hs.assert_one_line_error(run, name, want)
    assert not (tmp_path / "v.html").exists()


def _dh_yaml(n):
    rows = "\n".join(f"  - {{joint: R, a: 0.1, alpha: 0, d: 0, theta: 0, qlim: [-3, 3]}}" for _ in range(n))
    return f"name: snake\nconvention: standard\nlinks:\n{rows}\n"


def _mjcf_chain(n):
    opens = "".join(f'<body name="b{i}" pos="0 0 0.1"><joint name="j{i}" axis="0 0 1"/>'
                    f'<geom type="sphere" size="0.01" mass="1"/>' for i in range(n))
    return f'<mujoco model="m"><worldbody>{opens}{"</body>" * n}</worldbody></mujoco>'


def _xacro_chain(n):
    """n calls of one segment macro (not recursive: xacro nests macros at most 100 deep)."""
    calls = "".join(f'<xacro:seg i="{i}" parent="{"base" if i == 0 else f"l{i - 1}"}"/>' for i in range(n))
    return r2.xacro_robot(
        '<xacro:macro name="seg" params="i parent">'
        '<link name="l${i}"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" iyz="0" ixz="0"/>'
        '</inertial></link>'
        '<joint name="j${i}" type="revolute"><parent link="${parent}"/>'
        '<child link="l${i}"/><axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>'
        '</xacro:macro>' + calls)


MAKERS = {"snake.urdf": lambda n: hs.urdf_text(links=[hs.link("base")], joints=[]).replace(
              "</robot>", r2.arm_links(n) + "</robot>"),
          "snake.yaml": _dh_yaml, "snake.xml": _mjcf_chain, "snake.urdf.xacro": _xacro_chain}


def test_joint_limit(tmp_path):
    for name, make in MAKERS.items():
        (tmp_path / name).write_text(make(129))
    runs = r2.run_many([["view", tmp_path / name, "-o", tmp_path / "v.html"] for name in MAKERS])
    for name, run in zip(MAKERS, runs):
        hs.assert_one_line_error(run, name, "129", "at most 128 joints")
    assert not (tmp_path / "v.html").exists()


def test_joint_limit_is_inclusive(tmp_path):
    """128 joints load, and the chain's FK is the closed form (all joints about z, 0.1 m apart)."""
    from robokit.description.loading import load

    src = tmp_path / "snake.yaml"
    src.write_text(_dh_yaml(128))
    robot = load(src)
    assert robot.n == 128
    q = np.full(128, 2 * np.pi / 128)
    T = robot.frame_pose(q)
    # planar chain of equal links turning by 2π/128 each: its tip returns to the base (a closed polygon)
    assert np.allclose(T[:3, 3], 0, atol=1e-9)
