"""Product lines (``designer fleet``): per-chair recommendations and the fewest part numbers for a fleet.

Modules
-------
_fleet    :func:`fleet`: the per-chair recommendations, the part-number choice and the suggested count,
          :class:`FleetResult`
_table    the fleet table (CSV in, units, ranges, the example fleet)
_rule     the vectorised per-chair recommendation over the stock table
_kmedian  the K-median of part numbers, solved to proven optimality
"""

from __future__ import annotations

from designer.studies.fleet._fleet import (
    DEFAULT_MAX_REGRET,
    FleetResult,
    fleet,
    fleet_data,
    fleet_recommendations,
    fleet_run,
    suggest_skus,
)
from designer.studies.fleet._kmedian import kmedian_curve, solve_kmedian
from designer.studies.fleet._table import (
    EXAMPLE_KIND,
    EXAMPLE_RANGES,
    MAX_CHAIRS,
    example_fleet,
    read_fleet,
    write_fleet_csv,
)

__all__ = [
    "DEFAULT_MAX_REGRET",
    "EXAMPLE_KIND",
    "EXAMPLE_RANGES",
    "MAX_CHAIRS",
    "FleetResult",
    "example_fleet",
    "fleet",
    "fleet_data",
    "fleet_recommendations",
    "fleet_run",
    "kmedian_curve",
    "read_fleet",
    "solve_kmedian",
    "suggest_skus",
    "write_fleet_csv",
]
