"""A xacro file is data, and what it makes robokit build is bounded before it is built.

* Every operation of robokit's expression interpreter that can grow (``str.join``, repetition,
  concatenation, powers, shifts, ``%``/``format``/f-strings, ``str()``, padding, ``list``/
  ``sorted``/``zip``/``dict``/``range``, comprehensions, ``math.factorial``…) estimates its
  result from its operands and is refused, with the operation named, before anything large is
  allocated: checked in a subprocess with a 1 GB address-space limit (``('a'*60000).join('b'*30000)``
  alone is a 1.8 GB string), where the refusal must name the operation.
* Every xacro construct robokit now expands has a hostile twin — a huge default, a macro that
  recurses through a default, a YAML alias bomb, ``$(arg)`` doubling, a macro body of comments
  cloned by every call, a regular expression from the file — refused with one line and exit 2 by
  the CLI in a subprocess limited to 3 GB (a safety net and a hang guard, never a timing); its
  benign twin expands to what the xacro program gives.
"""
from __future__ import annotations

import json
import resource
import subprocess
import sys
import warnings
import xml.etree.ElementTree as ET

import pytest

import robokit
from robokit.description.xacro_files import expand_xacro

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'
GB = 1 << 30


def _limited(memory):
    def limit():  # pragma: no cover - runs in the child
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
    return limit


def _python(code, args, memory, timeout=120):
    """``python -c code json(args)`` under an address-space limit; its stdout as JSON."""
    run = subprocess.run([sys.executable, "-c", code, json.dumps(args)], capture_output=True, text=True,
                         timeout=timeout, check=False, preexec_fn=_limited(memory))
    assert run.returncode == 0, run.stderr[-3000:]
    return json.loads(run.stdout)


# --------------------------------------------------------------------------- growing operations
#: (expression, words the refusal must contain): one per operation that can grow.
GROWING = [
    ("('a' * 60000).join('b' * 30000)", "str.join()"),  # 1.8 GB if built
    ("('a' * 99999).join('b' * 99999)", "str.join()"),  # 10 GB: was a MemoryError with no reason
    ("('-' * 20000).join(['x' * 30000, 'y' * 30000, 'z' * 30000])", "str.join()"),
    ("'x' * 60000 + 'y' * 60000", "a concatenation"),
    ("[0] * 10 ** 6", "a repetition"),
    ("(1, 2) * 10 ** 9", "a repetition"),
    ("9 ** 99999", "an integer power"),
    ("1 << 10 ** 7", "a left shift"),
    ("(2 ** 4000) * (2 ** 4000)", "an integer product"),
    ("'%099999999d' % 1", "format width"),
    ("'%.5000f' % 1.5", "format precision"),
    ("'%s%50000s' % ('x' * 60000, 'y')", "a %-formatted string"),
    ("'{:>999999999}'.format(1)", "format width"),
    ("'{0}{0}{0}'.format('x' * 40000)", "a formatted string"),
    ("str(['\\x00' * 30000] * 3)", "str()"),
    ("python.repr('\\x00' * 30000)", "repr()"),
    ("'x'.center(10 ** 9)", "str.center()"),
    ("'7'.zfill(10 ** 9)", "str.zfill()"),
    ("'\\t'.expandtabs(10 ** 9)", "str.expandtabs()"),
    ("('ab' * 40000).replace('a', 'xyz')", "str.replace()"),
    ("('a b ' * 25000).split()", "str.split()"),
    ("list('x' * 70000)", "list()"),
    ("sorted('x' * 70000)", "sorted()"),
    ("python.zip('x' * 40000, 'y' * 40000)", "zip()"),
    ("list(python.enumerate('x' * 40000))", "enumerate()"),
    ("dict(a='x' * 60000, b='y' * 60000)", "dict()"),
    ("range(10 ** 9)", "range()"),
    ("['x' * 1000 for i in range(200)]", "a list comprehension"),
    ("dict((i, 'x' * 1000) for i in range(200))", "a generator expression"),
    ("[0 for a in range(40000) for b in range(40000) if 0]", "evaluation steps"),
    ("math.factorial(10 ** 5)", "math.factorial()"),
    ("math.comb(10 ** 6, 5 * 10 ** 5)", "math.comb()"),
    ("math.prod(range(1, 5000))", "math.prod()"),
]

_EVALUATE = r"""
import json, sys
from robokit.description.xacro_safety import evaluate
out = []
for expr in json.loads(sys.argv[1]):
    try:
        value = evaluate(expr, {})
        out.append("VALUE " + str(value)[:80])
    except MemoryError:
        out.append("MemoryError")
    except Exception as exc:
        out.append(type(exc).__name__ + ": " + str(exc))
sys.stdout.write(json.dumps(out))
"""


@pytest.fixture(scope="module")
def growing_results():
    """Each GROWING expression evaluated in one subprocess limited to 1 GB of address space."""
    return dict(zip([e for e, _ in GROWING], _python(_EVALUATE, [e for e, _ in GROWING], GB)))


@pytest.mark.parametrize("expr, why", GROWING, ids=[e[:40] for e, _ in GROWING])
def test_growing_operations_are_refused_before_they_run(expr, why, growing_results):
    got = growing_results[expr]
    assert got.startswith("UnsafeXacro: ") and "refused" in got and why in got, got


def test_the_same_operations_within_bounds_give_python_values():
    """The benign side of each: the same operations on small operands give what Python gives."""
    from robokit.description.xacro_safety import evaluate

    for expr, want in [("('a' * 6).join('b' * 3)", "babab" if False else "baaaaaabaaaaaab"),
                       ("'%05d|%-3s|%.2f' % (7, 'x', 3.14159)", "00007|x  |3.14"), ("'{:>4}'.format(1)", "   1"),
                       ("str(['x'] * 2)", "['x', 'x']"), ("'x'.center(5, '*')", "**x**"), ("'7'.zfill(3)", "007"),
                       ("dict(a='x' * 2)", {"a": "xx"}), ("[x for x in range(3) for y in 'ab']", [0, 0, 1, 1, 2, 2]),
                       ("math.factorial(20)", 2432902008176640000), ("1 << 64", 2 ** 64), ("9 ** 99", 9 ** 99)]:
        assert evaluate(expr, {}) == want, expr


# --------------------------------------------------------------------------- hostile twins
def _doc(body):
    """A robot whose one joint makes it loadable, with ``body`` in it."""
    return (f'<?xml version="1.0"?>\n<robot name="r" {NS}>\n<link name="base"/>\n{body}\n'
            '<link name="l1"/><joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>'
            '<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>\n</robot>\n')


def _doubling_args(levels):
    return "".join(f'<xacro:arg name="a{i + 1}" default="$(arg a{i})$(arg a{i})"/>' for i in range(levels))


def _yaml_bomb(levels):
    lines = ["a0: &a0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]"]
    lines += [f"a{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * 10) + "]" for i in range(1, levels)]
    return "\n".join(lines) + "\n"


def _merge_bomb(levels):
    lines = ["m0: &m0 {k0: 0}"]
    lines += [f"m{i}: &m{i} {{<<: [*m{i - 1}, *m{i - 1}], k{i}: {i}}}" for i in range(1, levels)]
    return "\n".join(lines) + "\n"


_GROW = ('<xacro:macro name="grow" params="s:=^|x n:=^|{n}"><xacro:property name="s" value="${{s + s}}" '
         'lazy_eval="false"/><xacro:property name="n" value="${{n - 1}}" lazy_eval="false"/>'
         '<xacro:if value="${{n != 0}}"><xacro:grow/></xacro:if><xacro:unless value="${{n != 0}}">'
         '<g s="${{len(s)}}"/></xacro:unless></xacro:macro><xacro:grow/>')

#: name -> (benign body, what it expands to (element tag, attribute, value), hostile body, refusal words)
TWINS = {
    "macro default": (
        '<xacro:macro name="m" params="p:=${\'ab\' * 3}"><d p="${p}"/></xacro:macro><xacro:m/>', ("d", "p", "ababab"),
        '<xacro:macro name="m" params="p:=${\'ab\' * 10**8}"><d p="${p}"/></xacro:macro><xacro:m/>', "a repetition"),
    "macro recursing through a default": (
        _GROW.format(n=3), ("g", "s", "8"), _GROW.format(n=-1), "a concatenation"),
    "yaml aliases": ("<xacro:property name=\"y\" value=\"${xacro.load_yaml('ok.yaml')}\"/><d p=\"${y.link.mass}\"/>",
                     ("d", "p", "3.5"),
                     "<xacro:property name=\"y\" value=\"${xacro.load_yaml('bomb.yaml')}\"/><d p=\"${y.a0}\"/>",
                     "an alias bomb"),
    "yaml merge keys": ("<xacro:property name=\"y\" value=\"${xacro.load_yaml('ok.yaml')}\"/><d p=\"${y.link.color}\"/>",
                        ("d", "p", "red"),
                        "<xacro:property name=\"y\" value=\"${xacro.load_yaml('merge.yaml')}\"/><d p=\"${y.m0}\"/>",
                        "an alias bomb"),
    "yaml recursive alias": ("<d p=\"${xacro.load_yaml('ok.yaml').base.mass}\"/>", ("d", "p", "2.0"),
                             "<d p=\"${xacro.load_yaml('loop.yaml')}\"/>", "recursive structure"),
    "arguments from arguments": ('<xacro:arg name="a0" default="x"/>' + _doubling_args(3) + '<d p="$(arg a3)"/>',
                                 ("d", "p", "x" * 8),
                                 '<xacro:arg name="a0" default="xxxxxxxxxx"/>' + _doubling_args(40) + '<d p="$(arg a40)"/>',
                                 "the substitutions in one attribute or text give more than"),
    "dict with keywords": ('<d p="${dict(a=1, b=2)[\'b\']}"/>', ("d", "p", "2"),
                           '<d p="${dict(a=\'x\' * 60000, b=\'y\' * 60000)}"/>', "dict()"),
    "comprehension": ('<d p="${[i * i for i in range(4)]}"/>', ("d", "p", "[0, 1, 4, 9]"),
                      '<d p="${[0 for a in range(40000) for b in range(40000) if 0]}"/>', "evaluation steps"),
    "%-formatting": ("<d p=\"${'%s_%02d' % ('j', 3)}\"/>", ("d", "p", "j_03"),
                     "<d p=\"${'%0999999999d' % 3}\"/>", "format width"),
    "str.format": ('<xacro:property name="f" value="{0}_{1}"/><d p="${f.format(\'a\', 2)}"/>', ("d", "p", "a_2"),
                   '<xacro:property name="f" value="{0.__class__.__mro__}"/><d p="${f.format(1)}"/>',
                   "only positions and names"),
    "xacro.tokenize": ("<d p=\"${xacro.tokenize('a,b;c')}\"/>", ("d", "p", "['a', 'b', 'c']"),
                       "<d p=\"${xacro.tokenize('x' * 40 + 'y', 'a](x+x+)+z[b')}\"/>", "a plain set of characters"),
    "macro body copies": ('<xacro:macro name="c"><!-- ' + "c" * 100 + ' --><k/></xacro:macro><xacro:c/><xacro:c/>',
                          ("k", "", None),
                          '<xacro:macro name="c"><!-- ' + "c" * 1_000_000 + ' --><k/></xacro:macro>'
                          + "<xacro:c/>" * 5000, "the expansion produced more than"),
    "substitutions in one text": ('<xacro:property name="a" value="${\'x\' * 10}"/><d p="${a}${a}"/>',
                                  ("d", "p", "x" * 20),
                                  '<xacro:property name="a" value="${\'x\' * 99999}"/><d p="' + "${a}" * 3000 + '"/>',
                                  "the substitutions in one attribute or text give more than"),
}

_YAML = {
    "ok.yaml": "base: &base {mass: 2.0, color: red}\nlink: {<<: *base, mass: 3.5}\n",
    "bomb.yaml": _yaml_bomb(10),  # 10**10 values if expanded
    "merge.yaml": _merge_bomb(40),  # 2**40 merged pairs if flattened
    "loop.yaml": "a: &a [1, *a]\n",
}

_CLI = r"""
import contextlib, io, json, sys, warnings
warnings.simplefilter("always")
import robokit.cli
out = []
for argv in json.loads(sys.argv[1]):
    err = io.StringIO()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            rc = robokit.cli.main(argv)
        except MemoryError:
            rc = "MemoryError"
    out.append([rc, err.getvalue()])
sys.stdout.write(json.dumps(out))
"""


def _files(tmp, twin):
    for name, text in _YAML.items():
        (tmp / name).write_text(text)
    paths = []
    for k, body in enumerate(twin):
        p = tmp / f"{k}.urdf.xacro"
        p.write_text(_doc(body))
        paths.append(p)
    return paths


@pytest.fixture(scope="module")
def hostile_runs(tmp_path_factory):
    """Every hostile twin through ``robokit convert`` in one subprocess limited to 3 GB."""
    tmp = tmp_path_factory.mktemp("hostile")
    for name, text in _YAML.items():
        (tmp / name).write_text(text)
    argvs = {}
    for i, (name, (_, _, hostile, _)) in enumerate(TWINS.items()):
        p = tmp / f"hostile{i}.urdf.xacro"
        p.write_text(_doc(hostile))
        argvs[name] = ["convert", str(p), "-o", str(tmp / f"out{i}.json")]
    runs = _python(_CLI, list(argvs.values()), 3 * GB, timeout=300)
    return tmp, dict(zip(argvs, runs))


@pytest.mark.parametrize("name", list(TWINS))
def test_hostile_twin_is_refused_in_one_line(name, hostile_runs):
    tmp, runs = hostile_runs
    rc, err = runs[name]
    lines = err.strip().splitlines()
    assert rc == 2 and lines and lines[-1].startswith("robokit: error:"), (rc, err[-2000:])
    assert [line for line in lines if not line.startswith("robokit: note:")] == lines[-1:], err[-2000:]
    assert TWINS[name][3] in lines[-1], lines[-1]
    assert len(lines[-1]) < 600
    assert not list(tmp.glob("out*.json"))


@pytest.mark.parametrize("name", list(TWINS))
def test_benign_twin_expands_as_the_xacro_program_does(name, tmp_path):
    benign, (tag, attr, want), _, _ = TWINS[name]
    for fname, text in _YAML.items():
        (tmp_path / fname).write_text(text)
    src = tmp_path / "benign.urdf.xacro"
    src.write_text(_doc(benign))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        ours = ET.fromstring(expand_xacro(src))
    ref_code = ("import sys, xacro; sys.stdout.write(xacro.process_file(sys.argv[1]).toxml())")
    ref = subprocess.run([sys.executable, "-c", ref_code, str(src)], capture_output=True, text=True, timeout=120,
                         check=True, cwd=tmp_path).stdout
    ref_root = ET.fromstring(ref)
    assert [(e.tag, e.attrib) for e in ours.iter()] == [(e.tag, e.attrib) for e in ref_root.iter()]
    if want is not None:
        assert ours.find(tag).get(attr) == want
