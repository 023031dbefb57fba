"""URDF text written by hand for the tests of names, physicality and unmodelled elements.

``urdf(links, joints, extra)`` with ``link(...)`` and ``joint(...)`` pieces: every number is a
literal in the text, so a test's expected value comes from what it wrote, not from robokit.
"""


def inertial(mass, ixx=0.01, iyy=0.01, izz=0.01, ixy=0.0, ixz=0.0, iyz=0.0, xyz="0 0 0", rpy="0 0 0"):
    return (f'<inertial><origin xyz="{xyz}" rpy="{rpy}"/><mass value="{mass}"/>'
            f'<inertia ixx="{ixx}" iyy="{iyy}" izz="{izz}" ixy="{ixy}" ixz="{ixz}" iyz="{iyz}"/></inertial>')


def sphere(radius, xyz="0 0 0", kind="collision"):
    return f'<{kind}><origin xyz="{xyz}"/><geometry><sphere radius="{radius}"/></geometry></{kind}>'


def link(name, body="", extra=""):
    """A ``<link>``; ``body`` is its inertial/visual/collision text, ``extra`` anything else inside."""
    return f'<link name="{name}">{body}{extra}</link>'


def joint(name, parent, child, kind="revolute", xyz="0 0 0", rpy="0 0 0", axis="0 0 1", lower=-3.0, upper=3.0,
          extra=""):
    limit = f'<limit lower="{lower}" upper="{upper}" effort="10" velocity="2"/>' if kind in ("revolute", "prismatic") else ""
    ax = f'<axis xyz="{axis}"/>' if kind != "fixed" else ""
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}" rpy="{rpy}"/>{ax}{limit}{extra}</joint>')


def urdf(links, joints, extra="", name="arm"):
    return f'<?xml version="1.0"?>\n<robot name="{name}">\n' + "\n".join([*links, *joints, extra]) + "\n</robot>\n"


def arm(bodies=None, extra_links=(), extra_joints=(), extra=""):
    """A three-joint arm base → l1 → l2 → l3 (z, y, y axes; 0.3 m, 0.4 m, 0.3 m), with the
    inertial text of each link from ``bodies`` (default: physical ones)."""
    bodies = {"base": inertial(2.0, 0.02, 0.02, 0.02), "l1": inertial(1.5, 0.01, 0.01, 0.005, xyz="0 0 0.15"),
              "l2": inertial(1.0, 0.002, 0.015, 0.015, xyz="0.2 0 0"),
              "l3": inertial(0.5, 0.001, 0.004, 0.004, xyz="0.15 0 0"), **(bodies or {})}
    links = [link(n, bodies[n]) for n in ("base", "l1", "l2", "l3")] + list(extra_links)
    joints = [joint("j1", "base", "l1", axis="0 0 1"), joint("j2", "l1", "l2", xyz="0 0 0.3", axis="0 1 0"),
              joint("j3", "l2", "l3", xyz="0.4 0 0", axis="0 1 0")] + list(extra_joints)
    return urdf(links, joints, extra)
