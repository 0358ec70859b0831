"""Compute once, render purely (issue 13.2) and the first screen (issue 11.5): the pipeline computes, the
report renders; every sentence of the first screen states the data it was generated from; the caster is
drawn to scale; the groove-damper table from the closed form equals the NLP's."""

from __future__ import annotations

import dataclasses
import json
import math
import re
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from designer import load_problem
from designer.display import percent, shown
from designer.studies.front import pareto_front
from designer.data.paper import INCH
from designer.model import Design
from designer.pipeline import ReportData, price_of_stock, report_data
from designer.plots.caster import caster_geometry, caster_svg, draw_caster
from designer.report import text, write_report

ROOT = Path(__file__).resolve().parents[2]
INVACARE = ROOT / "problems" / "paper-invacare.toml"
INDOOR = ROOT / "problems" / "indoor-manual.toml"


def _record(problem, design, f, p, role="recommended", prob=0.031, se=0.0008, alpha=0.05, rule="test rule"):
    """A Recommendation-shaped record (the fields of COORD.md's interface) for rendering tests; its ``caster`` is
    the model's record of the design under the problem's conditions."""
    from designer.model import evaluate

    return SimpleNamespace(
        design=design,
        caster=evaluate(design, problem.conditions),
        turning_effort=f,
        threshold_force=p,
        critical_speed=3.1,
        confident_speed=2.61,
        shimmy_probability=prob,
        shimmy_probability_mc=prob - se,
        shimmy_probability_se=se,
        swept_radius=design.trail + design.diameter / 2,
        swept_radius_max=problem.swept_radius_max,
        rule=rule,
        role=role,
        wheel=None,
        alternatives=[],
        buildable=None,
        note="",
        target_speed=problem.target_speed,
        required_speed=problem.required_speed,
        alpha=alpha,
        mc_samples=50_000,
        mc_seed=20111,
        measured=True,
        extrapolated=False,
        risk=None,
        spec=None,
        if_measured=None,
        to_dict=lambda: {"design": design.to_dict(), "turning_effort": f, "threshold_force": p, "role": role},
    )


@pytest.fixture(scope="module")
def indoor_data():
    """Report data of indoor-manual without the tighter front and without the recommendation module."""
    problem = load_problem(INDOOR)
    return report_data(problem, points=9, with_tighter=False, with_recommendation=False)


@pytest.fixture(scope="module")
def stub(indoor_data):
    """indoor-manual's report data with a stub recommendation at the front's knee and two alternatives."""
    problem, front = indoor_data.problem, indoor_data.front
    knee = front.knee()
    rec = _record(problem, knee.design, knee.turning_effort, knee.threshold_force)
    ends = (front.points[-1], front.points[0])
    rec.alternatives = [
        _record(problem, q.design, q.turning_effort, q.threshold_force, role=role)
        for q, role in zip(ends, ("easiest to turn", "easiest over the sill"))
    ]
    return dataclasses.replace(indoor_data, recommendation=rec, price_of_stock=price_of_stock(front, rec))


def test_report_renders_only_report_data(indoor_data, tmp_path):
    """write_report refuses anything but a ReportData (it computes nothing), and the pipeline's data renders."""
    with pytest.raises(TypeError, match="report_data"):
        write_report(indoor_data.problem, tmp_path / "x")
    folder = write_report(indoor_data, tmp_path / "r")
    assert (folder / "index.html").is_file()


def test_report_layer_calls_no_solver():
    """designer/report imports no optimiser, front sweep, check runner, trade-off or recommendation (render only)."""
    forbidden = (
        "designer.studies.optimum._optimise",
        "designer.studies.front._tradeoff",
        "designer.studies.front._pareto",
        "designer.studies.robust",
        "designer.studies.recommend._recommend",
        "designer.studies.checks.paper_checks",
        "designer.studies.checks.front_checks",
    )
    import ast

    for path in (ROOT / "designer" / "report").rglob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                names = [node.module or ""] + [f"{node.module}.{a.name}" for a in node.names]
            elif isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            else:
                continue
            assert not any(n.startswith(forbidden) for n in names), f"{path.name}:{node.lineno} imports {names}"


def test_cross_check_is_opt_in(indoor_data):
    """The main job solves the weighted optimum with the NLP only and the summary says how to add the cross-check."""
    assert indoor_data.run["cross_check"] is False
    assert set(indoor_data.solution.cross_check) == {"casadi-ipopt"}
    lines = text.summary_lines(indoor_data)
    assert any("designer pareto" in s and "--cross-check" in s for s in lines)


def test_cross_check_flag_runs_the_gp():
    """report_data(cross_check=True) (``designer pareto --cross-check``) also runs the geometric program."""
    problem = load_problem(INVACARE)
    data = report_data(problem, with_tighter=False, with_recommendation=False, cross_check=True)
    assert "cvxpy-gp" in data.solution.cross_check and data.cross_checked
    assert not any("--cross-check" in s for s in text.summary_lines(data))


def test_first_screen_is_build_this(stub, tmp_path):
    """The page opens with "Build this" above the figures: ONE caster in the headline, its sizes as the user writes
    them (inches to 1/16; this stub is the continuous knee, so its sizes are marked "≈"), the drawing (inline SVG),
    its one-row table; the other casters (3 rows with the recommendation) in a panel under the card; the
    Markdown links the SVG it writes."""
    from designer.report.formatting import size

    folder = write_report(stub, tmp_path / "build")
    html = (folder / "index.html").read_text()
    d = stub.recommendation.design
    build = html.index('id="build"')
    card = html[build : html.index("</section>", build)]
    assert build < html.index('id="figures"') and build < html.index('<ul class="summary">')
    assert f"{size(d.diameter)} wheel" in card and f"{size(d.trail)} trail" in card and "≈ " in card
    assert html.index("<svg", build) < html.index('id="figures"')
    table = card[card.index('<table class="card">') : card.index("</table>")]
    assert table.count("<tr") == 2 and "easiest" not in card  # one caster in the card
    others = html[html.index('id="panel-alternatives"') :]
    others = others[: others.index("</table>")]
    assert others.count("<tr") == 4 and "easiest to turn" in others and "easiest over the sill" in others
    md = (folder / "report.md").read_text()
    assert md.index("## Build this") < md.index("## Figures")
    assert "figures/caster.svg" in md and (folder / "figures" / "caster.svg").read_text().startswith("<svg")
    front = json.loads((folder / "front.json").read_text())
    assert front["recommendation"]["threshold_force"] == pytest.approx(stub.recommendation.threshold_force)
    assert len(front["alternatives"]) == 2


def test_build_card_shows_the_knock_safe_speeds(stub, tmp_path):
    """The "Build this" card shows each caster's knock-safe speeds (θ0 = 20° and 40° knocks, simulated) beside
    V_c in HTML and Markdown, and front.json carries them with the recommendation and the alternatives [m/s];
    the simulated θ0 value lies within 5 % of Eq. 7 (the model behind V_c) and the 40° one below it."""
    from designer.model import evaluate
    from designer.pipeline import card_knock_safe

    knock = card_knock_safe(stub.problem, stub.recommendation)
    assert len(knock) == 3
    for row, caster in zip(knock, [stub.recommendation, *stub.recommendation.alternatives]):
        v_c = float(evaluate(caster.design, stub.problem.conditions)["critical_speed"])
        assert row["knock_safe_speed"] == pytest.approx(v_c, rel=0.05)
        assert row["knock_safe_speed_double"] < row["knock_safe_speed"]
    folder = write_report(dataclasses.replace(stub, knock_safe=knock), tmp_path / "knock")
    html, md = (folder / "index.html").read_text(), (folder / "report.md").read_text()
    for page in (html, md):
        assert "Knock-safe speed: a second opinion" in page and "20° knock" in page and "40° knock" in page
        for row in knock:
            assert shown(row["knock_safe_speed"], "critical_speed") in page
            assert shown(row["knock_safe_speed_double"], "critical_speed") in page
    front = json.loads((folder / "front.json").read_text())
    assert front["recommendation"]["knock_safe_speed"] == pytest.approx(knock[0]["knock_safe_speed"])
    assert [a["knock_safe_speed_double"] for a in front["alternatives"]] == pytest.approx(
        [k["knock_safe_speed_double"] for k in knock[1:]]
    )


def test_card_knock_safe_uses_each_wheels_inertia():
    """Catalogue problem: each caster of the card is simulated with its own wheel's measured I_w (the one its
    V_c used), not the problem's default wheel: the θ0 knock-safe speed lies within 5 % of each caster's V_c."""
    from designer.studies.recommend import recommend
    from designer.pipeline import card_knock_safe

    problem = load_problem(ROOT / "problems" / "catalog-retrofit.toml")
    rec = recommend(problem)
    casters = [rec, *rec.alternatives]
    assert len({c.inertia for c in casters}) > 1 or casters[0].inertia != problem.conditions.inertia(
        casters[0].design.diameter
    )
    for caster, row in zip(casters, card_knock_safe(problem, rec)):
        assert row["knock_safe_speed"] == pytest.approx(caster.critical_speed, rel=0.05)


def test_build_sentences_state_the_data(stub):
    """The lead sentence and each "Build this" detail carry the recommendation's own numbers (rule, forces, risk,
    radius); the price of stock moved to the summary under the card."""
    rec, problem = stub.recommendation, stub.problem
    assert text.lead_sentence(stub).startswith("Chosen by the rule: test rule: ")
    stub = dataclasses.replace(
        stub, recommendation=SimpleNamespace(**{**vars(rec), "rule": "knee of the buildable front"})
    )
    rec = stub.recommendation
    lead = text.lead_sentence(stub)
    assert lead.startswith("The best balance between turning and the sill among the parts you can buy: ")
    force, effort = shown(rec.threshold_force, "threshold_force"), shown(rec.turning_effort, "turning_effort")
    assert f"{effort} of effort" in lead and f"with {force}" in lead
    assert f"probability {percent(rec.shimmy_probability)} (the bound is 5 %)" in lead
    lines = text.build_lines(stub)
    joined = " ".join(lines)
    assert f"F_turn = {effort}" in joined and f"P = {force}" in joined
    assert f"{percent(rec.shimmy_probability)} by the exact law" in joined
    assert f"{percent(rec.shimmy_probability_mc)} ± {percent(rec.shimmy_probability_se)}" in joined
    assert f"up to {shown(rec.confident_speed, 'confident_speed')}" in joined and "within the bound α = 5 %" in joined
    spare = problem.swept_radius_max - rec.swept_radius
    assert ("to spare" in joined) == (spare > 1e-9)
    assert text.stock_sentence(stub.price_of_stock, problem.stock is not None) in text.summary_lines(stub)
    assert "no [stock]" in text.stock_sentence(None, has_stock=False)


def test_risk_sentence_flags_an_estimate_above_the_bound(stub):
    """An exact P(shimmy) above α is said to be ABOVE the bound (0.0501 against 5 %: the exact law has no SE to
    hide in); without a bound the risk is still given as a number."""
    rec = stub.recommendation
    high = SimpleNamespace(**{**vars(rec), "shimmy_probability": 0.0501, "shimmy_probability_se": 0.001})
    assert "ABOVE" in text.risk_sentence(high)
    assert "within" in text.risk_sentence(rec)
    nominal = SimpleNamespace(**{**vars(rec), "alpha": None, "shimmy_probability": 0.49})
    sentence = text.risk_sentence(nominal)
    assert "No risk bound" in sentence and "= 49 % by the exact law" in sentence


def test_price_of_stock_reads_the_continuous_front(indoor_data):
    """price_of_stock interpolates the continuous front at the caster's P (extra F_turn) and at its F_turn (extra P)."""
    front = indoor_data.front
    f = front.objectives()
    a, b = front.points[3], front.points[4]
    p_mid = 0.5 * (a.threshold_force + b.threshold_force)
    f_mid = 0.5 * (a.turning_effort + b.turning_effort)
    rec = SimpleNamespace(threshold_force=p_mid, turning_effort=f_mid + 0.5)
    price = price_of_stock(front, rec)
    assert price["turning_effort_continuous"] == pytest.approx(f_mid, rel=1e-12)
    assert price["extra"] == pytest.approx(0.5, rel=1e-9)
    beyond = price_of_stock(front, SimpleNamespace(threshold_force=f[:, 1].max() + 10, turning_effort=f[:, 0].min()))
    assert beyond["extra"] == pytest.approx(0.0, abs=1e-12)  # beyond the largest P: the front's least F_turn
    assert price_of_stock(front, SimpleNamespace(threshold_force=f[:, 1].min() - 1, turning_effort=30.0)) is None
    sentence = text.stock_sentence(price, has_stock=True)
    assert f"{price['extra']:+.3f} N" in sentence


def test_weights_sentence_matches_where_the_optimum_sits(indoor_data):
    """The weighted-optimum sentence says "least-P end" only when the optimum is within 1 % of the front's P range
    from it, and otherwise gives its place as a percentage (today's powered-chair contradiction)."""
    problem, front, s = indoor_data.problem, indoor_data.front, indoor_data.solution
    line = text.weights_line(problem, s, front)
    p = front.objectives()[:, 1]
    frac = (s.objectives["threshold_force"] - p.min()) / (p.max() - p.min())
    assert "1 N of sill force is worth 1 N of turning effort" in line
    if frac <= text.AT_END:
        assert "least-P end of the front" in line
    else:
        assert f"{frac:.0%} of the front's P range" in line and "is not the least-P end" in line
    at_end = dataclasses.replace(s, caster=dataclasses.replace(s.caster, threshold_force=float(p.min())))
    assert at_end.objectives["threshold_force"] == float(p.min())  # the optimum's objectives are its caster's
    assert "the optimum is the least-P end" in text.weights_line(problem, at_end, front)


def test_margin_sentence_counts_designs_on_the_constraint():
    """Without margin or risk bound the sentence counts the front designs at V_c = V_req (today's catalog-retrofit
    said "exactly at V_c = V_req" of a design at 2.31 m/s)."""
    problem = load_problem(INVACARE)
    problem = problem.replace(conditions=problem.conditions.replace(uncertainty=None), margin=0.0)
    front = pareto_front(problem)
    v = np.array([q.critical_speed for q in front.points])
    on = int(np.sum(np.abs(v / problem.required_speed - 1) <= text.ACTIVE_REL))
    line = text.margin_line(problem, front)
    if on == len(v):
        assert "every front design sits exactly" in line
    else:
        assert f"{on} of {len(v)} front designs" in line or (on == 0 and "no front design sits" in line)
    above = dataclasses.replace(front.points[0], critical_speed=problem.required_speed * 1.15)
    moved = front.__class__(problem, [above], [], front.meta)
    line = text.margin_line(problem, moved)
    assert "no front design sits" in line and f"{above.critical_speed:.3f} m/s" in line


def test_caster_drawing_is_to_scale():
    """The SVG's wheel radius, swept circle and footrest circle are d/2, T + d/2 and R_max at one px/in scale; the
    sill sits where a wheel of radius d/2 touches an edge of height h; draw_caster draws the same circles."""
    t, d, b, h, r_max = 2.0 * INCH, 6.0 * INCH, 0.25 * INCH, 0.5 * INCH, 5.5 * INCH
    svg = caster_svg(t, d, b, h, r_max, scale=30.0)
    radii = sorted(float(r) for r in re.findall(r'<circle [^>]*r="([0-9.]+)"', svg))
    assert pytest.approx(3.0 * 30.0, abs=0.06) in radii  # wheel
    assert pytest.approx(5.0 * 30.0, abs=0.06) in radii  # swept radius T + d/2
    assert pytest.approx(5.5 * 30.0, abs=0.06) in radii  # footrest limit
    g = caster_geometry(t, d, b, h, r_max)
    assert g.sill_x == pytest.approx(-t + math.sqrt((d / 2) ** 2 - (d / 2 - h) ** 2))
    assert "6.000 in" in svg and "2.000 in" in svg and "0.500 in" in svg
    assert "<script" not in caster_svg(t, d, b, h, None, label="<script>x</script>")
    from matplotlib.figure import Figure

    side, top = Figure().subplots(1, 2)
    draw_caster(side, top, t, d, b, h, r_max)
    circles = sorted(round(p.get_radius(), 6) for p in top.patches if hasattr(p, "get_radius"))
    assert circles == [5.0, 5.5]
    assert any(round(p.get_radius(), 6) == 3.0 for p in side.patches if hasattr(p, "get_radius"))


@pytest.mark.parametrize("robust", [False, True], ids=["nominal", "risk-bounded"])
def test_tradeoff_closed_form_equals_the_nlp(robust):
    """The closed-form groove-damper table equals the NLP optimum (restricted problems, trail free) at three
    diameters for each mechanism, to 1e-4 relative (the NLP's tolerance), nominal and risk-bounded."""
    from designer.studies.optimum import optimise
    from designer.studies.front._tradeoff import MECHANISMS, _restricted, groove_damper_tradeoff
    from designer.errors import DesignerError
    from designer.physics.uncertainty import Uncertainty
    from designer.problem import Bound

    problem = load_problem(INDOOR)
    problem = problem.replace(conditions=problem.conditions.replace(uncertainty=Uncertainty() if robust else None))
    rows = groove_damper_tradeoff(problem, count=3)
    assert len(rows) == 3
    for row in rows:
        sub = problem.replace(bounds={**problem.bounds, "diameter": Bound(row.diameter, row.diameter)})
        for mechanism in MECHANISMS:
            restricted = _restricted(sub, mechanism) if mechanism != "optimum mix" else sub
            try:
                ref = optimise(restricted, weights=(1.0, 0.0), cross_check=False, samples=64)
                expected = ref.objectives["turning_effort"]
            except DesignerError:
                expected = None
            got = row.effort[mechanism]
            if expected is None:
                assert got is None, (row.diameter, mechanism)
            else:
                assert got == pytest.approx(expected, rel=1e-4), (row.diameter / INCH, mechanism)


def test_report_data_is_a_plain_record(indoor_data):
    """ReportData holds the computed parts and the CPU seconds of each step (the benchmark's split)."""
    assert isinstance(indoor_data, ReportData)
    cpu = indoor_data.run["compute_cpu_seconds"]
    assert {"front", "recommendation", "optimum", "checks", "tradeoff"} <= set(cpu)
    assert all(v >= 0 for v in cpu.values())
    assert indoor_data.recommendation is None and indoor_data.recommendation_error == "not computed"
    assert isinstance(indoor_data.solution.design, Design)


def test_robust_figure_title_is_the_page_title():
    """The robust report's figure carries the page's title (one source: report.robust.title)."""
    from designer.pipeline import robust_data
    from designer.report import robust as robust_report

    data = robust_data(load_problem(ROOT / "problems" / "indoor-manual-robust.toml"), points=5)
    fig = robust_report.figure(data)
    assert fig.axes[0].get_title() == robust_report.title(data)
    assert "Price of safety" in robust_report.title(data)


# ----------------------------------------------------------------------------------------------------
# The main job's compute loads none of the heavy libraries issue 13 names (cvxpy, scipy.stats, optuna).
import subprocess
import sys
from pathlib import Path

HEAVY = ("cvxpy", "scipy.stats", "optuna", "pint", "matplotlib")


def test_report_data_of_the_default_problem_loads_no_heavy_library():
    """``report_data`` of the default problem (front, tighter front, recommendation, knock-safe speeds, optimum,
    checks) runs without importing cvxpy, scipy.stats, optuna, pint or matplotlib: the GP cross-check is
    opt-in, normal quantiles come from scipy.special, the default risk-bound fit and Sobol sample are stored,
    "2.5 in" is read without pint, and matplotlib waits for the figures."""
    code = (
        "import sys, warnings; warnings.simplefilter('ignore')\n"
        "from designer.problem import load_problem\n"
        "from designer.pipeline import report_data\n"
        "data = report_data(load_problem('problems/indoor-manual.toml'))\n"
        "assert data.knock_safe and data.knock_safe[0]['knock_safe_speed'] > 0 and data.front.points\n"
        f"print(sorted(m for m in sys.modules if m.split('.')[0] in {HEAVY!r} or m in {HEAVY!r}))\n"
        "print(sorted(m for m in sys.modules if m.startswith('scipy.stats')))\n"
    )
    root = Path(__file__).resolve().parents[2]
    out = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True, check=True)
    heavy, stats = out.stdout.strip().splitlines()[-2:]
    assert heavy == "[]"
    assert stats == "[]"


MAIN_JOB_NEVER = HEAVY + ("scipy.optimize", "dask", "dash", "flask", "plotly", "PIL", "pandas", "pgserver", "psycopg2")
"""What the whole ``designer pareto`` process must not load: the GP stack, the samplers, unit parsing, the
plotting and web stacks, dask, and scipy.optimize (check 6 and the knock events use physics.bracketed_root)."""


def test_designer_pareto_process_loads_no_heavy_library(tmp_path):
    """The whole ``designer pareto problems/indoor-manual.toml`` process (CLI, compute, SVG figures, writing)
    exits 0 with a complete report and, at its exit, has none of MAIN_JOB_NEVER in sys.modules."""
    out, modules = tmp_path / "report", tmp_path / "modules.json"
    code = (
        "import atexit, json, runpy, sys\n"
        f"atexit.register(lambda: open({str(modules)!r}, 'w').write(json.dumps(sorted(sys.modules))))\n"
        f"sys.argv = ['designer', 'pareto', 'problems/indoor-manual.toml', '--out', {str(out)!r}]\n"
        "runpy.run_module('designer', run_name='__main__')\n"
    )
    root = Path(__file__).resolve().parents[2]
    done = subprocess.run([sys.executable, "-c", code], cwd=root, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr[-2000:]
    assert (out / "index.html").is_file() and len(list((out / "figures").glob("*.svg"))) == 7  # six + caster
    loaded = json.loads(modules.read_text())
    heavy = sorted(m for m in loaded if any(m == h or m.startswith(h + ".") for h in MAIN_JOB_NEVER))
    assert heavy == []
