"""The records of a shimmy simulation: :class:`SimulationResult` (one knock: the trace, the amplitudes, the
measured frequency and the paper's predictions, with its text, HTML, pandas and plot views) and
:class:`OnsetResult` (the simulated onset speed beside Eq. 7).  Built by :mod:`designer.studies.dynamics._simulate`,
which re-exports both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from designer.plots.simulation import plot_knock
from designer.reprs import Key, Record, dataframe
from designer.plots.svg import svg_sparkline


@dataclass(frozen=True, kw_only=True)
class SimulationResult(Record):
    """Outcome of one shimmy simulation (all SI).

    Attributes
    ----------
    t, theta, lateral : arrays
        Time [s], caster angle θ(t) [rad] and spindle displacement X(t) [m].
    speed : wheelchair speed V [m/s]
    angle, angular_velocity : initial θ_i [rad] and θ'_i [rad/s] (Eq. 24B)
    friction_moment : M_f = c_f θ0_design [N·m]
    inertia : I_w [kg·m²]
    early_amplitude : mean half peak-to-peak of θ over two periods just after
        the aligning transient (t ≳ 3T/V) [rad]
    late_amplitude : the same over the last two periods [rad]
    amplitude_ratio : late_amplitude / θ_i [-] (Eq. 29B predicts V/(ωT) at
        the threshold)
    growth_ratio : late_amplitude / early_amplitude [-]; > 1 is shimmy
    grows : True if the oscillation grows (growth_ratio > 1 or |θ| reached
        ``angle_limit``)
    diverged : True if |θ| reached ``angle_limit`` (simulation stopped)
    frequency : measured shimmy frequency [rad/s] from zero crossings of θ
    predicted_frequency : ω of Eq. 15B [rad/s]
    predicted_amplitude : θ_i V/(ω T) of Eq. 4 / 29B [rad] (Eq. 15B ω)
    critical_speed : Eq. 7 with c_f,eff = M_f/θ_i [m/s]
    switches : number of stick/slip transitions handled
    """

    t: np.ndarray
    theta: np.ndarray
    lateral: np.ndarray
    speed: float
    angle: float
    angular_velocity: float
    friction_moment: float
    inertia: float
    early_amplitude: float
    late_amplitude: float
    amplitude_ratio: float
    growth_ratio: float
    grows: bool
    diverged: bool
    frequency: float
    predicted_frequency: float
    predicted_amplitude: float
    critical_speed: float
    switches: int
    extrema: np.ndarray = field(repr=False, default_factory=lambda: np.empty((0, 2)))

    _keys = (
        *("speed", "angle", "angular_velocity", "friction_moment", "inertia", "amplitude_ratio", "growth_ratio"),
        *("early_amplitude", "late_amplitude", "grows", "diverged", "frequency", "predicted_frequency"),
        *("predicted_amplitude", "critical_speed", "switches"),
        Key("t", option="with_trace"),
        Key("theta", option="with_trace"),
    )
    """The scalars as plain Python types; ``to_dict(with_trace=True)`` adds the trace ``t``, ``theta``."""

    _units = {
        **dict.fromkeys(("angle", "early_amplitude", "late_amplitude", "predicted_amplitude", "theta"), "rad"),
        **dict.fromkeys(("angular_velocity", "frequency", "predicted_frequency"), "rad/s"),
        **{"speed": "m/s", "critical_speed": "m/s", "friction_moment": "N·m", "inertia": "kg·m²", "t": "s"},
    }

    def _repr_lines(self) -> list[str]:
        """Two lines: speed, knock, verdict and amplitudes; frequency, Eq. 7 V_c and the trace length."""
        verdict = "GROWS (shimmy)" if self.grows else "decays"
        freq = f"{self.frequency:.4g}" if math.isfinite(self.frequency) else "n/a"
        return [
            f"SimulationResult(V {self.speed:.3g} m/s, knock {math.degrees(self.angle):.3g}°: {verdict}; "
            f"amplitude {self.early_amplitude:.3g} → {self.late_amplitude:.3g} rad, Eq. 29B "
            f"{self.predicted_amplitude:.3g} rad)",
            f"  ω {freq} rad/s (Eq. 15B {self.predicted_frequency:.4g}), "
            f"Eq. 7 V_c {self.critical_speed:.4g} m/s, {len(self.t)} samples over {self._end():.3g} s",
        ]

    def _end(self) -> float:
        return float(self.t[-1]) if len(self.t) else 0.0

    def _html_title(self) -> str:
        return "Shimmy after a knock (Coulomb friction, App. B)"

    def _html_caption(self) -> str:
        return "θ(t); dashed: ± the Eq. 29B amplitude"

    def _html_rows(self) -> list[tuple[Any, Any, Any]]:
        """A compact table with units (notebooks; no integration runs): the verdict, the amplitudes beside Eq. 4 /
        29B's, the frequency beside Eq. 15B's and Eq. 7's V_c at the friction's effective damping."""
        deg = math.degrees
        return [
            ("speed V", f"{self.speed:.4g}", "m/s"),
            ("knock θ_i (θ'_i)", f"{deg(self.angle):.3g}° ({self.angular_velocity:.3g} rad/s)", ""),
            (
                "verdict",
                ("grows: shimmy" if self.grows else "decays") + (" (|θ| hit the limit)" if self.diverged else ""),
                "",
            ),
            ("amplitude after the transient", f"{self.early_amplitude:.4g} ({deg(self.early_amplitude):.3g}°)", "rad"),
            ("amplitude at the end", f"{self.late_amplitude:.4g} ({deg(self.late_amplitude):.3g}°)", "rad"),
            ("Eq. 4 / 29B amplitude θ_i V/(ωT)", f"{self.predicted_amplitude:.4g}", "rad"),
            (
                "frequency (Eq. 15B)",
                (f"{self.frequency:.4g}" if math.isfinite(self.frequency) else "n/a")
                + f" ({self.predicted_frequency:.4g})",
                "rad/s",
            ),
            ("Eq. 7 V_c (c_f,eff = M_f/θ_i)", f"{self.critical_speed:.4g}", "m/s"),
            ("friction moment M_f", f"{self.friction_moment:.4g}", "N·m"),
            ("wheel inertia I_w", f"{self.inertia:.4g}", "kg·m²"),
            ("trace", f"{len(self.t)} samples, {self._end():.3g}", "s"),
        ]

    def _html_extra(self) -> str:
        """A small SVG of θ(t) [deg] with ± the Eq. 29B amplitude."""
        return svg_sparkline(
            self.t, np.degrees(self.theta), "time t [s]", "θ [deg]", band=math.degrees(self.predicted_amplitude)
        )

    def to_pandas(self) -> Any:
        """The trace as a pandas DataFrame (pandas: the ``notebook`` extra): columns ``t_s`` [s], ``theta_rad``
        [rad], ``theta_deg`` [deg] and ``lateral_m`` (spindle displacement X [m]); the scalars of
        :meth:`to_dict` in ``df.attrs``, units in ``df.attrs["units"]``."""
        records = [
            {"t_s": float(t), "theta_rad": float(th), "theta_deg": math.degrees(th), "lateral_m": float(x)}
            for t, th, x in zip(self.t, self.theta, self.lateral)
        ]
        units = {"t_s": "s", "theta_rad": "rad", "theta_deg": "deg", "lateral_m": "m"}
        return dataframe("SimulationResult.to_pandas", records, list(units), units, **self.to_dict())

    def plot(self, ax: Any = None, onset_speed: float | None = None) -> Any:
        """θ(t) in degrees against time [s], with ± the Eq. 29B amplitude; returns the matplotlib Axes.

        ``ax``: your Axes or None for a new figure; ``onset_speed`` [m/s] (e.g. from :func:`onset_speed`) is
        added to the title.  Drawn by :func:`designer.plots.simulation.plot_knock` (as ``designer simulate
        --plot``).
        """
        return plot_knock(
            self.t,
            self.theta,
            self.speed,
            self.grows,
            self.critical_speed,
            self.predicted_amplitude,
            onset_speed=onset_speed,
            ax=ax,
        )


@dataclass(frozen=True, kw_only=True)
class OnsetResult(Record):
    """Simulated shimmy onset speed beside Eq. 7.

    Attributes
    ----------
    speed : simulated onset speed [m/s] (geometric mean of the final bracket)
    low, high : final bracket [m/s]: the knock decays at ``low``, grows at ``high``
    critical_speed : Eq. 7 with c_f,eff = M_f/θ_i [m/s]
    relative_error : (speed − critical_speed)/critical_speed [-]
    angle : initial angle θ_i [rad]
    evaluations : number of simulations run
    amplitude_at_onset : early shimmy amplitude simulated at ``high`` [rad]
    predicted_amplitude : Eq. 4 / 29B amplitude θ_i V/(ω T) at ``speed`` [rad]
    frequency_at_onset : measured ω at ``high`` [rad/s]
    predicted_frequency : Eq. 15B ω [rad/s]
    """

    speed: float
    low: float
    high: float
    critical_speed: float
    relative_error: float
    angle: float
    evaluations: int
    amplitude_at_onset: float
    predicted_amplitude: float
    frequency_at_onset: float
    predicted_frequency: float

    _units = {
        **dict.fromkeys(("speed", "low", "high", "critical_speed"), "m/s"),
        **dict.fromkeys(("angle", "amplitude_at_onset", "predicted_amplitude"), "rad"),
        **dict.fromkeys(("frequency_at_onset", "predicted_frequency"), "rad/s"),
    }

    def __float__(self) -> float:
        return float(self.speed)


@dataclass(frozen=True, kw_only=True)
class OnsetStudy(Record):
    """The simulated-onset study of ``designer simulate --report`` (:func:`write_simulation_report`): what it wrote
    into onset.csv, onset.json and report.md.

    Attributes
    ----------
    rows : one dict per case of the grid (trail [in], I_w [kg·m²], groove [in], knock [deg], Eq. 7's V_c and
        the simulated onset [m/s], its bracket, the relative error [-], the amplitudes [rad] and frequencies
        [rad/s] simulated and predicted, the simulations run): the columns of onset.csv
    summary : error statistics by group of cases, the Appendix C case, the conditions, ``cases`` and the run's
        wall time ``seconds`` [s] (onset.json's ``summary`` without the time)
    """

    rows: list[dict[str, Any]]
    summary: dict[str, Any]

    _units = {"summary.seconds": "s"}
