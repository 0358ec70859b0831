"""Regenerate the notebook screenshots in docs/img/: two reprs rendered by headless Chromium and one figure
per plot method.  Run from the repository root: ``python docs/img/render.py`` (needs matplotlib and the
Debian ``chromium`` package; takes about a minute).

repr-front.png, repr-recommendation.png, repr-simulation.png: ``_repr_html_`` as Jupyter shows it;
plot-front.png (``front.plot()``), plot-variables.png (``front.plot_variables()``),
recommendation-draw.png (``recommendation.draw()``), simulation-plot.png (``simulation.plot()``).
"""

from __future__ import annotations

import subprocess
import tempfile
from pathlib import Path

import matplotlib

import designer

matplotlib.use("Agg")
OUT = Path(__file__).resolve().parent
PAGE = (
    '<!doctype html><html><head><meta charset="utf-8"><title>{title}</title></head>'
    '<body style="margin:12px;background:white">{body}</body></html>'
)
WINDOWS = {"front": "680,190", "recommendation": "920,275", "simulation": "700,230"}
"""Chromium window size [px] per repr (the repr's own size plus a margin)."""


def main() -> None:
    problem = designer.example_problem("indoor-manual")
    front = designer.pareto_front(problem, points=41)
    rec = designer.recommend(problem)
    # 10 % above Eq. 7's V_c the knock grows: the plot shows shimmy building up
    sim = designer.simulate(rec.design, problem.conditions, speed=1.1 * rec.critical_speed, cycles=12)
    with tempfile.TemporaryDirectory() as tmp:
        for name, obj in (("front", front), ("recommendation", rec), ("simulation", sim)):
            page = Path(tmp) / f"{name}.html"
            page.write_text(PAGE.format(title=name, body=obj._repr_html_()), encoding="utf-8")
            subprocess.run(
                [
                    "chromium",
                    "--headless",
                    "--no-sandbox",
                    "--disable-gpu",
                    "--hide-scrollbars",
                    f"--screenshot={OUT / f'repr-{name}.png'}",
                    f"--window-size={WINDOWS[name]}",
                    page.as_uri(),
                ],
                check=True,
                capture_output=True,
            )
    front.plot().figure.savefig(OUT / "plot-front.png", dpi=90)
    front.plot_variables().flat[0].figure.savefig(OUT / "plot-variables.png", dpi=90)
    rec.draw()[0].figure.savefig(OUT / "recommendation-draw.png", dpi=90)
    sim.plot().figure.savefig(OUT / "simulation-plot.png", dpi=90)


if __name__ == "__main__":
    main()
