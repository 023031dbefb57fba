"""The capability map page carries a colour legend: the bar's colours are the points' colour
map (matplotlib's viridis, sampled independently here) from index 0 to 1."""
import re

import numpy as np
from matplotlib import colormaps

import robokit
from robokit.workspace.plot import capability_html, legend_html


def test_legend_bar_is_the_point_colour_map_and_the_page_carries_it():
    cmap = robokit.capability_map("rrr", 0.15, orientations=6, client="serial")
    legend = legend_html(cmap)
    stops = re.findall(r"rgb\((\d+),(\d+),(\d+)\) (\d+)%", legend)
    assert len(stops) == 11 and stops[0][3] == "0" and stops[-1][3] == "100"
    viridis = colormaps["viridis"]
    for r, g, b, pct in stops:
        want = np.array(viridis(int(pct) / 100)[:3]) * 255
        assert np.abs(np.array([int(r), int(g), int(b)]) - want).max() <= 0.51
    assert "6 tool orientations" in legend and f"{len(cmap.centres)} voxels" in legend
    page = capability_html(cmap)
    assert page.count('id="robokit-legend"') == 1 and page.index("robokit-legend") < page.rindex("</body>")
