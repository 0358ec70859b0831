"""Simulated shimmy onset against Eq. 7 over a grid of casters: the validation study behind
``designer simulate --report`` (results/simulation).

For every case of :func:`simulation_report_cases` (trail × wheel inertia × groove × knock angle) the onset
speed is found by bisection on the time-domain model (:func:`designer.studies.dynamics._simulate.onset_speed`,
Appendix B with Coulomb spindle friction) and set beside Eq. 7, the Eq. 4/29B amplitude and the Eq. 15B
frequency; :func:`write_simulation_report` writes the table, a summary of where the describing-function
approximation holds and where it breaks, and the comparison figure
(:func:`designer.plots.simulation.figure_onset_comparison`).
"""

from __future__ import annotations

import json
import io
import math
import time
from pathlib import Path

import numpy as np

from designer.textfiles import csv_text, dict_rows
from designer.studies.dynamics._result import OnsetStudy
from designer.studies.dynamics._simulate import onset_speed, simulate
from designer.data.paper import INCH
from designer.model import Conditions, Design, critical_speed
from designer.jsonsafe import stamped
from designer.output import PLOT, SOFTWARE, FileKind, write_file
from designer.physics.inertia import Fixed
from designer.plots.simulation import figure_onset_comparison
from designer.data.paper import APPENDIX_C_CASE
from designer.studies.dynamics.limit_cycles._studies import appendix_c_caster

__all__ = [
    "REPORT_ANGLES",
    "REPORT_GROOVES",
    "REPORT_INERTIAS",
    "REPORT_TRAILS",
    "simulation_report_cases",
    "write_simulation_report",
]


# ---------------------------------------------------------------------------
# Comparison report: simulated onset vs Eq. 7 over a grid (results/simulation)

REPORT_TRAILS = (1.0 * INCH, 2.0 * INCH, 3.0 * INCH)
"""Trails of the report grid [m] (1, 2, 3 in)."""
REPORT_INERTIAS = (0.33e-3, 1.27e-3, 3.42e-3)
"""Wheel inertias of the report grid [kg·m²]: Table 1 wheel B, the Eq. 8 wheel, Table 1 wheel G."""
REPORT_GROOVES = (0.0, 9 / 16 * INCH)
"""Groove widths of the report grid [m]: single tread and Eq. 8's 9/16 in."""
REPORT_ANGLES = (math.radians(10.0), math.radians(20.0), math.radians(40.0))
"""Initial (knock) angles θ_i of the report grid [rad]."""


def simulation_report_cases():
    """The grid of the comparison report: (T [m], I_w [kg·m²], B [m], θ_i [rad]) tuples.

    3 trails × 3 inertias × 2 grooves × 3 angles = 54 cases, bare fork
    c_f = 1.3 N·m/rad (Eq. 11C) defined at θ0 = 20°, K_s = 1250 N.
    """
    return [(T, I, B, a) for T in REPORT_TRAILS for I in REPORT_INERTIAS for B in REPORT_GROOVES for a in REPORT_ANGLES]


def _report_row(trail, inertia, groove, angle, conditions, damping, rtol):
    cond = conditions.replace(inertia=Fixed(inertia))
    design = Design(trail=trail, diameter=0.2, groove=groove, damping=damping)
    onset = onset_speed(design, cond, angle=angle, rtol=rtol)
    omega = onset.predicted_frequency
    groove_share = float(
        critical_speed(trail, inertia, groove, 0.0, cond.slip_coefficient) ** 2 / onset.critical_speed**2
    )
    return {
        "trail_in": trail / INCH,
        "inertia_kgm2": inertia,
        "groove_in": groove / INCH,
        "angle_deg": math.degrees(angle),
        "eq7_critical_speed": onset.critical_speed,
        "onset_speed": onset.speed,
        "onset_low": onset.low,
        "onset_high": onset.high,
        "relative_error": onset.relative_error,
        "omega_eq15b": omega,
        "omega_T_over_V": omega * trail / onset.critical_speed,
        "groove_share": groove_share,
        "amplitude_sim": onset.amplitude_at_onset,
        "amplitude_eq29b": onset.predicted_amplitude,
        "amplitude_error": onset.amplitude_at_onset / onset.predicted_amplitude - 1,
        "frequency_sim": onset.frequency_at_onset,
        "frequency_error": onset.frequency_at_onset / omega - 1,
        "simulations": onset.evaluations,
    }


def write_simulation_report(
    out_dir="results/simulation",
    conditions: Conditions = Conditions(),
    damping: float = 1.3,
    rtol: float = 0.005,
    progress=None,
) -> OnsetStudy:
    """Write the simulated-onset vs Eq. 7 comparison to ``out_dir``.

    Files: ``onset.csv`` and ``onset.json`` (one row per case of
    :func:`simulation_report_cases`), ``report.md`` (table, where the
    describing-function approximation holds and where it breaks, Eq. 4/29B
    amplitude and Eq. 15B frequency checks) and ``onset.png`` (simulated vs
    Eq. 7 onset; error against ωT/V_c; amplitude vs Eq. 29B; θ(t) traces of
    the Appendix C case below, near and above onset, as Fig. 1C).

    Parameters
    ----------
    out_dir : directory to (re)write [created if missing]
    conditions : K_s [N], θ0 [rad], dynamics (K, N); inertia is set per case
    damping : c_f = M_f/θ0 [N·m/rad] of every case (bare fork 1.3, Eq. 11C)
    rtol : relative width of each onset bracket
    progress : optional callable(i, n) for progress display

    Returns
    -------
    OnsetStudy
        ``rows`` (list of dicts) and ``summary`` (error statistics); ``to_dict()`` gives the dict this function
        returned before.
    """
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    cases = simulation_report_cases()
    rows = []
    start = time.perf_counter()
    for i, (T, I, B, a) in enumerate(cases):
        rows.append(_report_row(T, I, B, a, conditions, damping, rtol))
        if progress is not None:
            progress(i + 1, len(cases))
    elapsed = time.perf_counter() - start

    onset_c, traces, appendix_c = _appendix_c(conditions, rtol)
    summary = _summarise(rows) | {
        "cases": len(rows),
        "seconds": elapsed,
        "appendix_c": appendix_c,
        "conditions": {
            "damping": damping,
            "design_angle": conditions.disturbance_angle,
            "slip_coefficient": conditions.slip_coefficient,
            "frame_stiffness": conditions.dynamics.stiffness,
            "lateral_mass": conditions.dynamics.lateral_mass,
            "bracket_rtol": rtol,
        },
    }
    # the run time stays out of the committed files (it is in the returned summary): a rerun writes the same bytes
    kept = {k: v for k, v in summary.items() if k != "seconds"}
    png = io.BytesIO()
    figure_onset_comparison(rows, traces, onset_c).savefig(png, format="png", dpi=110, metadata={"Software": SOFTWARE})
    files = {
        # onset.csv: one line per case, floats to 6 significant digits, each quantity's unit in its column
        "onset.csv": csv_text(dict_rows(rows, list(rows[0]), "{:.6g}", quantities=ONSET_CSV_QUANTITIES)),
        "onset.json": json.dumps(stamped("onset.json", {"summary": kept, "rows": rows}), indent=2),
        "onset.png": png.getvalue(),
        "report.md": _report_markdown(rows, summary),
    }
    for name, content in files.items():
        write_file(out / name, content, "--report", name, kind=ONSET_KINDS[name])
    return OnsetStudy(rows=rows, summary=summary)


def _appendix_c(conditions: Conditions, rtol: float):
    """The Appendix C reference case (Fig. 1C): its onset (bracket ``rtol``/5), the onset after a 0.7 rad/s
    kick, θ(t) at 0.9, 1.0 and 1.1 × the onset, and its summary record: ``(onset, traces, record)``."""
    # Appendix C reference case (Fig. 1C): T = 2.5 in, I_w from V_c = 2.53 m/s via Eq. 7, θ0 = 20°.
    case = APPENDIX_C_CASE
    design_c, fixed = appendix_c_caster()
    cond_c = conditions.replace(inertia=fixed.inertia)
    onset_c = onset_speed(design_c, cond_c, angle=case.initial_angle, rtol=rtol / 5)
    onset_c_kick = onset_speed(design_c, cond_c, angle=case.initial_angle, angular_velocity=0.7, rtol=rtol / 5)
    traces = {
        f: simulate(design_c, cond_c, f * onset_c.speed, angle=case.initial_angle, cycles=20, angle_limit=0.6)
        for f in (0.9, 1.0, 1.1)
    }
    record = {
        "inertia": float(cond_c.inertia(design_c.diameter)),
        "eq7_critical_speed": onset_c.critical_speed,
        "onset_speed": onset_c.speed,
        "relative_error": onset_c.relative_error,
        "onset_speed_with_0.7_rad_per_s": onset_c_kick.speed,
        "amplitude_sim": onset_c.amplitude_at_onset,
        "amplitude_eq29b": onset_c.predicted_amplitude,
        "paper_amplitude": case.steady_amplitude,
        "frequency_sim": onset_c.frequency_at_onset,
        "frequency_eq15b": onset_c.predicted_frequency,
    }
    return onset_c, traces, record


ONSET_KINDS = {
    "onset.json": FileKind("an onset.json of designer simulate"),
    "onset.csv": FileKind("an onset.csv of designer simulate"),
    "report.md": FileKind("the onset report of designer simulate"),
    "onset.png": PLOT,
}
"""The onset study's files: an existing one is replaced only while the manifest of its folder proves it the tool's,
unedited (:func:`designer.output.write_file`)."""


ONSET_CSV_QUANTITIES = {
    **dict.fromkeys(("eq7_critical_speed", "onset_speed", "onset_low", "onset_high"), "speed"),
    **dict.fromkeys(("omega_eq15b", "frequency_sim"), "angular_speed"),
    **dict.fromkeys(("amplitude_sim", "amplitude_eq29b"), "angle"),
}
"""The quantities of onset.csv that do not name their unit in the row's key, and their dimensions: each column names
its unit (the one rule, :func:`designer.textfiles.dict_rows`: ``onset_speed_m_per_s``, ``omega_eq15b_rad_per_s``)."""


def _summarise(rows) -> dict:
    keys = ("relative_error", "omega_T_over_V", "groove_share", "amplitude_error", "frequency_error", "trail_in")
    err, wtv, share, amp, freq, trail, inertia = (np.array([r[k] for r in rows]) for k in (*keys, "inertia_kgm2"))
    grooved = share > 0

    def stats(mask):
        if not mask.any():
            return None
        e = err[mask]
        return {
            "n": int(mask.sum()),
            "max_abs_error": float(np.abs(e).max()),
            "mean_error": float(e.mean()),
            "min_error": float(e.min()),
            "max_error": float(e.max()),
        }

    implied = (1 + amp) ** -0.5 - 1
    single = {
        f"T={t:.0f}in,I_w={i:.3g}": stats(~grooved & np.isclose(trail, t) & np.isclose(inertia, i))
        for t in sorted(set(np.round(trail, 6)))
        for i in sorted(set(inertia))
    }
    return {
        "single_tread_by_trail_inertia": single,
        "error_minus_amplitude_implied": {
            "max_abs_single_tread": float(np.abs(err - implied)[~grooved].max()),
            "median_abs_single_tread": float(np.median(np.abs(err - implied)[~grooved])),
            "max_abs_all": float(np.abs(err - implied).max()),
        },
        "all": stats(np.ones_like(err, bool)),
        "omega_T_over_V_ge_2": stats(wtv >= 2),
        "omega_T_over_V_lt_2": stats(wtv < 2),
        "groove_share_ge_0.5": stats(share >= 0.5),
        "single_tread": stats(~grooved),
        "single_tread_omega_T_over_V_ge_2": stats(~grooved & (wtv >= 2)),
        "amplitude_error_single_tread": {"min": float(amp[~grooved].min()), "max": float(amp[~grooved].max())},
        "amplitude_error_grooved": {"min": float(amp[grooved].min()), "max": float(amp[grooved].max())},
        "frequency_error": {"min": float(np.nanmin(freq)), "max": float(np.nanmax(freq))},
    }


def _pct(x) -> str:
    return f"{100 * x:+.1f} %"


def _report_markdown(rows, summary) -> str:
    """``report.md`` of the study: title and ``## Model`` (the equations integrated, the constants and the grid),
    where the describing-function approximation (Eq. 6 + Eq. 29B -> Eq. 7) holds and where it breaks, the Eq. 4/29B
    amplitude and Eq. 15B frequency checks with the Appendix C case (Fig. 1C), and the table of every case."""
    s, c, ac = summary, summary["conditions"], summary["appendix_c"]

    def line(key, text):
        st = s.get(key)
        if not st:
            return f"- {text}: no cases\n"
        return (
            f"- {text} ({st['n']} cases): error {_pct(st['min_error'])} to {_pct(st['max_error'])}, "
            f"max |error| {100 * st['max_abs_error']:.1f} %\n"
        )

    md = [
        "# Simulated shimmy onset vs Eq. 7\n\n",
        "Generated by `designer simulate --report results/simulation` "
        "(`designer.studies.dynamics._onset_study.write_simulation_report`).\n\n",
        "## Model\n\n",
        "Two-degree-of-freedom caster of Appendix B (Eq. 3B, 4B, 6B, masses of Eq. 9B–11B), state "
        "(X, θ, θ'), with the spindle moment a true Coulomb friction M_f sgn(θ') integrated with exact "
        "stick–slip events (scipy `solve_ivp`, DOP853, rtol 1e-8):\n\n",
        "    X'  = −T θ' − V θ\n",
        "    θ'' = [T K X − (N T V + K_s B²/(2V)) θ' − M_f sgn θ'] / (I_w + N T²)\n\n",
        f"K = {c['frame_stiffness']:.0f} N/m, N = {c['lateral_mass']:.2f} kg (DynamicsParameters: ω = 104.7 rad/s "
        f"at T = 2.5 in), K_s = {c['slip_coefficient']:.0f} N, M_f = c_f θ0 with c_f = {c['damping']} N·m/rad "
        f"and θ0 = {math.degrees(c['design_angle']):.0f}°. Each case starts from θ = θ_i, θ' = 0, θ'' = 0 "
        "(Eq. 24B); Eq. 7 is evaluated with c_f,eff = M_f/θ_i. The onset is found by bisection on whether the "
        "oscillation over the last two periods is larger than just after the aligning transient "
        f"(bracket width {100 * c['bracket_rtol']:.1f} %).\n\n",
        f"{s['cases']} cases (trail 1, 2, 3 in × I_w 0.33e-3, 1.27e-3, 3.42e-3 kg·m² × B = 0, 9/16 in × "
        "θ_i = 10°, 20°, 40°).\n\n",
        "![onset comparison](onset.png)\n\n",
        "## Where the describing-function approximation (Eq. 6 + Eq. 29B → Eq. 7) holds and where it breaks\n\n",
        line("all", "All cases"),
        line("omega_T_over_V_ge_2", "ωT/V_c ≥ 2 (Eq. 26B's assumption ωT/V ≫ 1 roughly met)"),
        line("omega_T_over_V_lt_2", "ωT/V_c < 2"),
        line("single_tread", "Single tread, B = 0 (onset set by friction alone)"),
        line("single_tread_omega_T_over_V_ge_2", "Single tread with ωT/V_c ≥ 2"),
        line("groove_share_ge_0.5", "Groove term ≥ 50 % of V_c² (viscous tread damping dominates)"),
        "\n",
        "Reading the figure: (1) with a groove the tread moment K_s B² θ'/(2V) is a true viscous damper, "
        "so the groove part of Eq. 7 is exact (Routh–Hurwitz of Eq. 12B) and only the friction share is "
        "approximate: the more the groove term dominates V_c², the better Eq. 7 agrees. "
        "(2) For a single tread the onset rests entirely on the friction equivalence Eq. 6 evaluated at the "
        "amplitude of Eq. 4/29B, θ_a = θ_i V/(ωT). The describing function itself (Eq. 6) is accurate: the "
        "onset error is almost exactly the error of that amplitude, (θ_a,29B/θ_a,sim)^½ − 1 (panel b; "
        f"for B = 0 the two differ by {100 * s['error_minus_amplitude_implied']['median_abs_single_tread']:.1f} "
        f"points (median), {100 * s['error_minus_amplitude_implied']['max_abs_single_tread']:.1f} at worst). (3) The amplitude is where Eq. 29B breaks: for a heavy wheel on a short trail the friction-"
        "dominated transient leaves a larger oscillation than θ_i V/(ωT) and Eq. 7 is optimistic (the "
        "simulated onset is lower); for a light wheel with a small knock ωT/V_c approaches 1, where Eq. 29B "
        "(which needs ωT/V ≫ 1; the exact Eq. 3 amplitude is θ_i/√(1+ω²T²/V²)) overestimates the amplitude "
        "and Eq. 7 is conservative. Single-tread errors by trail and wheel (over θ_i = 10°, 20°, 40°):\n\n",
        "".join(
            f"  - {k}: {_pct(v['min_error'])} to {_pct(v['max_error'])}\n"
            for k, v in s["single_tread_by_trail_inertia"].items()
            if v
        ),
        "\n",
        "## Amplitude (Eq. 4 / 29B) and frequency (Eq. 15B)\n\n",
        f"- Amplitude just after the transient, simulated at the onset vs θ_i V/(ωT): single tread "
        f"{_pct(s['amplitude_error_single_tread']['min'])} to {_pct(s['amplitude_error_single_tread']['max'])}; "
        f"grooved {_pct(s['amplitude_error_grooved']['min'])} to {_pct(s['amplitude_error_grooved']['max'])} "
        "(the tread damping shrinks the oscillation that the knock excites, which Eq. 29B ignores).\n",
        f"- Shimmy frequency (zero crossings after the transient) vs Eq. 15B: "
        f"{_pct(s['frequency_error']['min'])} to {_pct(s['frequency_error']['max'])}.\n\n",
        "## Appendix C case (Fig. 1C)\n\n",
        f"T = 2.5 in, I_w = {ac['inertia']:.4g} kg·m² (from V_c = 2.53 m/s via Eq. 7), θ_i = 20°, B = 0: "
        f"simulated onset {ac['onset_speed']:.3f} m/s vs Eq. 7 {ac['eq7_critical_speed']:.3f} m/s "
        f"({_pct(ac['relative_error'])}); with the paper's θ'_0 = 0.7 rad/s (Eq. 7C) "
        f"{ac['onset_speed_with_0.7_rad_per_s']:.3f} m/s. Amplitude after the transient at onset "
        f"{ac['amplitude_sim']:.3f} rad vs Eq. 29B {ac['amplitude_eq29b']:.3f} rad (paper's measured "
        f"steady amplitude {ac['paper_amplitude']:.2f} rad); frequency {ac['frequency_sim']:.1f} rad/s vs "
        f"Eq. 15B {ac['frequency_eq15b']:.1f} rad/s. Above the onset the model (linear apart from friction, "
        "small angles) grows without bound; the paper's sustained 8° shimmy is limited by effects it does "
        "not contain (tyre saturation, large angles).\n\n",
    ]
    return "".join(md + _table(rows))


def _table(rows) -> list[str]:
    """``## Table``: one line per case."""
    md = [
        "## Table\n\n",
        "| T [in] | I_w [kg·m²] | B [in] | θ_i [deg] | ωT/V_c | V_c Eq. 7 [m/s] | onset sim [m/s] | error | "
        "amp sim [rad] | amp Eq. 29B [rad] | ω sim [rad/s] | ω Eq. 15B [rad/s] |\n",
        "|---|---|---|---|---|---|---|---|---|---|---|---|\n",
    ]
    for r in rows:
        md.append(
            f"| {r['trail_in']:.0f} | {r['inertia_kgm2']:.3g} | {r['groove_in']:.4g} | {r['angle_deg']:.0f} | "
            f"{r['omega_T_over_V']:.2f} | {r['eq7_critical_speed']:.3f} | {r['onset_speed']:.3f} | "
            f"{_pct(r['relative_error'])} | {r['amplitude_sim']:.3f} | {r['amplitude_eq29b']:.3f} | "
            f"{r['frequency_sim']:.1f} | {r['omega_eq15b']:.1f} |\n"
        )
    return md
