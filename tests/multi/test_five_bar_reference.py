"""The shipped five-bar (two inputs) against its independent 50-digit reference.

tests/data/reference_five_bar.json comes from tests/reference/mp_reference.py (mpmath only, never
the solver): closed-form positions at mp.dps = 50, partial derivatives in (q1, q2) by mpmath's
numerical differentiation, on the grid (q1, q2) ∈ {40°, 50°, …, 140°}².

Tolerances (issue 14, "How it is checked"):
* P to TOL_POS m; joints to TOL_POS rad;
* jacobian TOL_JACOBIAN and velocity (ω = (2, −1.5) rad/s) TOL_VELOCITY, hessian TOL_HESSIAN and
  acceleration (ε = (0.7, 3) rad/s²) TOL_ACCELERATION, relative to max(|ref|, scale): the scale is
  the longest link L = 0.25 m for P (1 rad for joints) times |ω| for velocities and
  |ω|² + |ε| for accelerations (1 for the derivatives), so a component passing through zero is
  held to the tolerance times the mechanism's size, not relative to a tiny number.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

import solver

TOL_POS = 1e-12
TOL_JACOBIAN = 1e-9
TOL_HESSIAN = 1e-8
TOL_VELOCITY = 1e-9
TOL_ACCELERATION = 1e-8

REF = json.loads((Path(__file__).resolve().parent.parent / "data" / "reference_five_bar.json").read_text())
OMEGA = np.array([float(x) for x in REF["motion"]["omega"]])
EPSILON = np.array([float(x) for x in REF["motion"]["epsilon"]])
Q = np.array([[float(a), float(b)] for a, b in REF["q"]])
JOINTS = ("q1", "q2", "left_distal", "right_distal")


def _floats(values: list) -> np.ndarray:
    return np.array([_floats(v) if isinstance(v, list) else float(v) for v in values], dtype=float)


def _reference(entry: dict) -> tuple[np.ndarray, ...]:
    """(position, jacobian, hessian, velocity, acceleration) with the solver's axis order."""
    d1, d2 = _floats(entry["d_dq1"]), _floats(entry["d_dq2"])
    h11, h12, h22 = (_floats(entry[k]) for k in ("d2_dq1dq1", "d2_dq1dq2", "d2_dq2dq2"))
    jac = np.stack([d1, d2], axis=-1)
    hess = np.stack([np.stack([h11, h12], axis=-1), np.stack([h12, h22], axis=-1)], axis=-2)
    return _floats(entry["position"]), jac, hess, _floats(entry["velocity"]), _floats(entry["acceleration"])


def _assert_rel(label: str, got: np.ndarray, want: np.ndarray, scale: float, tol: float) -> None:
    assert got.shape == want.shape, f"{label}: shape {got.shape}, reference {want.shape}"
    rel = np.abs(got - want) / np.maximum(np.abs(want), scale)
    worst = np.unravel_index(np.argmax(rel), rel.shape)
    assert rel[worst] <= tol, f"{label}: relative error {rel[worst]:.3e} > {tol:g} at {worst}"


@pytest.fixture(scope="module")
def solved() -> solver.Kinematics:
    return solver.load_scene("five_bar").solve(Q, omega=OMEGA, epsilon=EPSILON)


def test_five_bar_declares_two_inputs_and_the_contracted_outputs() -> None:
    scene = solver.load_scene("five_bar")
    assert scene.inputs == ("q1", "q2") == tuple(REF["inputs"])
    assert scene.input_joint == "q1"
    assert scene.output_points == ("P",)
    assert scene.output_joints == JOINTS


def test_end_effector_matches_the_50_digit_reference(solved: solver.Kinematics) -> None:
    pos, jac, hess, vel, acc = _reference(REF["points"]["P"])
    length = float(REF["scale_length"])
    p = solved.point("P")
    err = np.abs(p.position - pos)
    assert err.max() <= TOL_POS, f"P position: max error {err.max():.3e} m"
    _assert_rel("P jacobian", p.jacobian, jac, length, TOL_JACOBIAN)
    _assert_rel("P hessian", p.hessian, hess, length, TOL_HESSIAN)
    w, e = np.abs(OMEGA).max(), np.abs(EPSILON).max()
    _assert_rel("P velocity", p.velocity, vel, length * w, TOL_VELOCITY)
    _assert_rel("P acceleration", p.acceleration, acc, length * (w * w + e), TOL_ACCELERATION)


@pytest.mark.parametrize("joint", JOINTS)
def test_joints_match_the_50_digit_reference(solved: solver.Kinematics, joint: str) -> None:
    pos, jac, hess, vel, acc = _reference(REF["joints"][joint])
    j = solved.joint(joint)
    assert np.abs(j.position - pos).max() <= TOL_POS
    _assert_rel(f"{joint} jacobian", j.jacobian, jac, 1.0, TOL_JACOBIAN)
    _assert_rel(f"{joint} hessian", j.hessian, hess, 1.0, TOL_HESSIAN)
    w, e = np.abs(OMEGA).max(), np.abs(EPSILON).max()
    _assert_rel(f"{joint} velocity", j.velocity, vel, w, TOL_VELOCITY)
    _assert_rel(f"{joint} acceleration", j.acceleration, acc, w * w + e, TOL_ACCELERATION)


def test_per_tick_instants_match_the_reference_too() -> None:
    scene = solver.load_scene("five_bar")
    pos, jac, hess, vel, acc = _reference(REF["points"]["P"])
    for i in range(0, len(Q), 13):
        k = scene.solve(tuple(Q[i]), omega=tuple(OMEGA), epsilon=tuple(EPSILON))
        p = k.point("P")
        assert np.abs(p.position - pos[i]).max() <= TOL_POS
        _assert_rel("P jacobian (tick)", p.jacobian, jac[i], 0.25, TOL_JACOBIAN)
        _assert_rel("P hessian (tick)", p.hessian, hess[i], 0.25, TOL_HESSIAN)
        _assert_rel("P velocity (tick)", p.velocity, vel[i], 0.25 * 2.0, TOL_VELOCITY)
        _assert_rel("P acceleration (tick)", p.acceleration, acc[i], 0.25 * 7.0, TOL_ACCELERATION)


def test_stored_reference_is_what_its_generator_computes() -> None:
    """A few samples of the file regenerated from scratch (mpmath only)."""
    mpmath = pytest.importorskip("mpmath", reason="regenerating the reference needs mpmath")
    import importlib.util
    import sys

    path = Path(__file__).resolve().parent.parent / "reference" / "mp_reference.py"
    spec = importlib.util.spec_from_file_location("mp_reference", path)
    assert spec is not None and spec.loader is not None
    gen = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("mp_reference", gen)
    spec.loader.exec_module(gen)
    picks = [0, 60, 120]
    fresh = gen.build_five_bar_reference([tuple(float(x) for x in REF["q"][i]) for i in picks])
    assert REF["provenance"].startswith("tests/reference/mp_reference.py (mpmath ")
    for kind in ("points", "joints"):
        for name, entry in fresh[kind].items():
            for key, values in entry.items():
                if key == "kind":
                    continue
                for row, i in enumerate(picks):
                    a, b = np.atleast_1d(REF[kind][name][key][i]), np.atleast_1d(values[row])
                    diff = max(abs(mpmath.mpf(x) - mpmath.mpf(y)) for x, y in zip(a, b, strict=True))
                    assert diff < 1e-40, f"{name} {key} at #{i}: {diff}"
