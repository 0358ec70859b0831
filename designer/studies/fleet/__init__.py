"""Product lines (``designer fleet``): per-chair recommendations and the fewest part numbers for a fleet.

Modules
-------
_fleet    :func:`fleet`: the per-chair recommendations and the part-number choice, :class:`FleetResult`
_table    the fleet table (CSV in, units, ranges, the example fleet)
_rule     the vectorised per-chair recommendation over the stock table
_kmedian  the exact K-median of part numbers
"""

from __future__ import annotations

from designer.studies.fleet._fleet import FleetResult, fleet, fleet_data, fleet_recommendations
from designer.studies.fleet._kmedian import solve_kmedian
from designer.studies.fleet._table import EXAMPLE_RANGES, example_fleet, read_fleet, write_fleet_csv

__all__ = [
    "EXAMPLE_RANGES",
    "FleetResult",
    "example_fleet",
    "fleet",
    "fleet_data",
    "fleet_recommendations",
    "read_fleet",
    "solve_kmedian",
    "write_fleet_csv",
]
