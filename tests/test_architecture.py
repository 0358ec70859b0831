"""The layer contract: data flows one way, model -> problem -> solvers -> studies -> pipeline -> report -> CLI;
and the rooms are cut by purpose: no private name crosses a room, and no folder keeps a prefix cluster.

Every ``import`` in the package, including the ones inside functions, is read from the source (AST), so
a late import cannot hide an upward arrow or a cycle.  CONTRIBUTING.md draws the same layers.
"""

from __future__ import annotations

import ast
import sys
from pathlib import Path


PACKAGE = Path(__file__).resolve().parents[1] / "designer"

LAYERS: list[tuple[str, tuple[str, ...]]] = [
    (
        "ground",
        (
            "designer.errors",
            "designer.children",
            "designer.textfiles",
            "designer.output",
            "designer.units",
            "designer.boundary",
            "designer.jsonsafe",
            "designer.data",
            "designer.parameters",
            "designer.display",
            "designer.reprs",
            "designer.versions",
        ),
    ),
    ("physics", ("designer.physics",)),
    ("model", ("designer.model",)),
    ("problem", ("designer.problem",)),
    ("plots", ("designer.plots",)),
    ("solvers", ("designer.solvers",)),
    ("studies", ("designer.studies",)),
    ("reportdata", ("designer.reportdata",)),
    ("pipeline", ("designer.pipeline",)),
    ("report", ("designer.report",)),
    ("jobs", ("designer.jobs",)),
    ("entry", ("designer.cli", "designer.studio", "designer.__main__", "designer.entry")),
]
"""Lowest first.  A module may import its own layer and the layers below it, never one above."""

HEAVY = (
    "casadi",
    "cvxpy",
    "optuna",
    "matplotlib",
    "scipy.stats",
    "pandas",
    "dask",
    "distributed",
    "dash",
    "panel",
    "plotly",
    "pgserver",
    "psycopg2",
    "jinja2",
    "pymoo",
    "sqlalchemy",
)
"""Dependencies that ``import designer`` must not load: imported late, inside the functions that need them."""


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def layer_of(module: str) -> int | None:
    for index, (_, prefixes) in enumerate(LAYERS):
        if any(module == p or module.startswith(p + ".") for p in prefixes):
            return index
    return None


def imports_of(path: Path) -> list[tuple[str, int, bool]]:
    """(imported module, line, at module level) for every designer import in a file."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    module = module_name(path)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    top_level = {id(node) for node in tree.body}
    out = []
    for node in ast.walk(tree):
        names: list[str] = []
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = node.module or ""
            if node.level:
                base = ".".join(
                    package.split(".")[: len(package.split(".")) - node.level + 1] + ([base] if base else [])
                )
            names = [base] + [f"{base}.{alias.name}" for alias in node.names]
        for name in names:
            if name.startswith("designer.") and (name in ALL_MODULES or name == names[0]):
                out.append((name, node.lineno, id(node) in top_level))
    return out


ALL_FILES = sorted(PACKAGE.rglob("*.py"))
ALL_MODULES = {module_name(p) for p in ALL_FILES}


def test_every_module_has_a_layer():
    """Every module of the package belongs to exactly one layer of the contract (no module outside it)."""
    missing = [m for m in ALL_MODULES if m != "designer" and layer_of(m) is None]
    assert missing == []


def test_no_upward_import():
    """No module imports a module of a higher layer (function-local imports included)."""
    upward = []
    for path in ALL_FILES:
        source = module_name(path)
        if source == "designer":  # the package's lazy public API may name anything
            continue
        for target, line, _ in imports_of(path):
            if target == "designer":
                continue
            low, high = layer_of(source), layer_of(target)
            if high is not None and low is not None and high > low:
                upward.append(f"{source}:{line} imports {target} ({LAYERS[low][0]} -> {LAYERS[high][0]})")
    assert upward == []


def test_no_import_cycle():
    """The module import graph (every import, late ones included) has no cycle."""
    graph: dict[str, set[str]] = {m: set() for m in ALL_MODULES}
    for path in ALL_FILES:
        source = module_name(path)
        if source == "designer":
            continue
        for target, _, _ in imports_of(path):
            while target not in ALL_MODULES and "." in target:
                target = target.rsplit(".", 1)[0]
            if target in ALL_MODULES and target not in (source, "designer"):
                graph[source].add(target)
    # Tarjan-free check: depth-first search with colours
    colour: dict[str, int] = {}
    cycles = []

    def visit(node: str, stack: list[str]) -> None:
        colour[node] = 1
        for nxt in sorted(graph[node]):
            if colour.get(nxt) == 1:
                cycles.append(" -> ".join(stack[stack.index(nxt) :] + [nxt]) if nxt in stack else f"{node} -> {nxt}")
            elif colour.get(nxt) is None:
                visit(nxt, stack + [nxt])
        colour[node] = 2

    for node in sorted(graph):
        if node not in colour:
            visit(node, [node])
    assert cycles == []


def test_the_contract_catches_an_upward_import(tmp_path):
    """The checker is not vacuous: a physics module importing the solvers is reported as upward."""
    fake = PACKAGE / "physics" / "_contract_probe.py"
    assert not fake.exists()
    try:
        fake.write_text("from designer.solvers.nlp import CasterNLP\n")
        source = module_name(fake)
        found = [(t, layer_of(t)) for t, _, _ in imports_of(fake)]
        assert any(layer > layer_of(source) for _, layer in found if layer is not None)
    finally:
        fake.unlink()


def test_import_designer_is_light():
    """``import designer`` loads NumPy and the physics only: none of the heavy dependencies."""
    import subprocess

    code = "import sys, designer; heavy = %r; print(sorted(h for h in heavy if h in sys.modules))" % (HEAVY,)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert out == "[]"


LATE = HEAVY + ("scipy", "pint", "rich", "werkzeug", "flask", "contourpy", "selenium", "fcntl", "shtab")
"""What a function may import inside itself: a heavy or optional library (CONTRIBUTING, "Heavy dependencies
load late"; fcntl exists on POSIX only; shtab takes ~40 ms, for `designer completion` only), or a designer module whose import would load one."""

LATE_ENTRY = {"designer.entry": "designer.cli"}
"""The one late import of a light designer module: the console script installs its signal handlers first and
then imports the whole command line (designer/entry.py)."""


def _top_imports(path: Path) -> set[str]:
    """Modules a file imports when it is imported: its module-level imports (also in top-level ``try``/``if``
    blocks, but not under ``if TYPE_CHECKING``), with the designer packages that contain them; a module-level
    ``__getattr__`` counts too (it serves names of the module: using them loads what it imports)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    module = module_name(path)
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    out: set[str] = set()

    def visit(nodes) -> None:
        for node in nodes:
            if isinstance(node, ast.If) and "TYPE_CHECKING" in ast.unparse(node.test):
                continue
            if isinstance(node, ast.FunctionDef) and node.name == "__getattr__":
                visit(node.body)
            elif isinstance(node, (ast.If, ast.Try)):
                visit(node.body + node.orelse + getattr(node, "finalbody", []))
                for handler in getattr(node, "handlers", []):
                    visit(handler.body)
            elif isinstance(node, ast.Import):
                out.update(alias.name for alias in node.names)
            elif isinstance(node, ast.ImportFrom) and node.module != "__future__":
                base = node.module or ""
                if node.level:
                    base = ".".join(
                        package.split(".")[: len(package.split(".")) - node.level + 1] + ([base] if base else [])
                    )
                out.add(base)
                out.update(f"{base}.{alias.name}" for alias in node.names if f"{base}.{alias.name}" in ALL_MODULES)

    visit(tree.body)
    return {parent for name in out for parent in _with_parents(name)}


def _with_parents(name: str) -> list[str]:
    """``a.b.c`` and, for a designer module, the packages it is in (importing it imports them)."""
    parts = name.split(".")
    if parts[0] != "designer":
        return [name]
    return [".".join(parts[:k]) for k in range(2, len(parts) + 1)]


_LOADS: dict[str, bool] = {}


def loads_late_library(module: str, seen: frozenset = frozenset()) -> bool:
    """Whether importing designer ``module`` loads a library of :data:`LATE` (through its own module-level imports
    and those of the designer modules it imports)."""
    if module in _LOADS:
        return _LOADS[module]
    path = PACKAGE.parent / (module.replace(".", "/") + ".py")
    if not path.exists():
        path = PACKAGE.parent / module.replace(".", "/") / "__init__.py"
    if not path.exists() or module in seen:
        return False
    found = False
    for name in _top_imports(path):
        if name.startswith("designer."):
            found = name in ALL_MODULES and loads_late_library(name, seen | {module})
        else:
            found = any(name == lib or name.startswith(lib + ".") for lib in LATE)
        if found:
            break
    _LOADS[module] = found
    return found


def _module_of(path: Path) -> str | None:
    """The module name of a file of the package (None for a file elsewhere, such as a planted probe)."""
    try:
        return module_name(path)
    except ValueError:
        return None


def late_imports_without_reason(path: Path) -> list[str]:
    """Imports inside a function of ``path`` that are neither of a :data:`LATE` library nor of a designer module
    that loads one (such an import belongs at the top of the module)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for func in ast.walk(tree):
        if not isinstance(func, (ast.FunctionDef, ast.AsyncFunctionDef)):
            continue
        for node in ast.walk(func):
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                modules = [f"{node.module}.{alias.name}" for alias in node.names]  # `from pkg import module`
                names = [m for m in modules if m in ALL_MODULES] or [node.module]
            else:
                continue
            for name in names:
                if name.startswith("designer"):
                    ok = loads_late_library(name) or LATE_ENTRY.get(_module_of(path)) == name
                else:
                    ok = any(name == lib or name.startswith(lib + ".") for lib in LATE)
                if not ok:
                    found.append(f"line {node.lineno}: {ast.unparse(node)}")
    return sorted(set(found))


def test_late_imports_are_of_heavy_libraries():
    """A function-local import is only of a heavy or optional library, or of a designer module whose import
    would load one (CONTRIBUTING: "Heavy dependencies load late"); every other import sits at the top."""
    offenders = {
        str(path.relative_to(PACKAGE)): found for path in ALL_FILES if (found := late_imports_without_reason(path))
    }
    assert offenders == {}


def test_the_late_import_rule_catches_a_light_late_import(tmp_path):
    """The rule is not vacuous: a late ``import json`` or a late import of the (light) parameter table is
    reported; a late matplotlib, scipy.optimize or designer.studies.front (which loads casadi) is not."""
    probe = tmp_path / "probe.py"
    probe.write_text(
        "def f():\n    import json\n    from designer.parameters import VARIABLES\n"
        "    import matplotlib.pyplot as plt\n    from scipy.optimize import brentq\n"
        "    from designer.studies.front import pareto_front\n"
    )
    assert late_imports_without_reason(probe) == [
        "line 2: import json",
        "line 3: from designer.parameters import VARIABLES",
    ]
    assert loads_late_library("designer.studies.front") and not loads_late_library("designer.parameters")


# --------------------------------------------------------------------------- rooms by purpose


def room_of(module: str) -> str:
    """The room of a module: ``designer.<x>``, or ``designer.studies.<x>`` for a study (each study is a room)."""
    parts = module.split(".")
    if len(parts) >= 3 and parts[1] == "studies":
        return ".".join(parts[:3])
    return ".".join(parts[:2])


def _is_private(dotted: str) -> bool:
    return any(part.startswith("_") and part != "__init__" for part in dotted.split(".")[1:])


def private_imports(path: Path) -> list[str]:
    """Imports in ``path`` of a ``_private`` module or name that belongs to another room."""
    source = module_name(path)
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0 and node.module.startswith("designer"):
            if _is_private(node.module):  # the module itself is private: one finding for the statement
                targets = [node.module]
            else:
                targets = [f"{node.module}.{alias.name}" for alias in node.names]
        elif isinstance(node, ast.Import):
            targets = [alias.name for alias in node.names if alias.name.startswith("designer")]
        else:
            continue
        for target in targets:
            if room_of(target) != room_of(source) and _is_private(target):
                found.append(f"{source}:{node.lineno} imports {target}")
    return found


def prefix_clusters(folder: Path) -> dict[str, list[str]]:
    """Groups of three or more modules of one folder whose names share a prefix before ``_`` (``recommend_*``)."""
    groups: dict[str, list[str]] = {}
    for path in folder.glob("*.py"):
        stem = path.stem.lstrip("_")
        if path.stem == "__init__" or "_" not in stem:
            continue
        groups.setdefault(stem.split("_", 1)[0], []).append(path.name)
    for path in folder.glob("*.py"):  # a module named as the prefix itself (recommend.py beside recommend_rule.py)
        stem = path.stem.lstrip("_")
        if stem in groups and path.name not in groups[stem]:
            groups[stem].append(path.name)
    return {prefix: sorted(names) for prefix, names in groups.items() if len(names) >= 3}


def test_no_private_name_crosses_a_room():
    """No module imports a ``_private`` module or name of another room: a room is used through its ``__init__``."""
    crossing = [line for path in ALL_FILES if module_name(path) != "designer" for line in private_imports(path)]
    assert crossing == []


def test_no_prefix_cluster():
    """No folder of the package keeps three or more modules sharing a name prefix: such a group is a package."""
    clusters = {
        str(folder.relative_to(PACKAGE.parent)): groups
        for folder in [PACKAGE, *sorted(p for p in PACKAGE.rglob("*") if p.is_dir())]
        if (groups := prefix_clusters(folder))
    }
    assert clusters == {}


def test_every_package_states_its_api():
    """Every package of ``designer`` has an ``__init__`` with an ``__all__`` naming only names it defines or imports
    (or its public modules, for a package of modules such as ``plots``)."""
    missing = []
    for init in sorted(PACKAGE.rglob("__init__.py")):
        if "templates" in init.parts:
            continue
        tree = ast.parse(init.read_text(encoding="utf-8"))
        names = {
            alias.asname or alias.name.split(".")[0]
            for node in tree.body
            if isinstance(node, (ast.Import, ast.ImportFrom))
            for alias in node.names
        }
        names |= {
            t.id for node in tree.body if isinstance(node, ast.Assign) for t in node.targets if isinstance(t, ast.Name)
        }
        names |= {node.name for node in tree.body if isinstance(node, (ast.FunctionDef, ast.ClassDef))}
        names |= {  # served lazily by a module-level __getattr__
            alias.asname or alias.name
            for node in tree.body
            if isinstance(node, ast.FunctionDef) and node.name == "__getattr__"
            for inner in ast.walk(node)
            if isinstance(inner, ast.ImportFrom)
            for alias in inner.names
        }
        names |= {p.stem for p in init.parent.glob("*.py")} | {p.name for p in init.parent.iterdir() if p.is_dir()}
        declared = [
            node
            for node in tree.body
            if isinstance(node, ast.Assign) and any(isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets)
        ]
        if not declared:
            missing.append(f"{init.relative_to(PACKAGE.parent)}: no __all__")
            continue
        try:
            listed = ast.literal_eval(declared[0].value)
        except ValueError:
            continue  # computed (designer/__init__: the lazy names)
        unknown = [n for n in listed if n not in names]
        if unknown:
            missing.append(f"{init.relative_to(PACKAGE.parent)}: __all__ names {unknown} it does not define")
    assert missing == []


def test_the_room_rule_catches_a_private_import():
    """The private-name rule is not vacuous: a planted report module importing a study's private module, or a
    study's private name, is reported; the same import inside the study's own room is not."""
    fake = PACKAGE / "report" / "_contract_probe.py"
    inside = PACKAGE / "studies" / "recommend" / "_contract_probe.py"
    assert not fake.exists() and not inside.exists()
    try:
        fake.write_text(
            "from designer.studies.recommend._stock import stock_candidates\n"
            "from designer.studies.optimum import _secret\n"
        )
        inside.write_text("from designer.studies.recommend._stock import stock_candidates\n")
        found = private_imports(fake)
        assert len(found) == 2 and "designer.studies.recommend._stock" in found[0] and "_secret" in found[1]
        assert private_imports(inside) == []
    finally:
        fake.unlink(missing_ok=True)
        inside.unlink(missing_ok=True)


def test_the_cluster_rule_catches_a_prefix_cluster(tmp_path):
    """The cohesion rule is not vacuous: three modules ``fleet.py``, ``fleet_rule.py``, ``fleet_table.py`` in one
    folder are a cluster; two are not."""
    for name in ("fleet.py", "fleet_rule.py"):
        (tmp_path / name).write_text("")
    assert prefix_clusters(tmp_path) == {}
    (tmp_path / "fleet_table.py").write_text("")
    assert prefix_clusters(tmp_path) == {"fleet": ["fleet.py", "fleet_rule.py", "fleet_table.py"]}


# --------------------------------------------------------------------------- one evaluator

COMPOSED = (
    "turning_effort",
    "threshold_force",
    "threshold_force_ratio",
    "critical_shimmy_speed",
    "shimmy_probability_mc_many",
    "law_draws",
)
"""Physics functions of the objectives, Eq. 7 and the Monte Carlo of the risk law: outside the layers below, a
caster's F_turn, P, V_c and P(shimmy) come from the model (``designer.model.evaluate``), never from these."""

MAY_COMPOSE = ("designer.physics", "designer.model", "designer.solvers")
"""The rooms that may call them: the physics itself, the model that composes it, the solvers that build it into
their programs (the figures ask the model too)."""


def composed_physics_uses(path: Path) -> list[str]:
    """Uses in ``path`` of a function of :data:`COMPOSED`: imported from ``designer.physics`` (``from
    designer.physics.threshold import threshold_force``), or called on a physics module (``threshold.
    threshold_force(...)`` after ``from designer.physics import threshold`` or ``import designer.physics...``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    modules: set[str] = set()
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            for alias in node.names:
                dotted = f"{node.module}.{alias.name}"
                if node.module.startswith("designer.physics") and alias.name in COMPOSED:
                    found.append(f"line {node.lineno}: imports {dotted}")
                elif dotted.startswith("designer.physics"):
                    modules.add(alias.asname or alias.name)
        elif isinstance(node, ast.Import):
            modules |= {alias.asname or alias.name for alias in node.names if alias.name.startswith("designer.physics")}
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in COMPOSED:
            if ast.unparse(node.func.value) in modules:
                found.append(f"line {node.lineno}: calls {ast.unparse(node.func)}")
    return found


def test_only_the_model_composes_the_objectives():
    """No module outside physics/, model/ and solvers/ calls turning_effort, threshold_force, threshold_force_ratio,
    critical_shimmy_speed or the Monte Carlo (shimmy_probability_mc_many, law_draws): the studies, the plots, the
    pipeline, the report, the CLI and the studio ask the model."""
    offenders = [
        f"{module_name(path)}: {use}"
        for path in ALL_FILES
        if not any(module_name(path).startswith(room) for room in MAY_COMPOSE)
        for use in composed_physics_uses(path)
    ]
    assert offenders == []


def test_the_evaluator_rule_catches_a_study_composing_physics(tmp_path):
    """The rule is not vacuous: a planted study importing threshold_force_ratio, one calling turning.turning_effort
    on the physics module, and one importing Eq. 7's critical_shimmy_speed and calling the Monte Carlo are all
    reported; model.performance is not."""
    imports = tmp_path / "imports.py"
    imports.write_text("from designer.physics.threshold import threshold_force_ratio\n")
    calls = tmp_path / "calls.py"
    calls.write_text(
        "from designer.physics import turning as t\nimport designer.physics.threshold\n"
        "f = t.turning_effort(0.05, 0.0, 1.3, 178.0)\n"
        "p = designer.physics.threshold.threshold_force(0.2, 0.0127, 178.0)\n"
    )
    eq7 = tmp_path / "eq7.py"
    eq7.write_text(
        "from designer.physics.shimmy import critical_shimmy_speed\n"
        "from designer.physics import uncertainty as u\n"
        "p = u.shimmy_probability_mc_many(0.05, 1e-3, 0.0, 1.3, 1250.0, 2.5, None)\n"
    )
    assert composed_physics_uses(eq7) == [
        "line 1: imports designer.physics.shimmy.critical_shimmy_speed",
        "line 3: calls u.shimmy_probability_mc_many",
    ]
    clean = tmp_path / "clean.py"
    clean.write_text("from designer.model import performance\nrec = None\nP = rec.threshold_force if rec else 0\n")
    assert composed_physics_uses(imports) == ["line 1: imports designer.physics.threshold.threshold_force_ratio"]
    assert composed_physics_uses(calls) == [
        "line 3: calls t.turning_effort",
        "line 4: calls designer.physics.threshold.threshold_force",
    ]
    assert composed_physics_uses(clean) == []


# --------------------------------------------------------------------------- the renderer computes nothing

RENDERERS = ("designer.report", "designer.plots")
"""The rooms that only render: they take report data or records and import no study and not the pipeline."""
COMPUTERS = ("designer.studies", "designer.pipeline")


def renderer_imports(path: Path, module: str) -> list[str]:
    """The imports of a study or of the pipeline in ``path`` (module ``module``), when it is a renderer's."""
    if not any(module == r or module.startswith(r + ".") for r in RENDERERS):
        return []
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        else:
            continue
        found += [
            f"{module}:{node.lineno} imports {name}"
            for name in names
            if any(name == c or name.startswith(c + ".") for c in COMPUTERS)
        ]
    return found


def test_report_and_plots_import_no_study_nor_the_pipeline():
    """report/ and plots/ import nothing from studies/ or the pipeline (function-local imports included)."""
    offenders = [use for path in ALL_FILES for use in renderer_imports(path, module_name(path))]
    assert offenders == []


def test_the_renderer_rule_catches_a_planted_import(tmp_path):
    """The rule is not vacuous: a planted report module importing the pipeline inside a function, and a planted
    plots module importing a study, are reported; the same imports in a study are not."""
    report = tmp_path / "report_mod.py"
    report.write_text("def f():\n    from designer.pipeline import report_data\n    return report_data\n")
    plots = tmp_path / "plots_mod.py"
    plots.write_text("import designer.studies.checks\n")
    assert renderer_imports(report, "designer.report.planted") == [
        "designer.report.planted:2 imports designer.pipeline"
    ]
    assert renderer_imports(plots, "designer.plots.planted") == [
        "designer.plots.planted:1 imports designer.studies.checks"
    ]
    assert renderer_imports(report, "designer.studies.planted") == []
    assert renderer_imports(report, "designer.reportdata") == []  # the hand-over, not a renderer


# --------------------------------------------------------------------------- surfaces render records

EVALUATORS = (
    "evaluate",
    "performance",
    "critical_speed",
    "critical_shimmy_speed",
    "turning_effort",
    "turning_moment",
    "threshold_force",
    "threshold_force_ratio",
    "threshold_force_ratio_approx",
    "shimmy_probability",
    "shimmy_probability_mc_many",
    "shimmy_speed_quantile",
    "risk_record",
    "inertia_prediction",
    "shimmy_frequency",
    "steady_shimmy_amplitude",
    "effective_trail",
    "ground_trail",
    "weighted",
)
"""The evaluation functions of the model and the physics (and J's one expression): a surface shows the numbers a
record holds and calls none of these."""

SURFACES = ("designer.report", "designer.plots", "designer.studio")
"""The rooms that render records: report/, plots/ and the studio."""

EVALUATING_ROOMS = ("designer.model", "designer.physics")
"""Where the evaluation functions live: the model and the physics (and the public API, ``designer.evaluate``)."""


def _in(module: str, rooms) -> bool:
    return any(module == r or module.startswith(r + ".") for r in rooms)


def evaluation_uses(path: Path) -> list[str]:
    """Imports of an evaluation function (:data:`EVALUATORS`) from the public API, the model or the physics, and
    calls of one on an imported model or physics module or on any object (``problem.evaluate(...)``)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    found = []
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.ImportFrom)
            and node.level == 0
            and (node.module == "designer" or _in(node.module or "", EVALUATING_ROOMS))
        ):
            found += [
                f"line {node.lineno}: imports {node.module}.{alias.name}"
                for alias in node.names
                if alias.name in EVALUATORS
            ]
        elif isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and node.func.attr in EVALUATORS:
            found.append(f"line {node.lineno}: calls {ast.unparse(node.func)}")
    return found


SURFACE_EVALUATES: dict[str, int] = {}
"""Known offenders among the surfaces and how many uses each has: none (issue 41; the studio's card reads a front
point's risk from designer.fix's diagnosis); a module listed here would be allowed that many uses."""


def test_surfaces_evaluate_nothing():
    """No module of report/, plots/ or the studio imports or calls an evaluation function of the model or the
    physics (evaluate, performance, critical_speed, turning_effort, threshold_force, the risk functions, J): they
    render the records the studies return.  Known offenders of the studio's part are listed, with their count."""
    found = {
        module_name(path): uses
        for path in ALL_FILES
        if _in(module_name(path), SURFACES) and (uses := evaluation_uses(path))
    }
    over = {m: uses for m, uses in found.items() if len(uses) > SURFACE_EVALUATES.get(m, 0)}
    assert over == {}


def test_the_surface_rule_catches_a_plot_that_evaluates(tmp_path):
    """The rule is not vacuous: a planted plot importing the model's critical_speed, one calling
    problem.evaluate and one importing designer.evaluate are reported; a plot reading a record's numbers is not."""
    eq7 = tmp_path / "eq7.py"
    eq7.write_text("from designer.model import Conditions, critical_speed\nv = critical_speed(0.05, 1e-3, 0, 1.3)\n")
    method = tmp_path / "method.py"
    method.write_text("def draw(problem, designs):\n    return problem.evaluate(designs).critical_speed\n")
    public = tmp_path / "public.py"
    public.write_text("from designer import evaluate, Design\n")
    clean = tmp_path / "clean.py"
    clean.write_text("from designer.display import shown\ndef cell(rec):\n    return shown(rec.critical_speed)\n")
    assert evaluation_uses(eq7) == ["line 1: imports designer.model.critical_speed"]
    assert evaluation_uses(method) == ["line 2: calls problem.evaluate"]
    assert evaluation_uses(public) == ["line 1: imports designer.evaluate"]
    assert evaluation_uses(clean) == []


# --------------------------------------------------------------------------- the CLI calls the public API

INTERNALS = ("designer.model", "designer.physics", "designer.solvers", "designer.data")
"""What the CLI never imports: the model (its evaluator and internals), the physics, the solvers, the paper's raw
data.  It calls the public API (``designer.evaluate``, ``recommend``, ``fix``, ...) and renders the records."""


def internal_imports(path: Path) -> list[str]:
    """Imports in ``path`` of the model, the physics, the solvers or the paper's data (:data:`INTERNALS`)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            names = [node.module]
        elif isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        else:
            continue
        found += [f"line {node.lineno}: imports {name}" for name in names if _in(name, INTERNALS)]
    return found


CLI_INTERNALS: dict[str, int] = {}
"""Known offenders of the CLI and how many such imports each has: none (issue 41: the commands call the public API,
take the inertia models from it and the constants from the public tables, and render the records, e.g. the risk
law's sources that ``designer.evaluate`` gives for one caster); a module listed here would be allowed that many."""


def test_cli_calls_the_public_api():
    """No module of the CLI imports the model, the physics, the solvers or the paper's data: the commands call
    the public API and render what it returns.  Known offenders of the CLI's part are listed, with their count."""
    found = {
        module_name(path): uses
        for path in ALL_FILES
        if _in(module_name(path), ("designer.cli",)) and (uses := internal_imports(path))
    }
    over = {m: uses for m, uses in found.items() if len(uses) > CLI_INTERNALS.get(m, 0)}
    assert over == {}


def test_the_cli_rule_catches_a_command_evaluating_the_physics(tmp_path):
    """The rule is not vacuous: a planted command importing the physics' Eq. 7 inside its function, and one
    importing the model's Design, are reported; one calling designer.evaluate is not."""
    physics = tmp_path / "physics.py"
    physics.write_text("def run(args):\n    from designer.physics.shimmy import critical_shimmy_speed\n")
    model = tmp_path / "model.py"
    model.write_text("from designer.model import Design\n")
    public = tmp_path / "public.py"
    public.write_text("import designer\nfrom designer.display import shown\nrow = designer.evaluate\n")
    assert internal_imports(physics) == ["line 2: imports designer.physics.shimmy"]
    assert internal_imports(model) == ["line 1: imports designer.model"]
    assert internal_imports(public) == []


# --------------------------------------------------------------------------- inputs from the public API


def public_names() -> dict[str, str]:
    """The names of the public ``designer`` API and the module that defines each (``designer._LAZY``)."""
    tree = ast.parse((PACKAGE / "__init__.py").read_text(encoding="utf-8"))
    for node in tree.body:
        if isinstance(node, ast.AnnAssign) and getattr(node.target, "id", "") == "_LAZY":
            return ast.literal_eval(node.value)
        if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "_LAZY" for t in node.targets):
            return ast.literal_eval(node.value)
    raise AssertionError("designer/__init__.py has no _LAZY")


PUBLIC_MODULES = ("designer.errors",)
"""Public modules of their own: a name may come from them as well as from ``designer`` (the exceptions)."""


def side_door_inputs(path: Path, public: dict[str, str]) -> list[str]:
    """Imports in ``path`` of a public name (an input type such as Design, Problem, Uncertainty; a study) from its
    defining module instead of ``designer``, and of the paper's constants from ``designer.data`` instead of the
    public tables (``designer.units``, ``designer.parameters``)."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not (isinstance(node, ast.ImportFrom) and node.level == 0 and node.module):
            continue
        if _in(node.module, ("designer.data",)):
            found.append(f"line {node.lineno}: imports constants from {node.module}")
            continue
        found += [
            f"line {node.lineno}: imports {alias.name} from {node.module}, not from designer"
            for alias in node.names
            if node.module not in ("designer", *PUBLIC_MODULES)
            and alias.name in public
            and _in(node.module, ("designer",))
        ]
    return found


ENTRY_SIDE_DOORS: dict[str, int] = {
    # the studio imports the public types from their modules (issue 41, the studio's part, on its own branch; the
    # CLI's part has none): the lead shrinks this list after merging it; a module not listed here has no side door
    "designer.studio.app": 2,
    "designer.studio.helper": 1,
    "designer.studio.panels": 1,
    "designer.studio.state": 4,
    "designer.studio.view": 9,
}
"""Known side doors of the entry points and how many each has today: the number may only go down."""


def test_entry_points_take_inputs_from_the_public_api():
    """The CLI and the studio take the input types (Design, Conditions, Problem, Uncertainty, ...) and the studies
    from ``designer`` and the constants from the public tables, never from the defining modules or
    ``designer.data``.  Known offenders of the CLI's and the studio's parts are listed, with their count."""
    public = public_names()
    found = {
        module_name(path): uses
        for path in ALL_FILES
        if _in(module_name(path), ("designer.cli", "designer.studio")) and (uses := side_door_inputs(path, public))
    }
    over = {m: uses for m, uses in found.items() if len(uses) > ENTRY_SIDE_DOORS.get(m, 0)}
    assert over == {}


def test_the_input_rule_catches_a_side_door(tmp_path):
    """The rule is not vacuous: a planted command importing Design from designer.model and INCH from
    designer.data.paper is reported twice; ``from designer import Design`` and ``designer.units.INCH`` are not."""
    public = public_names()
    side = tmp_path / "side.py"
    side.write_text("from designer.model import Design\nfrom designer.data.paper import INCH\n")
    front = tmp_path / "front.py"
    front.write_text("from designer import Design, load_problem\nfrom designer.units import INCH\n")
    assert side_door_inputs(side, public) == [
        "line 1: imports Design from designer.model, not from designer",
        "line 2: imports constants from designer.data.paper",
    ]
    assert side_door_inputs(front, public) == []


# --------------------------------------------------------------------------- J written once

MAY_WEIGH = ("designer.model",)
"""Where J = w_turn F_turn + w_threshold P is written: the model (``designer.model.weighted``), which every solver,
study and record calls."""


def _weight_term(node: ast.AST, index: int) -> bool:
    """``node`` is ``w[index] * x`` or ``x * w[index]`` (any name of the weights)."""
    if not (isinstance(node, ast.BinOp) and isinstance(node.op, ast.Mult)):
        return False
    return any(
        isinstance(side, ast.Subscript) and isinstance(side.slice, ast.Constant) and side.slice.value == index
        for side in (node.left, node.right)
    )


def weighted_sums(path: Path) -> list[str]:
    """The expressions ``w[0] * a + w[1] * b`` in ``path``: J written again instead of asking the model."""
    return [
        f"line {node.lineno}: {ast.unparse(node)}"
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        if isinstance(node, ast.BinOp)
        and isinstance(node.op, ast.Add)
        and _weight_term(node.left, 0)
        and _weight_term(node.right, 1)
    ]


def test_j_is_written_once():
    """J = w_turn F_turn + w_threshold P is computed nowhere outside the model: the solvers, the studies, the
    records and the report call ``designer.model.weighted`` (or ``Casters.J``)."""
    offenders = {
        module_name(path): found
        for path in ALL_FILES
        if not _in(module_name(path), MAY_WEIGH) and (found := weighted_sums(path))
    }
    assert offenders == {}


def test_the_j_rule_catches_a_second_j(tmp_path):
    """The rule is not vacuous: a planted solver writing ``w[0] * f + w[1] * p`` (and one with the weights on the
    right) is reported; a sum of other indices, or a call of designer.model.weighted, is not."""
    second = tmp_path / "second.py"
    second.write_text(
        "def j(w, f, p):\n    return w[0] * f + w[1] * p\n\ndef k(w, v):\n    return v.f * w[0] + v.p * w[1]\n"
    )
    clean = tmp_path / "clean.py"
    clean.write_text("from designer.model import weighted\nj = weighted(1.0, 2.0, (1, 1))\nx = a[1] * b + a[0] * c\n")
    assert weighted_sums(second) == ["line 2: w[0] * f + w[1] * p", "line 5: v.f * w[0] + v.p * w[1]"]
    assert weighted_sums(clean) == []
