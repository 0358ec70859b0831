"""Retrofit (``designer fix``): diagnose a caster that shimmies and rank the fixes a clinician can fit.

Modules
-------
_retrofit   :func:`fix`: the diagnosis, the options and the ranked fixes
_input      the ``--current`` caster as the user writes it (stem angle, units)
_diagnosis  the current caster's risk and what drives it
_options    the parts that can change (washer, tyre, fork hole, wheel)
_records    :class:`FixResult` and its parts
"""

from __future__ import annotations

from designer.studies.retrofit._input import parse_current
from designer.studies.retrofit._records import FixResult, describe_changes, fix_sentence
from designer.studies.retrofit._retrofit import ONSET_SCATTER, fix

__all__ = ["ONSET_SCATTER", "FixResult", "describe_changes", "fix", "fix_sentence", "parse_current"]
