"""Pareto reports (docs/commands.md#reports): the committed results/ are reproducible, the HTML is
self-contained and escaped, writes are atomic, and ``designer pareto`` writes every file."""

from __future__ import annotations

import dataclasses
import json
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from designer import load_problem
from designer.display import shown
from designer.cli import main
from designer.plots import figures
from designer.pipeline import report_data
from designer.report import write_report
from designer.report.agreement import compare_folders

ROOT = Path(__file__).resolve().parents[2]
COMMITTED = ROOT / "results" / "indoor-manual"
FILES = ("index.html", "report.md", "front.csv", "front.json", "checks.json")
FIGURES = tuple(f"figures/{name}.svg" for name in figures.FIGURES)
VARYING = ("date", "versions", "wall_seconds", "compute_cpu_seconds", "render_cpu_seconds", "front_seconds")
"""Run metadata that changes from run to run: in run.json, never in a committed file."""


@pytest.fixture(scope="module")
def regenerated_all(tmp_path_factory) -> tuple[Path, int]:
    """``designer pareto --all problems`` into a temporary folder, from the checkout's root: the command that
    writes results/<problem>/ (a report names its problem file as given, so the path is the relative one)."""
    parent = tmp_path_factory.mktemp("pareto")
    with pytest.MonkeyPatch.context() as patch:
        patch.chdir(ROOT)
        code = main(["pareto", "--all", "problems", "--out", str(parent)])
    return parent, code


@pytest.fixture(scope="module")
def regenerated(regenerated_all) -> tuple[Path, int]:
    """The default problem's report of that run (the README's main job: problems/indoor-manual.toml)."""
    parent, code = regenerated_all
    return parent / "indoor-manual", code


@pytest.fixture(scope="module")
def invacare():
    """The report data of the paper's Invacare wheel (fixed diameter, single-point front): fast to compute."""
    problem = load_problem(ROOT / "problems" / "paper-invacare.toml")
    return problem, report_data(problem)


def _stale(committed: Path, fresh: Path) -> dict[str, list[str]]:
    """The files of ``committed`` and ``fresh`` that do not agree (designer.report.agreement: value by value, each
    within its field's tolerance; the same structure and text), or exist in one only, with what moved."""
    return {name: [m.line() for m in moved] for name, moved in compare_folders(committed, fresh).items()}


def test_cli_writes_every_file(regenerated, capsys):
    """`designer pareto` exits 0 (every check passes on every shipped problem) and writes the report files and
    figures; the run's date, seconds and library versions are in run.json beside them, and in no other file."""
    out, code = regenerated
    assert code == 0
    for name in FILES + FIGURES:
        assert (out / name).is_file(), name
        assert (out / name).stat().st_size > 0, name
    run = json.loads((out / "run.json").read_text())
    for key in ("caster-designer", "numpy", "scipy", "casadi", "cvxpy", "optuna"):
        assert run["versions"][key], key
    digest = load_problem(ROOT / "problems" / "indoor-manual.toml").digest()
    assert run["problem_digest"] == digest and run["wall_seconds"] > 0 and run["date"]
    data = json.loads((out / "front.json").read_text())
    assert data["run"]["problem_digest"] == digest
    assert not set(VARYING) & set(data["run"]), "run metadata that varies belongs in run.json"
    for name in ("index.html", "report.md"):
        text = (out / name).read_text()
        assert run["date"] not in text and run["date"][:10] not in text, name
        assert f"numpy {run['versions']['numpy']}" not in text, name


def test_committed_results_are_current(regenerated_all):
    """results/<problem>/ of every shipped problem agrees with what `designer pareto --all problems` writes now
    (run.json aside): every number of every data file, figure and page within the tolerance of what produced it,
    the same structure, labels and text (docs/checks.md#when-two-result-files-agree), on any CPU and numeric
    kernel; a difference beyond it means results/ is stale (test_agreement plants such differences)."""
    parent, _ = regenerated_all
    problems = sorted(path.stem for path in (ROOT / "problems").glob("*.toml"))
    stale = {name: _stale(ROOT / "results" / name, parent / name) for name in problems}
    stale = {name: files for name, files in stale.items() if files}
    assert not stale, f"results/ is stale (regenerate: designer pareto --all problems): {stale}"


def test_committed_robust_report_is_current(tmp_path, monkeypatch):
    """results/robust/indoor-manual-robust agrees with what `designer robust` writes now (run.json aside): robust.json
    value by value (Monte Carlo estimates within 4 SE), the pages by structure and numbers, and the PNG, which
    cannot be compared by number, byte for byte (a rerun keeps it when robust.json agrees)."""
    out = tmp_path / "indoor-manual-robust"
    monkeypatch.chdir(ROOT)
    assert main(["robust", "problems/indoor-manual-robust.toml", "--out", str(out)]) == 0
    assert (out / "run.json").is_file()
    stale = _stale(ROOT / "results" / "robust" / "indoor-manual-robust", out)
    assert not stale, (
        f"results/robust is stale (regenerate: designer robust problems/indoor-manual-robust.toml): {stale}"
    )


def test_main_job_twice_leaves_the_checkout_clean(tmp_path, monkeypatch, regenerated_all):
    """README command 1 (`designer pareto problems/indoor-manual.toml`, from the checkout's root) run twice in a
    git copy of problems/, results/indoor-manual/ and .gitignore: after each run `git status --porcelain` is
    empty (run.json is written and ignored)."""
    repo = tmp_path / "checkout"
    shutil.copytree(ROOT / "problems", repo / "problems")
    shutil.copytree(COMMITTED, repo / "results" / "indoor-manual", ignore=shutil.ignore_patterns("run.json"))
    shutil.copy(ROOT / ".gitignore", repo / ".gitignore")

    def git(*args: str) -> str:
        config = ["-c", "user.name=test", "-c", "user.email=test@example.invalid", "-c", "commit.gpgsign=false"]
        return subprocess.run(["git", *config, *args], cwd=repo, capture_output=True, text=True, check=True).stdout

    git("init", "-q")
    git("add", "-A")
    git("commit", "-q", "-m", "checkout")
    monkeypatch.chdir(repo)
    for run in (1, 2):
        assert main(["pareto", "problems/indoor-manual.toml"]) == 0
        assert git("status", "--porcelain", "--untracked-files=all") == "", f"run {run} changed the checkout"
        assert (repo / "results" / "indoor-manual" / "run.json").is_file()


def test_html_is_self_contained(regenerated):
    """index.html loads nothing: no http(s) src/href, no external CSS/JS, no <img>; every figure is an inline
    <svg> in its <figure>, the same SVG as figures/<name>.svg beside report.md (which links those files)."""
    out, _ = regenerated
    html = (out / "index.html").read_text()
    assert not re.search(r"""(src|href)\s*=\s*["']?\s*(https?:)?//""", html, re.I)
    assert not re.search(r"\b(src|href)\s*=", html.replace('href="#', ""), re.I)  # only in-page links
    assert "<link" not in html.lower() and "<script" not in html.lower() and "<img" not in html.lower()
    md = (out / "report.md").read_text()
    for name in figures.FIGURES:
        block = re.search(rf'<figure id="fig-{name}">\s*<div class="plot"[^>]*>(<svg.*?</svg>)', html, re.S)
        assert block, name
        assert block.group(1) == (out / "figures" / f"{name}.svg").read_text().strip(), name
        assert f"](figures/{name}.svg)" in md, name


def test_page_figures_carry_their_data_on_hover(regenerated):
    """Every valid front point is a hover target in the front and variables figures, whose tooltip gives its
    P, F_turn and design to the printed digits of front.json; the paper figures show Table 1's wheels."""
    out, _ = regenerated
    html = (out / "index.html").read_text()
    data = json.loads((out / "front.json").read_text())

    def tips(name):
        svg = re.search(rf'<figure id="fig-{name}">(.*?)</figure>', html, re.S).group(1)
        return re.findall(r"<circle[^>]*><title>([^<]*)</title></circle>", svg)

    front_tips = tips("front")
    points = data["points"]  # the valid points (failed ones are in data["failed"])
    assert len(points) > 2
    for p in points:
        text = f"P {p['threshold_force']:.2f} N, F_turn {p['turning_effort']:.3f} N"
        assert any(t.startswith(text) for t in front_tips), text
        assert sum(t.startswith(text) for t in tips("variables")) >= 4  # one per panel
    assert any(t.startswith("build this") for t in front_tips)
    assert len([t for t in tips("trail") if t.startswith("wheel ")]) == 5  # C–G measured at 2 in
    assert len([t for t in tips("inertia") if t.startswith("wheel ")]) == 7  # all of Table 1
    assert any("least F_turn" in t for t in tips("groove_damper"))


def test_figure_files_opened_alone_hide_their_hover_targets(regenerated):
    """A figure file opened on its own (no page stylesheet) draws no dots of its own: every hover target in
    figures/*.svg is transparent by its attributes (SVG's default fill is black), and the page's stylesheet,
    which overrides presentation attributes, still styles them."""
    out, _ = regenerated
    circles = 0
    for svg in sorted((out / "figures").glob("*.svg")):
        for group in re.findall(r'<g class="hover">(.*?)</g>', svg.read_text(), re.S):
            for circle in re.findall(r"<circle[^>]*>", group):
                circles += 1
                assert 'fill-opacity="0"' in circle, (svg.name, circle)
    assert circles > 41  # the front's points at least
    assert ".hover circle" in (out / "index.html").read_text()


def test_main_job_computes_the_knock_safe_speeds_of_the_card(regenerated):
    """`designer pareto` simulates the knock-safe speeds of the recommendation and its alternatives only
    (θ0 and 2 θ0 knocks, m/s in front.json, the 2 θ0 one lower), times the step, and the card shows them."""
    out, _ = regenerated
    data = json.loads((out / "front.json").read_text())
    rec = data["recommendation"]
    assert 0 < rec["knock_safe_speed_double"] < rec["knock_safe_speed"]
    assert rec["knock_safe_speed"] == pytest.approx(rec["critical_speed"], rel=0.05)
    assert all("knock_safe_speed" in a for a in data["alternatives"])
    assert "knock_safe_speed" not in data["points"][0]
    assert json.loads((out / "run.json").read_text())["compute_cpu_seconds"]["knock_safe"] > 0
    md = (out / "report.md").read_text()
    panel = md[md.index("### Knock-safe speed: a second opinion") : md.index("## Summary")]
    speeds = [
        shown(rec[k], "critical_speed") for k in ("critical_speed", "knock_safe_speed", "knock_safe_speed_double")
    ]
    assert f"| recommended | {speeds[0]} | {speeds[1]} | {speeds[2]} |" in panel


def test_no_nan_anywhere(regenerated):
    """No NaN in a report: tables, Markdown, CSV and JSON."""
    out, _ = regenerated
    for name in FILES:
        text = (out / name).read_text()
        assert not re.search(r"\bnan\b|\binf\b", text, re.I), name


def test_title_is_escaped(invacare, tmp_path):
    """User text is shown as text: a <script> title is escaped in index.html and report.md."""
    import dataclasses

    problem, data = invacare
    evil = problem.replace(title='<script>alert("x")</script> & co')
    folder = write_report(dataclasses.replace(data, problem=evil), tmp_path / "r")
    html = (folder / "index.html").read_text()
    assert "<script>" not in html
    assert "&lt;script&gt;" in html
    assert "<script>" not in (folder / "report.md").read_text()


def test_single_point_front_explained(invacare, tmp_path):
    """A fixed-diameter problem has a one-point front; the report says why and still has every figure."""
    problem, data = invacare
    assert len(data.front) == 1
    folder = write_report(data, tmp_path / "inv")
    html = (folder / "index.html").read_text()
    assert "Why the front is a single point" in html and "fixed at 7.750 in" in html
    assert all((folder / f).is_file() for f in FIGURES)


def test_failed_write_leaves_nothing(invacare, tmp_path, monkeypatch):
    """An exception while writing leaves no report folder and no temporary folder; an old report stays intact."""
    problem, data = invacare

    def broken(*args, **kwargs):
        raise RuntimeError("figure failed")

    monkeypatch.setattr(figures, "figure_threshold", broken)
    with pytest.raises(RuntimeError, match="figure failed"):
        write_report(data, tmp_path / "new")
    assert list(tmp_path.iterdir()) == []
    # an existing report is not touched by a failed rewrite
    old = tmp_path / "old"
    old.mkdir()
    (old / "index.html").write_text("previous report")
    (old / "front.json").write_text('{"problem": "old", "points": []}')
    _prove_ours(old)  # a previous report of this tool: its manifest proves it
    with pytest.raises(RuntimeError):
        write_report(data, old)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["old"]
    assert (old / "index.html").read_text() == "previous report"
    assert sorted(p.name for p in old.iterdir()) == [MANIFEST, "front.json", "index.html"]


def test_cli_exit_1_when_a_front_check_fails(tmp_path, monkeypatch, capsys):
    """A failing check 8 gives exit 1, after the report is written (docs/commands.md)."""
    import designer.studies.checks as checks

    real = checks.front_checks

    def failing(front, tighter=None, **kw):
        out = real(front, tighter, **kw)
        return [dataclasses.replace(out[0], outcome=checks.FAILS), *out[1:]]  # records do not change: a copy

    monkeypatch.setattr(checks, "front_checks", failing)
    out = tmp_path / "inv"
    code = main(["pareto", str(ROOT / "problems" / "paper-invacare.toml"), "--out", str(out)])
    assert code == 1
    assert (out / "index.html").is_file()
    assert "check failed on the front" in capsys.readouterr().err
    verdicts = {c["name"]: c["passed"] for c in json.loads((out / "checks.json").read_text())}
    assert verdicts["8a trade-off"] is False


# ----------------------------------------------------------------------------------------------------
# Issue 12.4 and 24.1: replacing a report keeps the files of the folder that the report does not own.
import os

from designer.output import MANIFEST, TEMP_PREFIX, output_folder
from designer.report.files import REPORT_OWNED


def _report(folder, marker: str) -> None:
    folder.mkdir()
    (folder / "figures").mkdir()
    (folder / "figures" / "front.svg").write_text(marker)
    for name in ("index.html", "report.md", "front.csv", "checks.json"):
        (folder / name).write_text(marker)
    (folder / "front.json").write_text('{"problem": "%s", "points": []}' % marker)


def _prove_ours(folder) -> None:
    """The manifest a run of the tool leaves beside its report: every file of it by its sha256."""
    import hashlib
    import json

    files = {
        p.relative_to(folder).as_posix(): {
            "sha256": hashlib.sha256(p.read_bytes()).hexdigest(),
            "by": "designer pareto",
        }
        for p in folder.rglob("*")
        if p.is_file() and p.name != MANIFEST
    }
    (folder / MANIFEST).write_text(json.dumps({"schema": "caster-designer/manifest/1", "files": files}))


def _replace(stage, target) -> None:
    """Commit the report in ``stage`` into ``target`` as write_report does (designer.output.output_folder)."""
    with output_folder(target, REPORT_OWNED, command="designer pareto") as tmp:
        for entry in stage.iterdir():
            os.rename(entry, tmp / entry.name)
    stage.rmdir()


def test_replace_keeps_explore_files_and_user_files(tmp_path):
    """explore.csv / explore.json (written by `designer explore`) and a user's notes survive a report
    replace; the report's own files and figures are the new ones; no temporary or moved-aside entry is left."""
    target, stage = tmp_path / "indoor-manual", tmp_path / "stage"
    _report(target, "old")
    (target / "explore.csv").write_text("trail,diameter\n0.05,0.2\n")
    (target / "explore.json").write_text('{"trials": 500}')
    (target / "notes").mkdir()
    (target / "notes" / "why.txt").write_text("mine")
    (target / "figures" / "stale.svg").write_text("old")  # an older run's figure: replaced whole
    _prove_ours(target)
    (target / "explore.csv").write_text("trail,diameter\n0.05,0.2\n")  # explore's own, not the report's
    (target / "notes" / "why.txt").write_text("mine")
    _report(stage, "new")
    _replace(stage, target)
    assert (target / "explore.csv").read_text() == "trail,diameter\n0.05,0.2\n"
    assert (target / "explore.json").read_text() == '{"trials": 500}'
    assert (target / "notes" / "why.txt").read_text() == "mine"
    assert (target / "index.html").read_text() == "new" and '"new"' in (target / "front.json").read_text()
    assert sorted(p.name for p in (target / "figures").iterdir()) == ["front.svg"]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["indoor-manual"]
    assert not [p for p in target.iterdir() if p.name.startswith(TEMP_PREFIX)]


def test_replace_failure_keeps_old_report_whole(tmp_path, monkeypatch):
    """If a rename fails half-way through the commit, every entry already replaced is put back: the folder is
    the old report, whole (no mixture of old and new), explore.csv is untouched, nothing temporary is left."""
    target, stage = tmp_path / "r", tmp_path / "stage"
    _report(target, "old")
    _prove_ours(target)
    (target / "explore.csv").write_text("keep")
    _report(stage, "new")
    real_replace = os.replace
    calls = {"n": 0}

    def failing(src, dst, *a, **k):
        if Path(dst).name == "index.html" and calls["n"] == 0:  # after checks, figures, front.* moved in
            calls["n"] += 1
            raise PermissionError(13, "Permission denied")
        return real_replace(src, dst, *a, **k)

    monkeypatch.setattr(os, "replace", failing)
    with pytest.raises(PermissionError):
        _replace(stage, target)
    monkeypatch.undo()
    assert calls["n"] == 1
    assert (target / "explore.csv").read_text() == "keep"
    for name in ("index.html", "report.md", "front.csv", "checks.json", "figures/front.svg"):
        assert (target / name).read_text() == "old", name
    assert '"old"' in (target / "front.json").read_text()
    assert sorted(p.name for p in target.iterdir()) == sorted(
        ["explore.csv", "figures", "index.html", "report.md", "front.csv", "front.json", "checks.json", MANIFEST]
    )


# ----------------------------------------------------------------------------------------------------
# Issue 12.2: no numerical noise from the package, and labels that say what was used (weights, units).
import warnings

import pytest


from conftest import ROOT

INDOOR = str(ROOT / "problems" / "indoor-manual.toml")


def test_structured_swept_radius_without_divide_by_zero():
    """The closed-form designs get T_max = R_max − d/2 from the geometry, not by evaluating the whole model
    at T = 0 (F_turn = M/T divided by zero on every pareto run); any warning here is an error."""
    from designer.problem import load_problem
    from designer.solvers import closed_form as structured

    problem = load_problem(INDOOR)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        x, ok = structured.designs_at_diameter(problem, np.linspace(4, 8, 9) * 0.0254)
    # trail = min(2.5 in, 6 in − d/2): the swept-radius limit binds above d = 7 in
    assert x[:, 0] == pytest.approx(np.minimum(2.5, 6 - np.linspace(4, 8, 9) / 2) * 0.0254)
    assert ok.all()


def test_package_runtime_warnings_fail_the_suite():
    """pyproject's filterwarnings turns a RuntimeWarning raised from a designer module into an error,
    while the same warning from elsewhere stays a warning."""
    code = compile("import warnings\nwarnings.warn('divide by zero', RuntimeWarning)\n", "designer/fake.py", "exec")
    with pytest.raises(RuntimeWarning, match="divide by zero"):
        exec(code, {"__name__": "designer.fake"})
    with pytest.warns(RuntimeWarning):
        exec(code, {"__name__": "elsewhere"})


def test_extrapolation_warning_only_for_reported_diameters():
    """The inertia-extrapolation warning names reported designs outside 4–8 in, never the bounds alone."""
    from designer.problem import load_problem

    problem = load_problem(INDOOR)  # diameter bounds 3–8 in reach outside Table 1
    assert problem.model_warnings([8 * 0.0254, 6 * 0.0254]) == []
    (message,) = problem.model_warnings([3.5 * 0.0254, 6 * 0.0254])
    assert "a reported design uses d = 3.5 in, outside the Table 1 inertia fit (4–8 in)" in message
    # a front's points are called so: the recommended caster may lie inside 4–8 in while the front's end does not
    (message,) = problem.model_warnings([3.5 * 0.0254, 3.75 * 0.0254, 6 * 0.0254], front=True)
    assert "points of the front use d = 3.5–3.75 in, outside the Table 1 inertia fit (4–8 in)" in message


def test_optimise_inside_table1_does_not_warn():
    """indoor-manual's bounds reach 3 in, but its (risk-bounded) optimum lies inside Table 1's 4-8 in
    (d = 7.72 in): no extrapolation warning."""
    from designer.studies.optimum import optimise
    from designer.problem import load_problem

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        solution = optimise(load_problem(INDOOR), cross_check=False)
    assert 4 * 0.0254 <= solution.design.diameter <= 8 * 0.0254 * (1 + 1e-9)
    assert not [w for w in caught if "extrapolated" in str(w.message)]


def test_run_weights_printed_and_recorded(capsys):
    """run --weights 10,1 prints the weights used (was the problem's '1, 1') and JSON records them; the one-screen
    answer says where they act (the weighted optimum, shown by --verbose)."""
    assert main(["run", INDOOR, "--weights", "10,1", "--no-cross-check", "--verbose"]) == 0
    assert "(weights 10, 1)" in capsys.readouterr().out
    assert main(["run", INDOOR, "--weights", "10,1", "--no-cross-check"]) == 0
    assert "--weights 10,1 sets the weighted optimum" in " ".join(capsys.readouterr().out.split())
    assert main(["run", INDOOR, "--weights", "10,1", "--no-cross-check", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["weights"] == [10.0, 1.0]


@pytest.mark.parametrize(
    "argv, fragment",
    [
        (["--weights", "-1,1"], "--weights = [-1.0, 1.0]: w_turn = -1 must be a finite non-negative number"),
        (["--weights=-1,1"], "--weights = [-1.0, 1.0]: w_turn = -1 must be a finite non-negative number"),
        (["--weights", "1,-2"], "--weights = [1.0, -2.0]: w_threshold = -2 must be a finite non-negative number"),
    ],
)
def test_negative_weights_named(argv, fragment, capsys):
    """A negative weight is named with its value (argparse used to take '-1,1' for an option)."""
    assert main(["run", INDOOR] + argv) == 2
    assert fragment in capsys.readouterr().err


def test_explore_summary_shows_units(tmp_path, capsys, monkeypatch):
    """The explore front table's headers keep their units (rich read '[in]' as a markup tag and dropped it);
    at 200 columns, so that no header is folded."""
    monkeypatch.setenv("COLUMNS", "200")
    assert main(["explore", INDOOR, "--trials", "20", "--no-compare", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    for header in ("T [in]", "d [in]", "B [in]", "c_f [N·m/rad]", "V_c [m/s]"):
        assert header in out


def test_calibration_rms_residual_has_unit(capsys):
    """The calibration summary gives the rms residual with the unit of the fitted quantity."""
    data = ROOT / "designer" / "data" / "examples"
    assert main(["calibrate", "turning", str(data / "turning_tile.csv")]) == 0
    assert "rms residual" in (out := capsys.readouterr().out)
    assert " N·m;" in out.split("rms residual", 1)[1].split(")")[0] + ")"
    assert main(["calibrate", "slip", str(data / "slip.csv"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["rms_residual_unit"] == "N"


def test_first_screen_panels_render_in_both_files(invacare, tmp_path, monkeypatch):
    """A first-screen Panel (heading, sentence, table, drawing, caption) appears in the "Build this" card of
    index.html (escaped, the drawing inline) and of report.md (a Markdown table, the drawing as figures/<id>.svg),
    with no template change: the extension point for the card's new content."""
    from designer.report import context

    panel = context.Panel(
        id="spec",
        title="Buy to this spec",
        text="Any 7 in wheel <under> 1.17e-3 kg·m²",
        table=context.PanelTable(["part", "value"], [["trail", "2.500 in"], ["max_inertia", "1.17e-3"]], [False, True]),
        svg='<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"><circle r="3"/></svg>',
        caption="Spec drawn to scale.",
    )
    monkeypatch.setattr(context, "_panels", lambda data: [panel])
    folder = write_report(invacare[1], tmp_path / "r")
    html = (folder / "index.html").read_text()
    card = html.split('<section class="build" id="build">', 1)[1].split("</section>", 1)[0]
    assert '<div class="panel" id="panel-spec">' in card and "<h3>Buy to this spec</h3>" in card
    assert "Any 7 in wheel &lt;under&gt; 1.17e-3" in card
    assert '<td class="num">1.17e-3</td>' in card and '<circle r="3"/>' in card
    md = (folder / "report.md").read_text()
    assert "### Buy to this spec" in md and "| part | value |" in md and "|---|---:|" in md
    assert "| max_inertia | 1.17e-3 |" in md and "![Buy to this spec](figures/spec.svg)" in md
    assert (folder / "figures" / "spec.svg").read_text().startswith("<svg")
    assert md.index("### Buy to this spec") < md.index("## Summary")


def test_report_shows_the_risk_law_its_spec_and_its_checks():
    """The committed indoor-manual report (kept current by test_committed_results_are_current) shows, on its first
    screen, where the risk comes from (each source with its kind and share), the spec to inspect against (each
    part's limit: the bearing's friction moment, the largest measured wheel inertia), what measuring the wheel
    allows, the knock-safe
    speed's Table 1 error beside it; and in its checks the leave-one-out check of the law with its count and the
    word that it is coarse."""
    text = (ROOT / "results" / "indoor-manual" / "report.md").read_text(encoding="utf-8")
    first = text[: text.index("## Summary")]
    for needle in (
        "### Where the risk comes from",
        "| wheel inertia (diameter only) | Student-t, ν = 5 |",
        "### The spec to inspect against",
        # nominal, tolerance, the joint box (every part inside passes), then one part at a time (others at nominal)
        "| bearing friction moment M_f = c_f θ0 | 0.454 N·m | — | min 0.393 N·m [risk] | min 0.251 N·m [risk] |",
        "| measured wheel inertia I_w | 0.00117 kg·m² | — | max 0.00133 kg·m² [risk] | max 0.00206 kg·m² [risk] |",
        "### If you measure the wheel",
        "log RMS error of 0.153",
        "The design criterion is the risk bound on Eq. 7",
    ):
        assert needle in first, needle
    checks = json.loads((ROOT / "results" / "indoor-manual" / "checks.json").read_text(encoding="utf-8"))
    loo = [c for c in checks if c["name"] == "11 leave-one-out"]
    assert len(loo) == 1 and loo[0]["kind"] == "law" and "coarse check" in loo[0]["detail"]
    assert loo[0]["got"].startswith("from d ") and len(loo[0]["rows"]) == 5


def _contour_offsets_px(data) -> list[float]:
    """How far [px] each vertex of the groove–damper figure's iso-V_c lines lies from the model's V_c = level line:
    |V_c(vertex) − level| over |∇V_c| in px (the figure's own scales), V_c from designer.model.performance."""
    from designer.model import performance
    from designer.plots.figures import MM
    from designer.report import figures as report_figures

    fig = report_figures.draw("groove_damper", data)
    fig.to_svg()  # lays the axes out (their boxes in px)
    plane = fig.axes[1]
    sx, sy, _, _ = plane._scales()
    per_x, per_y = abs(float(sx(1.0) - sx(0.0))), abs(float(sy(1.0) - sy(0.0)))  # px per mm of B, per N·m/rad
    design, conditions = data.solution.design, data.solution.problem.conditions

    def speed(g_mm, c):
        return performance(design.trail, design.diameter, g_mm / MM, c, conditions)["critical_speed"]

    offsets = []
    for lines in (args[0] for _, _, kind, args in plane.items if kind == "contour"):
        for level, pieces in lines.paths:
            for piece in pieces:
                g, c = piece[:, 0], piece[:, 1]
                v = speed(g, c)
                grad = np.hypot((speed(g + 0.5 / per_x, c) - v) / 0.5, (speed(g, c + 0.5 / per_y) - v) / 0.5)
                offsets.extend(np.abs(v - level) / grad)
    return offsets


def test_groove_damper_contours_lie_on_the_model(invacare, monkeypatch):
    """The groove–damper figure's iso-V_c lines, whose values no data file holds, checked by number: every vertex lies
    within the drawing tolerance (0.5 px, designer.report.agreement.DRAWING_PX) of the model's V_c = level line at
    the weighted optimum's T and d; a figure drawn from a V_c 2 % off (planted) fails it."""
    from designer.report.agreement import DRAWING_PX

    _, data = invacare
    offsets = _contour_offsets_px(data)
    assert len(offsets) > 100 and max(offsets) <= DRAWING_PX, max(offsets)

    plane = data.curves["plane"]  # the pipeline's plane (designer.studies.curves), planted 2 % off
    monkeypatch.setitem(data.curves, "plane", dict(plane, critical_speed=plane["critical_speed"] * 1.02))
    assert max(_contour_offsets_px(data)) > DRAWING_PX
