"""The teach page's size: at most 1 MB (10⁶ bytes) besides the robot's meshes (#44), measured on the
page ``teach_html`` writes for the PUMA 560 (DH links, labels, no mesh file) and the UR5 (mesh files),
with what each section weighs in the failure message."""
import base64
import json
import re

import numpy as np
import pytest

import robokit
from robokit._optional import available

pytestmark = pytest.mark.skipif(not available("ziglang"), reason="ziglang (the viz extra) not installed")
BUDGET = 1_000_000


def _sections(page):
    return {(m.group(1).strip() or f"script {k}")[:40]: len(m.group(2).encode())
            for k, m in enumerate(re.finditer(r"<script([^>]*)>(.*?)</script>", page, re.S))}


@pytest.mark.parametrize("name", ["puma560", "ur5"])
def test_page_is_at_most_a_megabyte_besides_the_meshes(name):
    import umsgpack

    from robokit.viz.teach import teach_data
    from tests.viz.test_teach import teach_page

    robot = robokit.load(name)
    page = teach_page(robot)
    size = len(page.encode("utf-8"))
    # the mesh files' triangles, as the page embeds them: the scene commands that draw a visual read
    # from a mesh file, its coloured parts included (not a primitive: the PUMA's DH links count)
    data = teach_data(robot)
    meshed = {v["path"] for v, go in zip(data["visuals"], robot.visual_model.geometryObjects)
              if go.meshPath and go.meshPath.upper() not in ("CYLINDER", "BOX", "SPHERE", "CAPSULE")}
    scene = json.loads(re.search(r"var RK_SCENE = (\[.*?\]);</script>", page, re.S).group(1))
    mesh_bytes = 0
    for entry in scene:
        if isinstance(entry, str):
            cmd = umsgpack.unpackb(base64.b64decode(entry))
            path = str(cmd.get("path", ""))
            if cmd.get("type") == "set_object" and any(path == m or path.startswith(m + "/") for m in meshed):
                mesh_bytes += len(entry) + 3  # the quotes and the comma
    if name == "ur5":
        assert mesh_bytes > 500_000  # the meshes were found (the UR5's are about 1 MB)
    else:
        assert mesh_bytes == 0
    assert size - mesh_bytes <= BUDGET, (size, mesh_bytes, _sections(page))
    # the module is in it once, and the scripts once each
    assert page.count('id="rk-wasm"') == 1 and page.count("var RKWasm") == 1 and page.count("var RKMath") == 1


def test_label_images_are_compacted_losslessly():
    """A frame label's PNG (grey text, white outline) is stored as grey + alpha: every pixel decodes to
    the RGBA value matplotlib drew; a coloured image keeps its colours."""
    import io

    from PIL import Image

    from robokit.viz._labels import _compact_png, label_png

    rng = np.random.default_rng(0)
    for rgba, grey in ((np.repeat(rng.integers(0, 256, (20, 30, 1)), 3, axis=2), True),
                       (rng.integers(0, 256, (20, 30, 3)), False)):
        img = np.concatenate([rgba, rng.integers(0, 256, (20, 30, 1))], axis=2).astype(np.uint8)
        buf = io.BytesIO()
        Image.fromarray(img, "RGBA").save(buf, format="PNG", compress_level=0)
        out = Image.open(io.BytesIO(_compact_png(buf.getvalue())))
        assert out.mode == ("LA" if grey else "RGBA")
        np.testing.assert_array_equal(np.asarray(out.convert("RGBA")), img)
    png = label_png("dh_3")
    assert Image.open(io.BytesIO(png)).mode == "LA" and len(png) < 3500
