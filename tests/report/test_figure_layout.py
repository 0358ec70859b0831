"""The report's figures agree and stay readable: one direction per axis (P increasing to the right in the front
figure, the design-variables figure, ``Front.plot()``, ``Front.plot_variables()`` and the studio's chart), no
text under a legend box in any figure of any shipped problem, and coinciding marked designs sharing one legend
entry (the knee and the weighted optimum of the default problem)."""

from __future__ import annotations

import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from designer.plots.fronts import plot_variables
from designer.plots.svg import Figure, text_width
from designer.report import figures as report_figures

ROOT = Path(__file__).resolve().parents[2]
FIGURES = sorted((ROOT / "results").glob("*/figures/*.svg"))
LEGEND = re.compile(
    r'<g class="legend"><rect x="([-\d.]+)" y="([-\d.]+)" width="([\d.]+)" height="([\d.]+)".*?</g>', re.S
)
TEXT = re.compile(r'<text x="([-\d.]+)" y="([-\d.]+)" font-size="([\d.]+)" text-anchor="(\w+)"[^>]*>([^<]*)</text>')


def text_boxes(svg: str) -> list[tuple[str, tuple[float, float, float, float]]]:
    """(text, (left, top, right, bottom) [px]) of every text outside the legends, its width estimated from
    DejaVu Sans' advance widths (the page's font)."""
    out = []
    for m in TEXT.finditer(LEGEND.sub("", svg)):
        x, y, size, anchor, s = float(m[1]), float(m[2]), float(m[3]), m[4], m[5]
        if not s.strip() or "rotate(-90" in m[0]:
            continue  # axis titles turned upright sit outside the axes, beside no legend
        width = text_width(s, size * 72 / 110)  # points, as the canvas sizes them
        left = {"start": x, "middle": x - width / 2, "end": x - width}[anchor]
        out.append((s, (left, y - 0.75 * size, left + width, y + 0.2 * size)))
    return out


def covered(svg: str) -> list[str]:
    """The texts of ``svg`` that a legend box overlaps."""
    hits = []
    for m in LEGEND.finditer(svg):
        x, y, w, h = map(float, m.groups())
        for s, (l, t, r, b) in text_boxes(svg):
            if l < x + w and r > x and t < y + h and b > y:
                hits.append(s)
    return hits


@pytest.mark.parametrize("path", FIGURES, ids=lambda p: f"{p.parent.parent.name}/{p.name}")
def test_no_text_under_a_legend(path):
    """No label of a figure (tick, contour label, annotation, title) lies under a legend box."""
    assert covered(path.read_text(encoding="utf-8")) == []


def test_the_legend_check_catches_a_covered_label():
    """Planted: a contour label drawn where the legend sits is found (Figure 6's legend covered the iso-V_c
    labels '5.0 m/s' and '5.5 m/s' before it moved under the plane)."""
    fig = Figure(figsize=(5, 4))
    ax = fig.add_subplot()
    ax.plot([0, 1], [0, 1], label="a line with a long legend label")
    ax.text(0.95, 0.95, "5.5 m/s", ha="right")
    ax.legend(loc="upper right")
    assert covered(fig.to_svg("planted")) == ["5.5 m/s"]


def test_variables_run_with_p_increasing_to_the_right():
    """The design-variables figure (SVG canvas and matplotlib, as ``Front.plot_variables()``) puts the smallest
    P on the left, as the front figure, ``Front.plot()`` and the studio do."""
    p = np.array([100.0, 110.0, 120.0])
    designs = np.array([[0.05, 0.2, 0.019, 3.0], [0.06, 0.18, 0.01, 1.3], [0.0635, 0.14, 0.0, 1.3]])
    bounds = [(0.0254, 0.0635), (0.0762, 0.2032), (0.0, 0.01905), (1.3, 6.0)]
    fig = Figure(figsize=(8.5, 6.2))
    axes = fig.subplots(2, 2, sharex=True)
    plot_variables(p, designs, ["groove+damper", "groove", "bare fork"], bounds, axes=axes)
    sx = axes.flat[0]._scales()[0]
    assert sx(100.0) < sx(120.0)
    import matplotlib

    matplotlib.use("Agg")
    mpl_axes = plot_variables(p, designs, ["groove+damper", "groove", "bare fork"], bounds)
    assert not mpl_axes.flat[0].xaxis_inverted()
    assert mpl_axes.flat[0].get_xlim()[0] < mpl_axes.flat[0].get_xlim()[1]


class _Front:
    """A front of three points whose middle one is the knee."""

    def __init__(self, points):
        self.points = points

    def __len__(self):
        return len(self.points)

    def knee(self):
        return self.points[1]

    def objectives(self):
        return np.array([[q.turning_effort, q.threshold_force] for q in self.points])


def _marks(knee, optimum):
    """The front figure's marks for a three-point front whose knee and weighted optimum are given (F, P) [N]."""
    points = [SimpleNamespace(turning_effort=f, threshold_force=p) for f, p in ((7.0, 130.0), knee, (37.0, 98.0))]
    front = _Front(points)
    data = SimpleNamespace(
        front=front,
        problem=SimpleNamespace(weights=(1.0, 1.0), stock=None),
        solution=SimpleNamespace(objectives={"turning_effort": optimum[0], "threshold_force": optimum[1]}),
        recommendation=None,
    )
    return report_figures._front_marks(data)[1]


def test_knee_and_optimum_on_one_spot_share_a_legend_entry():
    """The default problem's knee (P 105.0 N, F_turn 8.32 N) and weighted optimum (P 105.06 N, F_turn 8.28 N): one legend
    entry naming both, the cross still drawn; 5 N apart in P on a 32 N wide front, two entries."""
    marks = _marks((8.32, 105.0), (8.28, 105.06))
    labels = [m["label"] for m in marks]
    assert labels == ["knee of the continuous front = weighted optimum (w = 1, 1): P 105.00 N, F_turn 8.320 N", ""]
    assert [m["kind"] for m in marks] == ["knee", "weighted"]
    apart = [m["label"] for m in _marks((8.32, 105.0), (8.0, 110.0))]
    assert apart == [
        "knee of the continuous front: P 105.00 N, F_turn 8.320 N",
        "weighted optimum (w = 1, 1; not the recommendation)",
    ]


def test_default_report_front_names_knee_and_optimum_once():
    """The committed default report's Figure 1 has one legend line for the knee and the weighted optimum (the knee
    found on the continuous front, not its nearest sample: both at P 105.06 N, F 8.28 N)."""
    svg = (ROOT / "results" / "indoor-manual" / "figures" / "front.svg").read_text(encoding="utf-8")
    assert "knee of the continuous front = weighted optimum (w = 1, 1): P 105.06 N, F_turn 8.280 N" in svg
    assert "not the recommendation" not in svg
