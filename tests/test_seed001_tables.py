"""Seed 001's Tables 1–2 (bench/seed001_tables.py) against the exact maxima and the paper.

Exact maxima come from tests/reference/mp_reference.py at 50 digits: max ω_cage = ω / tan α and
max |ε_cage| = ω² · max |ψ''| in closed form (cross-checked there against a root of ψ''' = 0).
"""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path
from types import ModuleType

import pytest

ROOT = Path(__file__).resolve().parent.parent
TOL_OMEGA_MAX = 1e-12
"""Relative: the sweep contains φ = 0, so ours is ψ'(0)·ω evaluated in double precision."""
TOL_EPSILON_MAX = 1e-9
"""Relative: ours is a refined sweep of the solver's ψ''·ω², whose peak is flat to second order."""
TOL_PHI_AT_MAX = 1e-6
"""rad: where |ψ''| peaks is known only to ~√eps from its values."""
TOL_MATHCAD = 2e-3
"""The paper's Mathcad column was sampled: within 0.2 % of the exact maxima."""
TOL_SOLIDWORKS = 2e-2
"""SolidWorks Motion is a numerical simulation: within 2 % (its 500 rpm ε is 1.5 % low)."""


def _load(name: str, path: Path) -> ModuleType:
    if name in sys.modules:
        return sys.modules[name]
    spec = importlib.util.spec_from_file_location(name, path)
    module = importlib.util.module_from_spec(spec)
    sys.modules[name] = module
    spec.loader.exec_module(module)
    return module


tables = _load("seed001_tables", ROOT / "bench" / "seed001_tables.py")
mpmath = pytest.importorskip("mpmath", reason="the exact maxima are computed with mpmath")
ref = _load("mp_reference", ROOT / "tests" / "reference" / "mp_reference.py")


@pytest.fixture(scope="module")
def scene():
    import solver

    return solver.load_scene("spherical_converter")


@pytest.mark.parametrize("rpm", tables.RPM)
def test_max_cage_velocity_is_omega_over_tan_alpha(scene, rpm: int) -> None:
    ours = tables.cage_maximum(rpm, "omega", scene=scene)
    with mpmath.workdps(ref.DPS):
        exact = ref.spherical_max_cage_omega(rpm)
        assert abs((ours.value - exact) / exact) < TOL_OMEGA_MAX
    assert min(ours.phi, 2 * math.pi - ours.phi) < TOL_PHI_AT_MAX


@pytest.mark.parametrize("rpm", tables.RPM)
def test_max_cage_acceleration_is_the_exact_maximum(scene, rpm: int) -> None:
    ours = tables.cage_maximum(rpm, "epsilon", scene=scene)
    with mpmath.workdps(ref.DPS):
        exact = ref.spherical_max_cage_epsilon(rpm)
        where = float(ref.spherical_max_psi_ddot()[1])
        assert abs((ours.value - exact) / exact) < TOL_EPSILON_MAX
    peaks = (where, math.pi - where, math.pi + where, 2 * math.pi - where)
    assert min(abs(ours.phi - p) for p in peaks) < TOL_PHI_AT_MAX


@pytest.mark.parametrize("quantity", ["omega", "epsilon"])
def test_paper_columns_agree_with_ours(scene, quantity: str) -> None:
    for row in tables.table_rows(quantity, scene=scene):
        assert abs(row["Mathcad rel"]) < TOL_MATHCAD, row
        assert abs(row["SolidWorks rel"]) < TOL_SOLIDWORKS, row


def test_script_prints_both_tables_with_every_speed(scene) -> None:
    text = tables.markdown(scene=scene)
    assert "Table 1." in text and "Table 2." in text
    for rpm in tables.RPM:
        assert text.count(f"\n| {rpm} |") == 2
