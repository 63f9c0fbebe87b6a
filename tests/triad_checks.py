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


def dense_sweep(make_scene: Any, case: dict) -> tuple[Any, Any, np.ndarray, list[bool]]:
    """A slider triad's reference ``case`` swept 1201 samples across its range (its own φ among
    them): ``(k, full, where, calls)`` — the sweep through the anchors' shortcut
    (solver.groups._slider_triad_sweep.fast_sweep, watched: ``calls`` says for each call whether
    it was taken), the same sweep on the full path, and where the reference's φ lie in it."""
    from unittest import mock

    from solver.groups import _slider_triad_sweep

    phi_s = np.array([float(s["phi"]) for s in case["samples"]])
    phi = np.unique(np.concatenate([np.linspace(phi_s.min(), phi_s.max(), 1201), phi_s]))
    calls: list[bool] = []
    real = _slider_triad_sweep.fast_sweep

    def spy(*args: Any, **kw: Any) -> Any:
        out = real(*args, **kw)
        calls.append(out is not None)
        return out
    with mock.patch.object(_slider_triad_sweep, "fast_sweep", spy):
        k = make_scene(case).solve(phi)
    with mock.patch.object(_slider_triad_sweep, "fast_sweep", lambda *a, **kw: None):
        full = make_scene(case).solve(phi)
    return k, full, np.searchsorted(phi, phi_s), calls


def assert_dense_match(k: Any, full: Any, where: np.ndarray, samples: Sequence[dict], size: float) -> None:
    """:func:`dense_sweep`'s sweep: the reference at its φ (positions and velocity analogs) and
    the full path's positions at every sample."""
    for name in "DEF":
        got = k.point(name).position @ [1, 1j]
        ref = np.array([complex_of(s[name]) for s in samples])
        vel = np.array([complex_of(s["d" + name]) for s in samples])
        assert np.abs(got[where] - ref).max() <= TOL_POS * size, name
        assert np.abs((k.point(name).velocity @ [1, 1j])[where] - vel).max() <= TOL_VEL * size, name
        assert np.abs(got - full.point(name).position @ [1, 1j]).max() <= TOL_POS * size, name
