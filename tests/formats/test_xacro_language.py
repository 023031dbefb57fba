"""The xacro language, construct by construct: robokit's expansion (its own expression
interpreter inside the xacro package's XML machinery) equals the xacro program's own expansion
(plain ``xacro.process_file``, Python's ``eval``, run in a subprocess) on small documents written
for each construct — macro parameter defaults, blocks, property scopes, YAML as PyYAML reads it,
``dict``/``list`` with keywords, comprehensions, formatting, ``math``, string methods,
``$(arg)`` in every place. One subprocess expands all the documents."""
from __future__ import annotations

import json
import subprocess
import sys
import warnings
import xml.etree.ElementTree as ET

import pytest

import robokit
from robokit.description.xacro_files import expand_xacro

NS = 'xmlns:xacro="http://www.ros.org/wiki/xacro"'

#: Files every document may include or load.
AUX = {
    "settings.yaml": """\
arm: {l1: 0.4, names: [a, b], ok: yes, small: 1e-3, dotted: 1.0e-3, octal: 017, under: 1_000, sexa: 1:30}
base: &base {mass: 2.0, color: red}
link: {<<: *base, mass: 3.5}
twice: {k: 1, k: 2}
list: [{val: {x: 1}}, {val: {x: 2}}]
units: {deg: !degrees 90, mm: !millimeters 2 * 5, rad: !radians pi / 2}
""",
    "A.xacro": f"""<robot {NS}>
  <xacro:property name="prop" value="A"/>
  <xacro:macro name="set"><xacro:property name="prop" value="macro" scope="global"/></xacro:macro>
  <xacro:macro name="mark" params="x"><mark from="A" x="${{x}}" p="${{prop}}"/></xacro:macro>
</robot>""",
    "part.xacro": f'<robot {NS}><part name="$(arg who)" p="${{outer}}"/></robot>',
    "glob_1.xacro": f'<robot {NS}><g n="1"/></robot>',
    "glob_2.xacro": f'<robot {NS}><g n="2"/></robot>',
}

#: name -> (body inside <robot>, xacro arguments)
DOCS: dict[str, tuple[str, dict[str, str]]] = {
    "macro defaults": ("""
<xacro:property name="outer" value="o"/>
<xacro:property name="fwd" value="from_caller"/>
<xacro:macro name="m" params="a b:=2 c:=${outer * 3} d:='x y' e:=^ fwd:=^|dflt f:=^|${pi/2} g:=$(arg n)">
  <m a="${a}" b="${b}" c="${c}" d="${d}" e="${e}" fwd="${fwd}" f="${f}" g="${g}"/>
</xacro:macro>
<xacro:property name="e" value="E"/>
<xacro:m a="1"/>
<xacro:m a="2" b="5" c="c" d="z" e="e2" fwd="given" f="0" g="g"/>
<xacro:macro name="n" params="e:=^ fwd:=^|dflt f:=^|${pi/2}"><n e="${e}" fwd="${fwd}" f="${f}"/></xacro:macro>
<xacro:macro name="scope" params=""><xacro:property name="fwd" value="inner"/><xacro:n/></xacro:macro>
<xacro:scope/>
<xacro:macro name="bools" params="t:=true f:=false p:=${pi} u:=${True} z:=0">
  <b t="${t}" f="${f}" p="${p}" u="${u}" z="${z}" ok="${not f and t}"/>
</xacro:macro>
<xacro:bools/>
""", {"n": "7"}),
    "blocks": ("""
<xacro:macro name="b" params="*first **rest name">
  <wrap name="${name}"><xacro:insert_block name="first"/><xacro:insert_block name="first"/></wrap>
  <all><xacro:insert_block name="rest"/></all>
</xacro:macro>
<xacro:b name="n"><origin xyz="1 2 3"/><rest><a/><b x="${1+1}"/></rest></xacro:b>
<xacro:property name="blk"><box size="1 1 1"/></xacro:property>
<geom><xacro:insert_block name="blk"/></geom>
""", {}),
    "property scopes": ("""
<xacro:property name="p" value="global"/>
<xacro:property name="d" default="first"/><xacro:property name="d" default="second"/>
<xacro:macro name="inner"><xacro:property name="p" value="parent_set" scope="parent"/>
  <xacro:property name="g" value="${p}_global" scope="global"/></xacro:macro>
<xacro:macro name="outer"><xacro:property name="p" value="local"/><before p="${p}"/><xacro:inner/><after p="${p}"/>
</xacro:macro>
<xacro:outer/>
<top p="${p}" g="${g}" d="${d}"/>
<xacro:property name="lazy" value="${later * 2}"/><xacro:property name="later" value="21"/><l v="${lazy}"/>
<xacro:property name="eager" value="${p}" lazy_eval="false"/><xacro:property name="p" value="changed"/>
<e v="${eager}" p="${p}"/>
<xacro:property name="gone" value="1"/><xacro:property name="gone" remove="true"/>
<r v="${'gone' in python.dir() if False else 1}"/>
""", {}),
    "includes: namespaced, optional, globbed": ("""
<xacro:property name="prop" value="root"/>
<xacro:include filename="A.xacro" ns="A"/>
<root prop="${prop}" a="${A.prop}"/>
<xacro:A.mark x="${A.prop * 2}"/>
<xacro:A.set/>
<after prop="${prop}"/>
<xacro:include filename="not_there.xacro" optional="true"/>
<xacro:include filename="glob_*.xacro"/>
""", {}),
    "yaml as pyyaml reads it": ("""
<xacro:property name="y" value="${xacro.load_yaml('settings.yaml')}"/>
<a l1="${y.arm.l1 * 2}" n0="${y.arm.names[0]}" ok="${y.arm.ok}" small="${y.arm.small}" dotted="${y.arm.dotted * 2}"
   octal="${y.arm.octal}" under="${y.arm.under}" sexa="${y.arm.sexa}"/>
<b mass="${y.link.mass}" color="${y.link.color}" base="${y['base']['mass']}" twice="${y.twice.k}"/>
<c xs="${[2 * item.val.x for item in y.list]}" has="${'arm' in y}" hasnot="${'baz' in y}" keys="${sorted(y.arm.keys())}"/>
<u deg="${y.units.deg}" mm="${y.units.mm}" rad="${y.units.rad}"/>
""", {}),
    "dict and list with keywords": ("""
<xacro:property name="init" value="${dict(shoulder=0.0, elbow=-1.57, wrist=0.0)}"/>
<xacro:macro name="m" params="pos:=${dict(a=1, b=2)}"><m v="${pos.get('b', 0)}" n="${len(pos)}"/></xacro:macro>
<xacro:m/><xacro:m pos="${init}"/>
<d v="${init}" e="${init['elbow']}" keys="${list(init.keys())}" z="${dict(python.zip(['x', 'y'], [1, 2]))}"
   l="${list(range(3))}" t="${python.tuple([1, 2])}" kw="${dict(dict(a=1), b=2)}" star="${max(*[3, 9, 4])}"
   srt="${sorted([3, 1, 2], reverse=True)}" key="${max([1, -5, 3], key=python.abs)}" rnd="${round(number=2.567, ndigits=2)}"/>
""", {}),
    "comprehensions and functions": ("""
<xacro:property name="abc" value="${[1, 2, 3]}"/>
<xacro:property name="xyz" value="${[abc[i] * abc[i] for i in [0, 1, 2]]}"/>
<c xyz="${xyz}" gen="${python.sum(x for x in abc)}" nest="${[(a, b) for a in abc for b in 'xy' if a != 2]}"
   d="${dict((str(k), v) for k, v in python.zip(abc, xyz))}" m="${list(map(float, '1 2.5'.split()))}"
   f="${list(python.filter(None, [0, 1, '', 'a']))}" e="${list(python.enumerate('ab', 1))}"
   r="${list(python.reversed(abc))}" any="${python.any(x > 2 for x in abc)}" all="${python.all([])}"
   dm="${python.divmod(17, 5)}" o="${python.ord('A')}" rp="${python.repr('q')}" ab="${python.abs(-2.5)}"
   pl="${python.len(abc)}" ps="${python.sorted(abc)[0]}" fs="${sorted(python.frozenset([2, 1]))}"
   st="${sorted(python.set('aba'))}"/>
""", {}),
    "math": ("""
<m r="${radians(90)}" d="${degrees(pi)}" a="${math.atan2(1, 2)}" f="${floor(2.7)}" c="${ceil(-0.5)}"
   h="${hypot(3, 4)}" s="${sqrt(2)}" fa="${math.factorial(6)}" cb="${math.comb(5, 2)}" e="${e ** 2}" t="${tau}"
   l="${log(8, 2)}" p="${pow(2, 10)}" fm="${fmod(7, 3)}" cs="${copysign(1, -0.0)}" tr="${trunc(-1.5)}"
   i="${1/3}" x="${2 ** 0.5}" n="${-7 % 3}" fd="${-7 // 2}" sh="${1 &lt;&lt; 10}" b="${5 &amp; 3 | 8 ^ 1}"
   inv="${~5}" big="${2 ** 100}" cmp="${1 &lt; 2 &lt;= 2}" ie="${1 if 0 else 2}" isc="${isclose(0.1 + 0.2, 0.3)}"/>
""", {}),
    "strings and formatting": ("""
<xacro:property name="name" value="left_arm"/>
<xacro:property name="fmt" value="{}_{n:>6}"/>
<s up="${name.upper()}" sp="${name.split('_')}" j="${'-'.join(['a', 'b'])}" rp="${name.replace('_', ' ')}"
   st="${name.startswith('left')}" z="${'7'.zfill(3)}" c="${'x'.center(5, '*')}" strip="${'  a '.strip()}"
   t="${name.title()}" sl="${name[::-1]}" fi="${name.find('arm')}" cnt="${name.count('a')}"
   pct="${'%s_%03d|%-4s|%.3f|%(x)s' % ('j', 7, 'ab', pi, ) if False else '%s_%03d|%-4s|%.3f' % ('j', 7, 'ab', pi)}"
   pd="${'%(x)s-%(x)s' % dict(x=1)}" ff="${fmt.format('a', n='b')}"
   cat="${name + '_' + str(2)}" mul="${'ab' * 3}" inn="${'arm' in name}" tk="${xacro.tokenize('a,b c;d')}"
   dot="${xacro.dotify(dict(a=1, b=2)).b}" lit="${'x' '_' 'y'}"/>
<literal v="1_2_3" w="${'1_2_3'}" e="$${not_evaluated}" f="$$(not_an_arg)"/>
""", {}),
    "arguments everywhere": ("""
<xacro:arg name="who" default="someone"/>
<xacro:arg name="tag" default="made"/>
<xacro:arg name="flag" default="true"/>
<xacro:arg name="list" default="['p', 'q']"/>
<xacro:arg name="derived" default="$(arg who)_x"/>
<xacro:arg name="m" default="mk"/>
<xacro:property name="outer" value="o"/>
<xacro:property name="fromarg" value="$(arg who)"/>
<xacro:property name="lst" value="${$(arg list)}"/>
<a who="$(arg who)" d="$(arg derived)" p="${fromarg}" l="${lst[1]}" xa="${xacro.arg('who')}" ev="$(eval 2 * n)"
   evb="$(eval true and flag)">text $(arg who) ${$(arg n) + 1}</a>
<xacro:if value="$(arg flag)"><iff/></xacro:if>
<xacro:unless value="${'$(arg flag)' == 'true'}"><never/></xacro:unless>
<xacro:element xacro:name="$(arg tag)" size="$(arg n)"><xacro:attribute name="by_$(arg who)" value="$(arg n)"/>
</xacro:element>
<xacro:macro name="mk" params="v:=$(arg n)"><mk v="${v}"/></xacro:macro>
<xacro:call macro="$(arg m)"/>
<xacro:mk v="$(arg who)"/>
<xacro:arg name="incfile" default="part"/>
<xacro:include filename="$(arg incfile).xacro"/>
<xacro:property name="$(arg tag)_prop" value="pv"/>
<named v="${made_prop}"/>
""", {"n": "3", "who": "me"}),
}


def _write(tmp_path):
    for name, text in AUX.items():
        (tmp_path / name).write_text(text)
    paths = {}
    for i, (name, (body, _)) in enumerate(DOCS.items()):
        p = tmp_path / f"doc{i}.urdf.xacro"
        p.write_text(f'<?xml version="1.0"?>\n<robot name="t" {NS}>{body}</robot>\n')
        paths[name] = p
    return paths


_REFERENCE = r"""
import json, sys, warnings
warnings.simplefilter("ignore")
import xacro
out = {}
for name, (path, args) in json.loads(sys.argv[1]).items():
    try:
        out[name] = xacro.process_file(path, mappings=dict(args)).toxml()
    except BaseException as exc:
        out[name] = "ERROR " + " ".join(str(exc).split())
sys.stdout.write(json.dumps(out))
"""


def _canonical(text):
    return [(e.tag, sorted(e.attrib.items()), " ".join((e.text or "").split())) for e in ET.fromstring(text).iter()]


@pytest.fixture(scope="module")
def expansions(tmp_path_factory):
    """(robokit's expansion, the xacro program's expansion) of every document."""
    tmp = tmp_path_factory.mktemp("xacro_language")
    paths = _write(tmp)
    cases = {name: (str(p), DOCS[name][1]) for name, p in paths.items()}
    run = subprocess.run([sys.executable, "-c", _REFERENCE, json.dumps(cases)], capture_output=True, text=True,
                         timeout=300, check=True, cwd=tmp)
    ref = json.loads(run.stdout)
    ours = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", robokit.RobokitWarning)
        for name, p in paths.items():
            try:
                ours[name] = expand_xacro(p, DOCS[name][1])
            except robokit.InputError as exc:
                ours[name] = f"ERROR {exc}"
    return {name: (ours[name], ref[name]) for name in DOCS}


@pytest.mark.parametrize("name", list(DOCS))
def test_construct_expands_as_the_xacro_program_expands_it(name, expansions):
    ours, ref = expansions[name]
    assert not ref.startswith("ERROR"), ref
    assert not ours.startswith("ERROR"), ours
    assert _canonical(ours) == _canonical(ref)


def test_the_documents_exercise_what_they_say(expansions):
    """A few values worked out by hand, so that agreement above is not two empty documents."""
    ours = {name: ET.fromstring(text) for name, (text, _) in expansions.items()}
    m = ours["macro defaults"].findall("m")
    assert m[0].attrib == {"a": "1", "b": "2", "c": "ooo", "d": "x y", "e": "E", "fwd": "from_caller",
                           "f": "1.5707963267948966", "g": "7"}
    assert ours["macro defaults"].find("n").attrib == {"e": "E", "fwd": "inner", "f": "1.5707963267948966"}
    # defaults that are xacro's own objects (False, math.pi) are data like any other (they were refused)
    assert ours["macro defaults"].find("b").attrib == {"t": "True", "f": "False", "p": "3.141592653589793",
                                                       "u": "True", "z": "0", "ok": "True"}
    assert ours["property scopes"].find("top").attrib == {"p": "global", "g": "parent_set_global", "d": "first"}
    y = ours["yaml as pyyaml reads it"]
    assert y.find("a").get("small") == "1e-3" and y.find("a").get("sexa") == "90" and y.find("a").get("octal") == "15"
    assert y.find("b").attrib == {"mass": "3.5", "color": "red", "base": "2.0", "twice": "2"}
    assert ours["arguments everywhere"].find("made").attrib == {"size": "3", "by_me": "3"}
    assert ours["strings and formatting"].find("s").get("pct") == "j_007|ab  |3.142"


def test_duplicate_yaml_keys_give_one_note(tmp_path):
    _write(tmp_path)
    src = tmp_path / "doc4.urdf.xacro"
    with pytest.warns(robokit.RobokitWarning) as notes:
        expand_xacro(src)
    dup = [str(n.message) for n in notes if "duplicate key" in str(n.message)]
    assert len(dup) == 1 and "settings.yaml: duplicate key 'k' (twice on line 4)" in dup[0]


def test_dirname_is_the_folder_of_the_file_being_read(tmp_path):
    """``$(dirname)``: the xacro program 2.1 cannot expand it (no file in its context); robokit
    gives the folder of the file it is reading, an included file's own folder for an include."""
    sub = tmp_path / "sub"
    sub.mkdir()
    (sub / "inc.xacro").write_text(f'<robot {NS}><inc d="$(dirname)"/></robot>')
    src = tmp_path / "top.urdf.xacro"
    src.write_text(f'<robot name="t" {NS}><top d="$(dirname)" e="$(dirname)/x"/>'
                   '<xacro:include filename="sub/inc.xacro"/></robot>')
    root = ET.fromstring(expand_xacro(src))
    assert root.find("top").attrib == {"d": str(tmp_path.resolve()), "e": f"{tmp_path.resolve()}/x"}
    assert root.find("inc").get("d") == str(sub.resolve())


def test_messages_and_print_location_are_notes(tmp_path):
    src = tmp_path / "m.urdf.xacro"
    src.write_text(f'<robot name="t" {NS}><xacro:macro name="inner"><x v="${{xacro.print_location()}}"/>'
                   '${xacro.warning("careful", 2)}${xacro.message("hello", print_location=False)}</xacro:macro>'
                   '<xacro:macro name="outer"><xacro:inner/></xacro:macro><xacro:outer/></robot>')
    with pytest.warns(robokit.RobokitWarning) as notes:
        text = expand_xacro(src)
    said = [str(n.message) for n in notes]
    assert any("xacro.print_location:" in s and "macro inner" in s and "macro outer" in s for s in said), said
    assert any("xacro.warning: careful 2 (at macro inner" in s for s in said), said
    assert any(s.endswith("xacro.message: hello") for s in said), said
    assert ET.fromstring(text).find("x").get("v") == ""
