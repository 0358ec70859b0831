"""Numbers as the solver resolves them: what the committed data files (front.csv, front.json, robust.json) hold.

A report's data files are committed (``results/``), so a rerun of the same command must write the same bytes,
on this machine and, as far as the solver allows, under other releases of numpy, CasADi/IPOPT and scipy.  Their
last digits are not results: IPOPT stops at its tolerance (``tol`` 1e-10 on the scaled NLP, acceptable 1e-8),
so a variable at a bound sits a few 1e-10 of its scale inside it, an inactive constraint keeps a multiplier of
about μ/slack ~ 1e-10, and a rerun in another order or another release moves those digits.  Every number is
therefore written to what the solver resolves:

- a design variable (T, d, B, c_f) to 9 significant digits of its scale (the largest magnitude of its default
  bounds in :data:`designer.parameters.DEFAULT_BOUNDS`: 2.5 in, 8 in, 0.75 in, 6 N·m/rad), so a value below
  1e-9 of the scale is 0; one within :data:`AT_BOUND` of its scale from a bound of the problem is the bound
  (IPOPT resolves an active bound, not the width of the gap: the gap times the bound's multiplier is IPOPT's
  barrier parameter, down to about tol = 1e-10, so with a bound multiplier of 1e-3 the gap is 1e-7 of the
  scale; observed gaps reach 1.8e-8, c_f = 7.99999989 N·m/rad at the 8 N·m/rad bound of powered-chair);
- an objective and any other computed number to 9 significant digits of its own magnitude; a difference of two
  objectives (the price of stock, the robust front's extra effort) to 9 digits of the objective's magnitude;
- a constraint margin to 9 digits of its constraint's scale (the target speed, the swept-radius limit, the
  variable's scale), so a margin at the solver's tolerance is 0;
- a Lagrange multiplier of the scaled NLP, and a sensitivity d log J / d log p made from them, to 4 significant
  digits, and 0 below :data:`MULTIPLIER_FLOOR`: an inactive constraint's multiplier is μ/slack, and IPOPT's
  scaled complementarity μ <= tol · s_max = 1e-10 · 100 = 1e-8 bounds it by 1e-6 for a slack of 1 % (observed
  at most 2e-9; the active ones of the shipped problems are above 1e-3).

Run metadata that varies between runs (the date, wall and CPU seconds, the versions of the libraries, the number
of NLP solves) is kept out of the committed files: :func:`split_run` puts it in ``run.json`` beside the report,
which ``.gitignore`` leaves untracked.
"""

from __future__ import annotations

import math

from designer.parameters import DEFAULT_BOUNDS, VARIABLES

SIGNIFICANT = 9
"""Significant digits of a design variable (of its scale), an objective and every other computed number."""
MULTIPLIER_SIGNIFICANT = 4
"""Significant digits of a Lagrange multiplier or a sensitivity."""
MULTIPLIER_FLOOR = 1e-6
"""A multiplier (of the scaled NLP, dimensionless) or a sensitivity below this is written 0 (module docstring)."""
AT_BOUND = 1e-7
"""A design variable within this fraction of its scale from a bound of the problem is written as the bound."""
VARIABLE_SCALES = {name: max(abs(lo), abs(hi)) for name, (lo, hi) in DEFAULT_BOUNDS.items()}
"""Scale of each design variable [SI]: the largest magnitude of its default bounds (the parameter table)."""
MULTIPLIER_GROUPS = frozenset({"sensitivities", "gp_duals", "multipliers"})
"""Dict keys whose values are multipliers or sensitivities."""
ROOT_SIGNIFICANT = 6
"""Significant digits of P(shimmy) at an acceptance limit (a spec's ``limit_probability``): it is α by
construction, found to the limit's root tolerance (1e-9 of the part, :data:`designer.physics.acceptance.LIMIT_RTOL`)
times P's elasticity in the part (up to about 20), so its digits past the 7th are the root finder's, not results."""
ROOT_GROUPS = frozenset({"limit_probability"})
"""Dict keys whose values are P at a root (:data:`ROOT_SIGNIFICANT` digits)."""
VARYING_RUN_KEYS = frozenset(
    {
        "date",
        "versions",
        "front_seconds",
        "optimum_seconds",
        "tighter_seconds",
        "compute_cpu_seconds",
        "compute_wall_seconds",
        "wall_seconds",
        "report_seconds",
        "render_cpu_seconds",
        "nlp_solves",
        "build_seconds",
        "total_seconds",
        "timings",
        "moved",
    }
)
"""Run metadata that changes from run to run (times, date, library versions, solve counts): run.json only."""


def on_scale(value: float, scale: float | None = None, digits: int = SIGNIFICANT) -> float:
    """``value`` rounded to ``digits`` significant digits of ``scale`` (default: of its own magnitude).

    The grid step is 10^(e − digits + 1) with e the decimal exponent of ``scale``, so a value below half a
    step, and in particular below 1e-9 of the scale for 9 digits, is 0.  Non-finite values are returned as they
    are (the JSON writer turns them into null), and so is 0.
    """
    if not math.isfinite(value) or value == 0:
        return value
    magnitude = abs(scale) if scale else abs(value)
    out = round(value, digits - 1 - math.floor(math.log10(magnitude)))  # correctly rounded in decimal
    return out if out else 0.0  # never -0.0


def multiplier(value: float) -> float:
    """A Lagrange multiplier or sensitivity to :data:`MULTIPLIER_SIGNIFICANT` digits, 0 below the floor."""
    if not math.isfinite(value):
        return value
    if abs(value) < MULTIPLIER_FLOOR:
        return 0.0
    return float(f"{value:.{MULTIPLIER_SIGNIFICANT}g}")


def design_value(name: str, value: float, bounds=None) -> float:
    """Design variable ``name`` [SI] to 9 digits of its scale; the bound itself when within AT_BOUND of one.

    ``bounds``: the problem's ``{name: Bounds}`` (``problem.bounds``), or None for no snapping.
    """
    if not math.isfinite(value):
        return value
    scale = VARIABLE_SCALES[name]
    if bounds is not None and name in bounds:
        for bound in (bounds[name].low, bounds[name].high):
            if bound is not None and math.isfinite(bound) and abs(value - bound) <= AT_BOUND * scale:
                return on_scale(float(bound), scale)
    return on_scale(value, scale)


DIFFERENCE_SCALE = {
    "extra": "turning_effort_buildable",
    "extra_threshold": "threshold_force",
    "extra_effort": "turning_effort_robust",
}
"""Keys whose value is a difference of two objectives: the key of the sibling objective giving its scale."""
_MARGIN_SCALE = {"shimmy": "required_speed"}  # the optimum's margins: m/s of the target, m of the limit


def resolved(data, bounds=None, scales: dict | None = None):
    """A copy of JSON-ready ``data`` (dicts, lists, numbers, strings) with every float written as resolved.

    Rules by key, recursively (module docstring): design variables (:data:`designer.parameters.VARIABLES`) by
    :func:`design_value` with ``bounds`` (the problem's); ``lambda_*`` keys and the values of
    :data:`MULTIPLIER_GROUPS` by :func:`multiplier`; differences and margins on their sibling's scale; the
    optimum's ``constraints`` margins on the target speed, the swept-radius limit or the variable's scale;
    keys of :data:`VARYING_RUN_KEYS` removed (they belong in run.json); every other float to 9 significant
    digits.  ``problem_definition`` (the problem as given, not computed) is copied unchanged.  ``scales``:
    extra ``{key: scale}`` for margins (``swept_radius`` of the optimum: the problem's limit).
    """
    return _resolve(data, None, bounds, scales or {})


def _resolve(value, key, bounds, scales, siblings=None):  # noqa: C901 - one branch per rule of the docstring
    if isinstance(value, dict):
        out = {}
        for k, v in value.items():
            if k in VARYING_RUN_KEYS:
                continue
            if k == "problem_definition":
                out[k] = v
            elif k in MULTIPLIER_GROUPS and isinstance(v, dict):
                out[k] = {name: multiplier(x) if isinstance(x, float) else x for name, x in v.items()}
            elif k in ROOT_GROUPS and isinstance(v, dict):
                out[k] = {
                    name: on_scale(x, digits=ROOT_SIGNIFICANT) if isinstance(x, float) else x for name, x in v.items()
                }
            elif k == "constraints" and isinstance(v, dict):
                out[k] = {name: _margin(name, x, value, scales) if isinstance(x, float) else x for name, x in v.items()}
            else:
                out[k] = _resolve(v, k, bounds, scales, value)
        return out
    if isinstance(value, list):
        return [_resolve(v, key, bounds, scales, siblings) for v in value]
    if not isinstance(value, float):
        return value
    if key in VARIABLES:
        return design_value(key, value, bounds)
    if isinstance(key, str) and key.startswith("lambda_"):
        return multiplier(value)
    if key in DIFFERENCE_SCALE and siblings is not None and isinstance(siblings.get(DIFFERENCE_SCALE[key]), float):
        return on_scale(value, abs(siblings[DIFFERENCE_SCALE[key]]))
    return on_scale(value)


def _margin(name: str, value: float, solution: dict, scales: dict) -> float:
    """An optimum's constraint margin on its constraint's scale."""
    variable = name.split(".", 1)[0]
    if variable in VARIABLE_SCALES and "." in name:
        return on_scale(value, VARIABLE_SCALES[variable])
    scale = scales.get(name)
    if scale is None and isinstance(solution.get(_MARGIN_SCALE.get(name, "")), float):
        scale = solution[_MARGIN_SCALE[name]]
    return on_scale(value, abs(scale) if scale else None)


def split_run(run: dict) -> tuple[dict, dict]:
    """(stable, varying) parts of a report's run metadata: the stable part goes into the committed files, the
    whole of it (dates, seconds, versions, solve counts as well) into run.json."""
    stable = {}
    for key, value in run.items():
        if key in VARYING_RUN_KEYS:
            continue
        if isinstance(value, dict):
            value = {k: v for k, v in value.items() if k not in VARYING_RUN_KEYS}
        stable[key] = value
    return stable, dict(run)


__all__ = [
    "AT_BOUND",
    "DIFFERENCE_SCALE",
    "MULTIPLIER_FLOOR",
    "MULTIPLIER_GROUPS",
    "MULTIPLIER_SIGNIFICANT",
    "ROOT_GROUPS",
    "ROOT_SIGNIFICANT",
    "SIGNIFICANT",
    "VARIABLE_SCALES",
    "VARYING_RUN_KEYS",
    "design_value",
    "multiplier",
    "on_scale",
    "resolved",
    "split_run",
]
