"""Issue 24.5: every shimmy study ends in bounded work. The simulations of one study share one budget of
evaluations of the equations of motion (deterministic, no clock) and end with one line when it is spent;
the onset search never leaves the model's speeds."""

from __future__ import annotations

import pytest

from designer.model import Conditions, Design
from designer.physics.inertia import Fixed
from designer.studies.dynamics import SPEED_RANGE, WorkLimitError, onset_speed, simulate, work_limit
from designer.errors import SolverError

CASTER = Design(trail=0.0508, diameter=0.2, groove=0.0, damping=1.3)


def test_a_spent_budget_ends_the_study_with_one_line():
    """A simulation that needs more evaluations than its budget ends with WorkLimitError (exit 5, as a solver
    failure) naming the study and the count, on one line; with the default budget the same run completes."""
    simulate(CASTER, Conditions(), 2.0)
    with pytest.raises(WorkLimitError) as info, work_limit("tiny study", evaluations=500):
        simulate(CASTER, Conditions(), 2.0)
    text = str(info.value)
    assert text.startswith("tiny study: stopped after 500 evaluations") and "\n" not in text
    assert info.value.exit_code == SolverError.exit_code == 5


def test_an_onset_search_shares_one_budget():
    """The trial simulations of an onset search draw on one budget: a budget that each single simulation
    fits in (about 2 000 evaluations here) is spent by the search, which ends instead of running on; a
    WorkLimitError is not a SolverError, so no search steps over it as over a failed trial."""
    with work_limit("one", evaluations=20_000):
        simulate(CASTER, Conditions(), 2.0)  # one simulation fits
    with pytest.raises(WorkLimitError), work_limit("search", evaluations=20_000):
        onset_speed(CASTER, Conditions())
    assert not issubclass(WorkLimitError, SolverError)


def test_onset_beyond_the_model_speeds_is_said_not_searched():
    """--find-onset with I_w = 1e-9 kg·m² (the documented lower limit) ran on for minutes: Eq. 7 puts the onset
    near 2 000 m/s and the bracket doubled into ever stiffer simulations. The bracket stays within the
    model's speeds (0.01 to 100 m/s): the search ends with one line saying the knock decays up to 100 m/s."""
    light = Conditions(inertia=Fixed(1e-9))
    with pytest.raises(SolverError) as info:
        onset_speed(CASTER, light)
    assert f"no shimmy onset up to {SPEED_RANGE[1]:g} m/s" in str(info.value) and "\n" not in str(info.value)


def test_budget_grows_with_the_requested_count(monkeypatch):
    """Work that grows with a requested count (the orbits of a bifurcation diagram, --points up to 200) gets a
    budget grown in proportion to the count over its default: 4 evaluations per orbit fit at 24 and at 200
    orbits, 5 per orbit do not (the budget is spent, not merely large)."""
    from designer.studies.dynamics import _work

    monkeypatch.setattr(_work, "MAX_EVALUATIONS", 100)

    def orbits(points=24, each=4):
        _work.spend(each * points)

    scaled = _work.bounded("orbits", scale="points")(orbits)
    scaled()
    scaled(points=200)
    with pytest.raises(WorkLimitError):
        scaled(points=200, each=5)
    with pytest.raises(WorkLimitError):
        _work.bounded("orbits")(orbits)(points=200)
