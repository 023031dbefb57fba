"""The capability map page frames the map: in headless Chromium, the voxels' projection (three.js's own
camera and matrices) lies inside the canvas and fills a fair part of it, and a planar arm's flat map is
seen nearly face-on (from the 3/4 view it was foreshortened to sin 25° ≈ 0.42: almost edge-on)."""
import html as html_mod
import json
import re

import pytest
from browser_support import CHROMIUM, dump_dom

import robokit
from robokit.workspace.plot import capability_html

_HARNESS = """
<pre id="rk-test-out"></pre>
<script>
(function () {
  // the page applies its commands as their fetch()es resolve, in no fixed order: measure until the
  // projection has stayed the same for five polls (1.5 s of the page's time)
  var last = "", same = 0;
  function measure() {
    var node = viewer.scene_tree.find(["meshcat", "points", "capability", "<object>"]);
    var obj = node && node.object, pos = obj && obj.geometry && obj.geometry.attributes && obj.geometry.attributes.position;
    if (!pos || !pos.count) { setTimeout(measure, 300); return; }
    viewer.camera.updateMatrixWorld(true);
    obj.updateMatrixWorld(true);
    var V = obj.position.constructor, v = new V(), canvas = viewer.renderer.domElement;
    var w = canvas.clientWidth, h = canvas.clientHeight, x0 = 1e9, y0 = 1e9, x1 = -1e9, y1 = -1e9;
    for (var i = 0; i < pos.count; i++) {
      v.set(pos.getX(i), pos.getY(i), pos.getZ(i)).applyMatrix4(obj.matrixWorld).project(viewer.camera);
      var px = (v.x + 1) / 2 * w, py = (1 - v.y) / 2 * h;
      x0 = Math.min(x0, px); x1 = Math.max(x1, px); y0 = Math.min(y0, py); y1 = Math.max(y1, py);
    }
    var now = JSON.stringify({box: [x0, y0, x1, y1], canvas: [w, h], points: pos.count});
    same = now === last ? same + 1 : 0;
    last = now;
    if (same < 5) { setTimeout(measure, 300); return; }
    document.getElementById("rk-test-out").textContent = now;
  }
  setTimeout(measure, 300);
})();
</script>
"""


def _measure(page: str, tmp_path) -> dict:
    i = page.rfind("</body>")
    path = tmp_path / "map.html"
    path.write_text(page[:i] + _HARNESS + page[i:], encoding="utf-8")
    dom = dump_dom(path.as_uri())
    m = re.search(r'<pre id="rk-test-out">(.*?)</pre>', dom, re.S)
    assert m and m.group(1), dom[-2000:]
    return json.loads(html_mod.unescape(m.group(1)))


@pytest.mark.skipif(CHROMIUM is None, reason="chromium not installed (apt-get install chromium)")
@pytest.mark.parametrize("name,resolution,with_robot", [("rrr", 0.1, True), ("rrr", 0.1, False), ("ur5", 0.15, True)])
def test_the_map_is_framed_and_a_flat_map_seen_nearly_face_on(name, resolution, with_robot, tmp_path):
    cmap = robokit.capability_map(name, resolution, orientations=6, client="serial")
    if not with_robot:
        cmap.description = None  # the page of a map that names no robot: the points alone
    got = _measure(capability_html(cmap), tmp_path)
    assert got["points"] == len(cmap.centres)
    x0, y0, x1, y1 = got["box"]
    w, h = got["canvas"]
    assert 0 <= x0 < x1 <= w and 0 <= y0 < y1 <= h, got  # all of it in view
    assert max((x1 - x0) / w, (y1 - y0) / h) > 0.45, got  # and not a speck
    if name == "rrr":  # a disk in the z = 0 plane: its projection's height/width is the view's sin(elevation)
        assert (y1 - y0) / (x1 - x0) > 0.75, got
