"""docs/examples/design-a-caster.ipynb runs top to bottom, from its own folder as Jupyter runs it (issue 17).

The notebook is stored without outputs; nbclient executes it in a fresh kernel of this interpreter and any
cell error fails the test.  A few outputs are checked: the recommendation prints a trail in inches, the
front and the simulation draw figures, the pandas cell shows the SI column names.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

nbformat = pytest.importorskip("nbformat")
nbclient = pytest.importorskip("nbclient")
pytest.importorskip("ipykernel")
pytest.importorskip("pandas")

NOTEBOOK = Path(__file__).resolve().parents[2] / "docs" / "examples" / "design-a-caster.ipynb"


def _text(cell) -> str:
    parts = []
    for out in cell.get("outputs", []):
        parts.append(out.get("text", ""))
        data = out.get("data", {})
        parts.append(data.get("text/plain", ""))
        parts.append(data.get("text/html", ""))
    return "\n".join(parts)


def test_notebook_is_stored_without_outputs():
    """The committed notebook has no outputs and no execution counts (a diff shows code, not results)."""
    nb = nbformat.read(NOTEBOOK, as_version=4)
    code = [c for c in nb.cells if c.cell_type == "code"]
    assert code
    assert all(not c.outputs and c.execution_count is None for c in code)


def test_notebook_runs_top_to_bottom():
    """Every cell runs without error in the notebook's folder; the outputs show the caster and the figures."""
    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        nb, timeout=600, kernel_name="python3", resources={"metadata": {"path": str(NOTEBOOK.parent)}}
    )
    client.execute()  # raises CellExecutionError on the first failing cell
    cells = [c for c in nb.cells if c.cell_type == "code"]

    def output_of(snippet: str) -> str:
        return "\n".join(_text(c) for c in cells if snippet in c.source)

    shown = output_of("designer.recommend(problem)")
    assert re.search(r"trail T\s+\d\.\d{3} in", shown), shown
    assert "<table" in output_of("recommendation  # in Jupyter")
    assert "Front('indoor-manual': 15 points" in output_of("front = designer.pareto_front(problem, points=15)")
    assert "turning_effort_N" in output_of("front.to_pandas()")
    assert re.search(
        r"knock 40 deg at 2\.5 m/s: (grows into shimmy|dies out)", output_of("simulate(recommendation.design")
    )
    images = [c for c in cells if any("image/png" in out.get("data", {}) for out in c.outputs)]
    assert len(images) >= 3  # the front, the two fronts, the knock
