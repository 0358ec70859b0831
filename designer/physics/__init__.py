"""The equations of the reference paper, one module per phenomenon.

Every function takes SI quantities and works unchanged on Python floats,
NumPy arrays and CasADi symbols (SX/MX/DM): the arithmetic is written once
with NumPy functions, and CasADi's NumPy mode is switched on here so that
``np.sqrt`` of a CasADi symbol is a CasADi expression.

Modules
-------
shimmy      Eq. 5, 6/3C, 7/10C, 12B–20B: critical speed and the third-order model
inertia     I_w(d): Table 1 power law, thin disc, catalog wheel
threshold   Eq. 1/4A exact, Eq. 5A approximate: force to climb a door sill
turning     docs/model.md#turning-effort, Eq. 9: turning effort at the caster spindle
geometry    swept radius of the swivelling caster
uncertainty scatter of Eq. 7's constants: V_c quantile and Monte Carlo probability of shimmy
motion      Eq. 3B, 4B, 6B, 24B: the equations of motion with Coulomb spindle friction (rolling and brush tyre)
roots       a root in a sign-change bracket (check 6, the knock simulations' events) without scipy.optimize
scatter     the risk law's scales derived from Table 1, each with its provenance

CasADi is not imported here (``import designer`` stays light): the solvers call
:func:`enable_casadi` when they build symbols.
"""

from designer.physics._checks import enable_casadi as enable_casadi  # re-exported for the solvers

from designer.physics.geometry import swept_radius
from designer.physics.inertia import (
    Catalog,
    Disc,
    Fixed,
    InertiaModel,
    PowerLaw,
    disc_inertia,
    disc_mass,
    fit_table1_power_law,
    power_law_inertia,
)
from designer.physics.shimmy import (
    DynamicsParameters,
    characteristic_roots,
    critical_shimmy_speed,
    critical_speed_hydraulic,
    equivalent_hydraulic_damping,
    friction_damping_at_speed,
    growth_rate,
    routh_hurwitz_critical_speed,
    routh_hurwitz_margin,
    shimmy_frequency,
    full_shimmy_amplitude,
    steady_shimmy_amplitude,
    third_order_coefficients,
)
from designer.physics.roots import bracketed_root
from designer.physics.threshold import (
    threshold_force,
    threshold_force_ratio,
    threshold_force_ratio_approx,
    threshold_series_coefficients,
    threshold_series_remainder_bound,
)
from designer.physics.turning import (
    TurningConstants,
    added_damper_moment,
    sliding_turning_moment,
    turning_effort,
)

__all__ = [
    "Catalog",
    "Disc",
    "Fixed",
    "DynamicsParameters",
    "InertiaModel",
    "PowerLaw",
    "TurningConstants",
    "added_damper_moment",
    "bracketed_root",
    "characteristic_roots",
    "critical_shimmy_speed",
    "critical_speed_hydraulic",
    "disc_inertia",
    "disc_mass",
    "equivalent_hydraulic_damping",
    "fit_table1_power_law",
    "friction_damping_at_speed",
    "growth_rate",
    "power_law_inertia",
    "routh_hurwitz_critical_speed",
    "routh_hurwitz_margin",
    "shimmy_frequency",
    "sliding_turning_moment",
    "full_shimmy_amplitude",
    "steady_shimmy_amplitude",
    "swept_radius",
    "third_order_coefficients",
    "threshold_force",
    "threshold_force_ratio",
    "threshold_force_ratio_approx",
    "threshold_series_coefficients",
    "threshold_series_remainder_bound",
    "turning_effort",
]
