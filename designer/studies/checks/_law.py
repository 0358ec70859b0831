"""Check 11: the risk law against the Table 1 wheels it was refitted without (leave one out)."""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict
from pathlib import Path
from typing import Any

from designer.data import leave_one_out
from designer.data.paper import BARE_FORK_DAMPING, SLIP_COEFFICIENT, TABLE1, TABLE1_TRAIL
from designer.physics.scatter import inertia_prediction, model_error
from designer.physics.uncertainty import data_law, shimmy_probability_exact
from designer.studies.checks._record import FAILS, REPRODUCED, WITHIN_SCATTER, Check


LOO_LEVEL = 0.90
"""Check 11: the central interval each left-out wheel's measured onset should fall in."""

LOO_REPRODUCED_AT = 4
"""Check 11 is reproduced when at least 4 of the 5 wheels fall inside, for both predictions (a calibrated
law puts each inside with probability 0.9: 4.5 expected, 3 or fewer with probability 8 %)."""

LOO_FAILS_BELOW = 3
"""... and fails when fewer than 3 do (probability 0.9 % for a calibrated law, wheels taken as independent)."""


def _pit_rows(assumed: bool) -> list[dict[str, Any]]:
    """One row per Table 1 wheel C–G: the law refitted without it, and the PIT of its measured onset."""
    rows = []
    for wheel in TABLE1:
        if wheel.critical_speed is None:
            continue
        others = tuple(w for w in TABLE1 if w is not wheel)
        prediction = inertia_prediction(others)
        error = model_error(others)
        changes = {} if assumed else {"damping": 0.0, "inertia": 0.0}
        law = data_law(model_error=error.scale, model_error_dof=error.dof, **changes)
        predicted = float(prediction.median(wheel.diameter))
        fork = (0.0, BARE_FORK_DAMPING, SLIP_COEFFICIENT, wheel.critical_speed, law)  # B, c_f, K_s, V, the law
        pit = {
            "diameter": float(
                shimmy_probability_exact(TABLE1_TRAIL, predicted, *fork, diameter=wheel.diameter, prediction=prediction)
            ),
            "inertia": float(shimmy_probability_exact(TABLE1_TRAIL, wheel.inertia, *fork)),
        }
        rows.append(
            {
                "wheel": wheel.key,
                "diameter": wheel.diameter,
                "measured_speed": wheel.critical_speed,
                "inertia": wheel.inertia,
                "predicted_inertia": predicted,
                "inertia_scale": float(prediction.scale(wheel.diameter)),
                "inertia_dof": prediction.dof,
                "model_error_scale": error.scale,
                "model_error_dof": error.dof,
                "pit_from_diameter": pit["diameter"],
                "pit_from_inertia": pit["inertia"],
                "inside_from_diameter": _inside(pit["diameter"]),
                "inside_from_inertia": _inside(pit["inertia"]),
            }
        )
    return rows


def _inside(pit: float) -> bool:
    return (1 - LOO_LEVEL) / 2 <= pit <= 1 - (1 - LOO_LEVEL) / 2


_LOO_CACHE: dict[bool, list[dict[str, Any]]] = {}

LOO_FILE = Path(__file__).resolve().parents[2] / "data" / "leave_one_out.py"
"""Check 11's two tables as :func:`_pit_rows` computes them, stored (a generated module,
:mod:`designer.data.leave_one_out`) with the digest of what they depend on (Table 1, the test fork, the default
law, the interval): the main job then needs no Bessel function of even order (the refitted laws are Student-t
on 4 degrees of freedom) and so no scipy import.  Read only while the digest matches (else computed);
``tests/studies/test_checks.py`` recomputes and compares them, and :func:`write_leave_one_out_table` rewrites
the file."""


def _loo_inputs_digest() -> str:
    """What check 11's tables depend on, as a digest: Table 1, the fork's constants, the default law, the level."""
    inputs = {
        "table1": [asdict(w) for w in TABLE1],
        "fork": [TABLE1_TRAIL, BARE_FORK_DAMPING, SLIP_COEFFICIENT],
        "law": asdict(data_law()),
        "level": LOO_LEVEL,
    }
    return hashlib.sha256(json.dumps(inputs, sort_keys=True, default=repr).encode()).hexdigest()[:16]


def _stored_loo_rows(assumed: bool) -> list[dict[str, Any]] | None:
    """The stored table, or None when its digest is not current."""
    if leave_one_out.DIGEST != _loo_inputs_digest():
        return None
    rows: list[dict[str, Any]] = leave_one_out.ROWS["assumed" if assumed else "bare"]
    return rows


def write_leave_one_out_table(path: Path = LOO_FILE) -> Path:
    """Compute check 11's two tables and write them to :data:`LOO_FILE` (after a change to Table 1 or the law;
    then `ruff format` the file): a row per wheel, each value by repr (exact) in the order of ``COLUMNS``."""
    path.write_text(_loo_module({"assumed": _pit_rows(True), "bare": _pit_rows(False)}), encoding="utf-8")
    return path


def _loo_module(rows: dict[str, list[dict[str, Any]]]) -> str:
    """The text of :data:`LOO_FILE` holding ``rows`` under today's digest."""
    columns = tuple(rows["assumed"][0])
    half = (len(columns) + 1) // 2

    def table(key: str) -> str:
        cells = [[repr(r[c]) if not isinstance(r[c], str) else r[c] for c in columns] for r in rows[key]]
        return "".join(" ".join(c[:half]) + "\n" + " ".join(c[half:]) + "\n" for c in cells)

    return (
        '"""Check 11\'s leave-one-out tables (generated by designer.studies.checks.write_leave_one_out_table; do not\n'
        "edit: a test recomputes them).  DIGEST names what they were computed from; each table holds a row per wheel\n"
        '(over two lines), its values by repr in the order of COLUMNS."""\n\n'
        f"DIGEST = {_loo_inputs_digest()!r}\n\nCOLUMNS = {columns!r}\n\n_TABLES = {{\n"
        + "".join(f'    "{key}": """\n{table(key)}""",\n' for key in rows)
        + "}\n\n\n"
        "def _value(text: str) -> object:\n"
        '    """A stored cell: True or False, an int, a float (its repr: exact), else the text (the wheel)."""\n'
        '    if text in ("True", "False"):\n'
        '        return text == "True"\n'
        "    for kind in (int, float):\n"
        "        try:\n"
        "            return kind(text)\n"
        "        except ValueError:\n"
        "            pass\n"
        "    return text\n\n\n"
        "def _rows(table: str) -> list[dict[str, object]]:\n"
        "    values = [_value(v) for v in table.split()]\n"
        "    return [dict(zip(COLUMNS, values[k : k + len(COLUMNS)])) for k in range(0, len(values), len(COLUMNS))]\n\n\n"
        "ROWS = {key: _rows(table) for key, table in _TABLES.items()}\n"
    )


def leave_one_out_rows(assumed: bool = True) -> list[dict[str, Any]]:
    """Check 11's table (cached): for each Table 1 wheel C–G, the power law and the model-error scale refitted
    without it (Student-t on 4 degrees of freedom each), and the probability integral transform
    P(V_c,true <= V_measured) of its measured onset under the exact law, predicted twice: from its diameter
    alone (the refitted power law's Student-t prediction of I_w) and from its measured I_w (σ 0.05).

    ``assumed``: with the law's assumed c_f scatter (σ 0.10; K_s does not enter at B = 0) and the
    measurement scatter, as the tool applies it; False: Eq. 7's error and the inertia prediction alone.
    Rows: wheel, diameter [m], measured_speed [m/s], inertia, predicted_inertia [kg·m²], inertia_scale,
    inertia_dof, model_error_scale, model_error_dof, pit_from_diameter, pit_from_inertia [-] and whether each
    lies in the central :data:`LOO_LEVEL` interval.
    """
    if assumed not in _LOO_CACHE:
        _LOO_CACHE[assumed] = _stored_loo_rows(assumed) or _pit_rows(assumed)
    return [dict(r) for r in _LOO_CACHE[assumed]]


def check_leave_one_out() -> Check:
    """Check 11: the risk law predicts each Table 1 wheel C–G it was refitted without (leave one out).

    Reproduced when at least :data:`LOO_REPRODUCED_AT` of the five measured onsets fall in the central 90 %
    interval for both predictions (from the diameter, from the measured inertia); fails below
    :data:`LOO_FAILS_BELOW`; otherwise disagrees within the scatter.  With five wheels it is a coarse check.
    """
    rows = leave_one_out_rows()
    bare = leave_one_out_rows(assumed=False)
    n = len(rows)
    count = {k: sum(r[f"inside_from_{k}"] for r in rows) for k in ("diameter", "inertia")}
    bare_count = {k: sum(r[f"inside_from_{k}"] for r in bare) for k in ("diameter", "inertia")}
    worst = min(count.values())
    outcome = REPRODUCED if worst >= LOO_REPRODUCED_AT else FAILS if worst < LOO_FAILS_BELOW else WITHIN_SCATTER
    lines = "; ".join(
        f"{r['wheel']}: PIT {r['pit_from_diameter']:.3f} from d, {r['pit_from_inertia']:.3f} from I_w" for r in rows
    )
    outside = [
        f"{r['wheel']}: measured {r['measured_speed']:.2f} m/s outside the central {LOO_LEVEL:.0%} interval "
        f"predicted from its {k} (PIT {r[f'pit_from_{k}']:.3f})"
        for r in rows
        for k in ("diameter", "inertia")
        if not r[f"inside_from_{k}"]
    ]
    return Check(
        name="11 leave-one-out",
        claim="the risk law, refitted without each Table 1 wheel C–G (power law and model error on 4 degrees of "
        "freedom), predicts that wheel's measured critical speed at 2 in trail within its central 90 % interval",
        expected=f">= {LOO_REPRODUCED_AT} of {n} inside, from the diameter and from the measured I_w",
        got=f"from d {count['diameter']}/{n}, from I_w {count['inertia']}/{n}",
        passed=outcome != FAILS,
        detail=f"{lines}. PIT = P(V_c,true <= V_measured) under the exact law with the assumed c_f scatter (σ 0.10) and "
        f"a measured I_w's σ 0.05; with Eq. 7's error and the inertia prediction alone: from d "
        f"{bare_count['diameter']}/{n}, from I_w {bare_count['inertia']}/{n}. A calibrated law puts each wheel "
        f"inside with probability 0.9 (4.5 of 5 expected). With five wheels this is a coarse check: only a law "
        f"far too narrow would fail it (at 70 % true coverage a fail still has probability 16 %, wheels taken "
        f"as independent).",
        kind="law",
        outcome=outcome,
        disagreements=outside,
        rows=rows,
    )


def law_checks() -> list[Check]:
    """The checks of the risk law against the paper's data (11, leave one out): ``designer validate``."""
    return [check_leave_one_out()]
