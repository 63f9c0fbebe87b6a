"""Checks shared by the triads' tests (tests/solver/test_triad.py, test_slider_triad.py,
test_slider_triad_variants.py) against their 50-digit continuation references
(tests/data/reference_*triad*.json, made by tests/reference/*triad*_mp.py): a reference's complex
numbers and the comparison of a sweep's points and joints with its samples."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

__all__ = ["TOL_POS", "TOL_VEL", "complex_of", "assert_points_match", "assert_joints_match"]

#: Positions against the reference, of the mechanism's size.
TOL_POS = 1e-12
#: Velocity analogs against the reference, of the size (per rad).
TOL_VEL = 1e-9


def complex_of(pair: Sequence[str]) -> complex:
    """A reference's point, stored as two decimal strings."""
    return complex(float(pair[0]), float(pair[1]))


def assert_points_match(k: Any, samples: Sequence[dict], size: float, names: str = "DEF") -> None:
    """The sweep ``k``'s positions and velocity analogs of ``names`` at the reference's samples
    (keys ``P`` and ``dP``), within ``TOL_POS``/``TOL_VEL`` of ``size``."""
    for name in names:
        ref = np.array([complex_of(s[name]) for s in samples])
        vel = np.array([complex_of(s["d" + name]) for s in samples])
        assert np.abs(k.point(name).position @ [1, 1j] - ref).max() <= TOL_POS * size, name
        assert np.abs(k.point(name).velocity @ [1, 1j] - vel).max() <= TOL_VEL * size, name


def assert_joints_match(k: Any, samples: Sequence[dict], size: float,
                        joints: Sequence[tuple[str, str]] = (("ternary", "theta"), ("s", "s"))) -> None:
    """The sweep ``k``'s joints (name, the reference's key) and their analogs (key ``d`` + key)."""
    for joint, key in joints:
        ref_q = np.array([float(s[key]) for s in samples])
        ref_v = np.array([float(s["d" + key]) for s in samples])
        assert np.abs(k.joint(joint).position - ref_q).max() <= TOL_POS * size, joint
        assert np.abs(k.joint(joint).velocity - ref_v).max() <= TOL_VEL * size, joint
