"""Shared fixtures: the shipped problems and a quiet warning filter."""

from __future__ import annotations

import warnings
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PROBLEMS = sorted((ROOT / "problems").glob("*.toml"))


@pytest.fixture(autouse=True)
def _quiet_extrapolation():
    """The Table 1 power-law extrapolation warning is tested on its own; silence it elsewhere."""
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="inertia power law used at")
        yield


@pytest.fixture(scope="session")
def root() -> Path:
    return ROOT
