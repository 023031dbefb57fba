"""A xacro file is data. No expression in it ever runs code, the environment is never
copied into an output, includes and YAML files are confined, and expansion work is bounded.

Each payload would create a marker file if it ran; the first test shows that the same
payload *does* run under the plain ``xacro`` package (so these tests can fail)."""
import subprocess
import sys

import numpy as np
import pytest

import hardening_support as hs
import limited_cli as r2

# A sandbox escape that gets through xacro's own filter (the dunders sit inside a lambda body).
GADGET = ("(lambda: [c for c in ().__class__.__base__.__subclasses__() if c.__name__ == 'catch_warnings'][0]()"
          "._module.__builtins__['open']('{mark}', 'w').close())()")


def _payloads(mark):
    """(label, expression) pairs: each would create ``mark`` (or run other code) if evaluated."""
    m = str(mark)
    return [
        ("lambda gadget", GADGET.format(mark=m)),
        ("comprehension", f"[().__class__ for x in [1]]"),
        ("dunder attribute", "''.__class__.__mro__[1].__subclasses__()"),
        ("import", f"__import__('os').system('touch {m}')"),
        ("open", f"open('{m}', 'w')"),
        ("getattr", "getattr(1, 'real')"),
        ("type", "python.type(1)"),
        ("vars", "python.vars()"),
        ("exec name", f"exec('open(\"{m}\",\"w\")')"),
        ("generator bomb", "sum(1 for a in range(99999) for b in range(99999))"),
        ("percent-format bomb", "'%99999999d' % 1"),
        ("walrus", "(y := 3)"),
        ("keyword lambda", "sorted([1], key=lambda x: x)"),
        ("huge power", "9 ** 9 ** 9"),
        ("huge repetition", "'a' * 10 ** 9"),
        ("join bomb", "''.join([str(list(range(10000)))] * 10000)"),
        ("replace bomb", "('x' * 50000).replace('', 'y' * 50000)"),
        ("round digits", "round(1, -1000000000)"),
        ("list sum", "sum([[1]] * 100, [])"),
        ("format method attribute", "'x'.format.__globals__"),
        ("math attribute escape", "math.__loader__"),
        ("xacro helper attribute", "xacro.load_yaml.__globals__"),
    ]


def _where(expr):
    """Places an expression can sit in a xacro file (attribute, text, property, condition,
    macro default, macro-produced, $(eval))."""
    e = expr.replace('"', "&quot;")
    return {
        "attribute": f'<link name="${{{e}}}"/>',
        "text": f'<link name="t"><visual><geometry><box size="1 1 1"/></geometry></visual>'
                f'<!-- c --><x>${{{e}}}</x></link>',
        "property": f'<xacro:property name="p" value="${{{e}}}"/><link name="${{p}}"/>',
        "if": f'<xacro:if value="${{{e}}}"><link name="i"/></xacro:if>',
        "macro default": f'<xacro:macro name="m" params="a:=${{{e}}}"><link name="${{a}}"/></xacro:macro><xacro:m/>',
        "macro produced": f'<xacro:macro name="m" params="a"><link name="${{a}}"/></xacro:macro><xacro:m a="${{{e}}}"/>',
    }


def test_the_gadget_runs_under_plain_xacro(tmp_path):
    """The reference: xacro alone runs the payload (so the refusals below are robokit's doing)."""
    mark = tmp_path / "ran"
    src = tmp_path / "g.urdf.xacro"
    src.write_text(r2.xacro_robot(f'<link name="${{{GADGET.format(mark=mark)}}}"/>'))
    code = f"import xacro; xacro.process_file({str(src)!r})"
    subprocess.run([sys.executable, "-c", code], capture_output=True, timeout=60, check=False)
    assert mark.exists()


@pytest.mark.parametrize("label", [p[0] for p in _payloads("M")])
def test_no_expression_runs_code(label, tmp_path, main_cli):
    mark = tmp_path / "ran"
    expr = dict(_payloads(mark))[label]
    places = _where(expr)
    for place, snippet in places.items():
        src = tmp_path / f"{place.replace(' ', '_')}.urdf.xacro"
        src.write_text(r2.xacro_robot(snippet))
        run = main_cli("convert", src, "-o", tmp_path / "out.json")
        line = hs.assert_one_line_error(run, src.name)
        assert "refused" in line, (place, line)
        assert not mark.exists(), place
        assert not (tmp_path / "out.json").exists()


@pytest.mark.parametrize("expr", ["[x.__class__ for x in [1]]", "arg.__globals__", "[lambda: 1]",
                                  "dirname.__code__", "env"])
def test_eval_substitution_is_checked_too(expr, tmp_path, main_cli):
    """$(eval ...) cannot hold a parenthesis (xacro's lexer ends it there), but everything else
    goes through the same interpreter."""
    src = tmp_path / "e.urdf.xacro"
    src.write_text(r2.xacro_robot(f'<link name="$(eval {expr})"/>'))
    run = main_cli("convert", src, "-o", tmp_path / "out.json")
    line = hs.assert_one_line_error(run, src.name)
    assert "refused" in line or "function, not a value" in line, line


def test_gadget_through_a_subprocess_with_limits(tmp_path):
    mark = tmp_path / "ran"
    src = tmp_path / "g.urdf.xacro"
    src.write_text(r2.xacro_robot(f'<link name="${{{GADGET.format(mark=mark)}}}"/>'))
    run = r2.run_limited("view", src, "-o", tmp_path / "v.html")
    hs.assert_one_line_error(run, "g.urdf.xacro", "refused")
    assert not mark.exists() and not (tmp_path / "v.html").exists()


def test_what_a_description_needs_still_evaluates(tmp_path):
    """Benign expressions: robokit's evaluator gives exactly what the plain xacro package gives
    (an independent implementation) on properties, math, macros, defaults, conditionals, strings,
    lists, dicts, YAML and $(eval)."""
    from robokit.description.xacro_files import expand_xacro

    (tmp_path / "p.yaml").write_text("arm: {l1: 0.4, names: [a, b], deg: !degrees 90, mm: !millimeters 2 * 5}\n")
    body = """
<xacro:property name="l" value="0.25"/>
<xacro:property name="d" value="${dict([('k', 1)]) if False else dict([('k', 2)])}"/>
<xacro:property name="y" value="${xacro.load_yaml('p.yaml')}"/>
<xacro:property name="lst" value="${[1, 2.5, -3]}"/>
<xacro:arg name="pre" default="p_"/>
<xacro:macro name="seg" params="n parent ln:=${l * 2} *geom">
  <link name="$(arg pre)${n}"><visual><xacro:insert_block name="geom"/></visual>
  <inertial><mass value="${max(1, ln) + lst[1]}"/>
  <inertia ixx="${radians(10)}" iyy="${math.pi / 100}" izz="${sin(pi / 6) ** 2}" ixy="0" iyz="0" ixz="0"/></inertial></link>
  <joint name="j_${n.upper()}" type="revolute"><parent link="${parent}"/><child link="$(arg pre)${n}"/>
  <axis xyz="0 0 1"/><limit lower="${-pi if ln > 0 else 0}" upper="${round(pi, 3)}" effort="${d['k']}"
  velocity="${y['arm']['l1'] * 10 + y.arm.deg + y.arm.mm}"/></joint>
</xacro:macro>
<xacro:seg n="${y.arm.names[0]}" parent="base"><box size="1 1 1"/></xacro:seg>
<xacro:if value="${l > 0.1 and not False}">
  <xacro:seg n="b" parent="$(arg pre)a" ln="$(eval 1 + 2)"><sphere radius="${python.abs(-0.1)}"/></xacro:seg>
</xacro:if>
<xacro:unless value="${len(lst) == 3}"><link name="never"/></xacro:unless>
"""
    src = tmp_path / "ok.urdf.xacro"
    src.write_text(r2.xacro_robot(body))
    ours = expand_xacro(src)
    code = ("import xacro, xml.etree.ElementTree as ET\n"
            f"doc = xacro.process_file({str(src)!r})\n"
            "print(doc.toxml())")
    ref = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, check=True,
                         cwd=tmp_path).stdout
    import xml.etree.ElementTree as ET

    def canon(text):
        root = ET.fromstring(text)
        return [(e.tag, sorted(e.attrib.items())) for e in root.iter()]

    assert canon(ours) == canon(ref)
    assert "never" not in ours and 'name="p_a"' in ours and 'name="j_B"' in ours


def test_environment_is_never_copied(tmp_path, main_cli, monkeypatch):
    monkeypatch.setenv("ROBOKIT_SECRET", "s3cr3t-value")
    src = tmp_path / "env.urdf.xacro"
    src.write_text(r2.xacro_robot('<link name="x$(env ROBOKIT_SECRET)"/>'))
    run = main_cli("convert", src, "-o", tmp_path / "o.json")
    hs.assert_one_line_error(run, "env.urdf.xacro", "$(env ROBOKIT_SECRET)", "--xacro-arg")
    assert "s3cr3t" not in run.err

    from robokit.description.xacro_files import expand_xacro

    opt = tmp_path / "opt.urdf.xacro"
    opt.write_text(r2.xacro_robot('<xacro:arg name="q" default="z"/><link name="x$(optenv ROBOKIT_SECRET dflt)"/>'
                                  '<link name="y${xacro.arg(\'q\')}"/>'))
    with pytest.warns(Warning, match="optenv ROBOKIT_SECRET"):
        text = expand_xacro(opt)
    assert "s3cr3t" not in text and 'name="xdflt"' in text
    # the user passes the value: it is used (env and optenv alike)
    assert 'name="xmine"' in expand_xacro(opt, {"ROBOKIT_SECRET": "mine"})
    assert 'name="xmine"' in expand_xacro(src, {"ROBOKIT_SECRET": "mine"})


@pytest.mark.parametrize("kind", ["absolute include", "include ../", "glob include", "load_yaml outside",
                                  "symlinked include"])
def test_files_outside_the_package_are_not_read(kind, tmp_path, main_cli):
    pkg = tmp_path / "pkg"
    pkg.mkdir()
    outside = tmp_path / "outside"
    outside.mkdir()
    (outside / "inc.xacro").write_text(r2.xacro_robot('<link name="leak"/>'))
    (outside / "p.yaml").write_text("a: 1\n")
    (pkg / "link.xacro").symlink_to(outside / "inc.xacro")
    body = {
        "absolute include": f'<xacro:include filename="{outside / "inc.xacro"}"/>',
        "include ../": '<xacro:include filename="../outside/inc.xacro"/>',
        "glob include": '<xacro:include filename="../outside/*.xacro"/>',
        "load_yaml outside": '<xacro:property name="y" value="${xacro.load_yaml(\'/etc/hostname\')}"/>',
        "symlinked include": '<xacro:include filename="link.xacro"/>',
    }[kind]
    src = pkg / "r.urdf.xacro"
    src.write_text(r2.xacro_robot(body))
    run = main_cli("convert", src, "-o", tmp_path / "o.json")
    hs.assert_one_line_error(run, "r.urdf.xacro", "outside")


def test_expansion_work_is_bounded(tmp_path):
    """A macro calling itself twice 30 levels deep (2**30 links if expanded), one calling itself
    forever, a file including itself: each stops with one line (in one limited subprocess)."""
    cases = {
        "doubling": ('<xacro:macro name="d" params="n"><xacro:if value="${n > 0}"><xacro:d n="${n-1}"/>'
                     '<xacro:d n="${n-1}"/></xacro:if><xacro:unless value="${n > 0}"><link name="x"/></xacro:unless>'
                     '</xacro:macro><xacro:d n="30"/>', "more than 20000 elements"),
        "recursion": ('<xacro:macro name="r" params="n"><xacro:r n="${n+1}"/></xacro:macro><xacro:r n="0"/>',
                      "nested deeper than 100"),
        "loop": ('<xacro:include filename="loop.urdf.xacro"/>', "includes nested deeper than 20"),
    }
    for name, (body, _) in cases.items():
        (tmp_path / f"{name}.urdf.xacro").write_text(r2.xacro_robot(body))
    runs = r2.run_many([["convert", tmp_path / f"{name}.urdf.xacro", "-o", tmp_path / "o.json"] for name in cases])
    for (name, (_, want)), run in zip(cases.items(), runs):
        hs.assert_one_line_error(run, f"{name}.urdf.xacro", want)


def test_expression_size_is_bounded(tmp_path, main_cli):
    src = tmp_path / "long.urdf.xacro"
    src.write_text(r2.xacro_robot('<link name="${' + "+".join(["1"] * 6000) + '}"/>'))
    run = main_cli("convert", src, "-o", tmp_path / "o.json")
    hs.assert_one_line_error(run, "long.urdf.xacro", "refused")


def test_evaluator_agrees_with_python_on_arithmetic():
    """Property: on the arithmetic a description needs, the whitelist interpreter equals Python."""
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from robokit.description.xacro_safety import evaluate

    num = st.one_of(st.integers(-50, 50).map(str), st.floats(-10, 10, allow_nan=False).map(lambda v: f"{v!r}"))
    ops = st.sampled_from(["+", "-", "*", "/", "<", "==", " and ", " or "])

    @st.composite
    def expr(draw, depth=0):
        if depth > 3 or draw(st.booleans()):
            return draw(num)
        kind = draw(st.integers(0, 3))
        a, b = draw(expr(depth + 1)), draw(expr(depth + 1))
        if kind == 0:
            return f"({a}{draw(ops)}{b})"
        if kind == 1:
            return f"({a} if {b} else -{a})"
        if kind == 2:
            return f"{draw(st.sampled_from(['abs', 'max', 'min']))}({a}, {b})" if False else f"abs({a})"
        return f"sin({a}) + cos({b}) * pi"

    import math

    @settings(max_examples=150, derandomize=True, deadline=None)
    @given(expr())
    def check(e):
        try:
            want = eval(e, {"__builtins__": {}, "abs": abs, "sin": math.sin, "cos": math.cos, "pi": math.pi})
        except ZeroDivisionError:
            with pytest.raises(ZeroDivisionError):
                evaluate(e, {})
            return
        got = evaluate(e, {})
        assert got == want or (isinstance(want, float) and np.isclose(got, want, rtol=0, atol=0))

    check()


def test_fuzzed_expressions_only_ever_give_plain_data():
    """Property: for token soup mixing dunders, builtins, lambdas, calls, attributes and
    subscripts, the interpreter returns plain data (numbers, strings, lists, tuples, dicts) or
    raises one of the expected errors — never a function, class, module or other object."""
    from hypothesis import given, settings
    from hypothesis import strategies as st

    from robokit.description.xacro_safety import evaluate

    tokens = st.sampled_from([
        "(", ")", "[", "]", ".", ",", ":", " ", "+", "*", "**", "-", "if", "else", "lambda", "for", "in", "not",
        "__class__", "__mro__", "__subclasses__", "__globals__", "__builtins__", "__import__", "mro",
        "open", "eval", "exec", "getattr", "type", "vars", "print", "python", "math", "xacro", "sin", "pi",
        "len", "str", "list", "dict", "range", "sorted", "p", "q", "''", "'a'", "0", "1", "2.5", "9", "x",
        "upper", "join", "split", "format", "real", "imag", "load_yaml", "arg", "dotify", "abs_filename",
    ])
    data = (int, float, bool, str, list, tuple, dict, type(None))

    @settings(max_examples=300, derandomize=True, deadline=None)
    @given(st.lists(tokens, min_size=1, max_size=14))
    def check(parts):
        text = "".join(parts)
        try:
            v = evaluate(text, {"p": 2, "q": "s"})
        except (SyntaxError, NameError, ArithmeticError, TypeError, ValueError, KeyError, IndexError,
                AttributeError):  # UnsafeXacro is an InputError (a ValueError)
            return
        assert isinstance(v, data), (text, type(v))

    check()
