"""Coupled inputs (issue 31): a crank turned by another input, q = c₀ + c₁·p, and a crank whose
joint is read in a model's own convention, θ = θ₀ + σ·q. Checked against the same mechanism
with two independent inputs driven along the coupling (positions, analogs, real motion,
efforts, the equation of motion), on the vectorised, scalar and compiled paths."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import solver
from tests.scene_builders import build

C0, C1, TH0, SG = math.radians(10.0), 0.5, math.radians(30.0), -1.0


def _pair(coupled: bool) -> dict[str, Any]:
    second: dict[str, Any] = {"type": "crank", "name": "crank2", "center": "O2", "point": "A2", "length": 0.1}
    if coupled:
        second |= {"joint": "q2", "offset": 30.0, "sign": -1, "follows": {"joint": "q", "ratio": C1, "offset": 10.0}}
    else:
        second |= {"joint": "t2"}
    body = {"mass": 1.0, "center": [0.05, 0.01], "inertia": 0.01}
    return {
        "scene": "coupled_pair",
        "units": {"length": "m", "angle": "deg"},
        "fixed": {"O": [0.0, 0.0], "C": [0.4, 0.0], "O2": [0.0, -1.0], "C2": [0.4, -1.0]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": 0.1, "joint": "q"},
            {"type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [0.4, 0.3], "M": 1},
            second,
            {"type": "rrr", "name": "dyad2", "ends": ["A2", "C2"], "point": "B2", "lengths": [0.4, 0.3], "M": -1},
        ],
        "bodies": {
            "crank": {"points": ["O", "A"], **body},
            "crank2": {"points": ["O2", "A2"], **body},
            "dyad.1": {"points": ["A", "B"], **body},
            "dyad2.2": {"points": ["C2", "B2"], **body},
        },
        "gravity": [0.0, -9.81],
        "outputs": {"points": ["B", "B2"], "joints": ["q2"] if coupled else ["t2"]},
    }


@pytest.fixture(scope="module")
def scenes() -> tuple[solver.Scene, solver.Scene]:
    return build(_pair(True)), build(_pair(False))


def _theta(q: Any) -> Any:
    return TH0 + SG * (C0 + C1 * q)


def test_one_input_and_the_joint_follows(scenes: tuple[solver.Scene, solver.Scene]) -> None:
    coupled, _ = scenes
    assert coupled.inputs == ("q",)
    k = coupled.solve(0.7, omega=1.3, epsilon=0.4)
    q2 = k.joint("q2")
    assert q2.position == pytest.approx(C0 + C1 * 0.7, abs=1e-15)
    assert q2.velocity == pytest.approx(C1 * 1.3, abs=1e-15)
    assert q2.acceleration == pytest.approx(C1 * 0.4, abs=1e-15)


@pytest.mark.parametrize("q", [0.0, 0.7, 2.5, -1.9])
def test_against_two_independent_inputs(scenes: tuple[solver.Scene, solver.Scene], q: float) -> None:
    coupled, free = scenes
    w, e, b = 1.3, 0.4, SG * C1
    k = coupled.solve(q, omega=w, epsilon=e)
    kf = free.solve((q, _theta(q)), omega=(w, b * w), epsilon=(e, b * e))
    for p in ("B", "B2"):
        for attr in ("position", "velocity", "acceleration"):
            assert np.allclose(getattr(k.point(p), attr), getattr(kf.point(p), attr), rtol=0, atol=1e-15)
    # the shared input's effort: its own crank's, plus c₁ times the coupled joint's (σ·torque)
    assert k.effort("q") == pytest.approx(kf.effort("q") + b * kf.effort("t2"), rel=1e-13, abs=1e-15)


def test_paths_agree(scenes: tuple[solver.Scene, solver.Scene]) -> None:
    coupled, _ = scenes
    qs = np.linspace(-3.0, 3.0, 41)
    kv = coupled.solve(qs, omega=1.3, epsilon=0.4)
    for i, q in enumerate(qs):
        compiled = coupled.solve(float(q), omega=1.3, epsilon=0.4)
        plain = coupled._solve_scalar(float(q), 1.3, 0.4, False, compiled=False)
        for k in (compiled, plain):
            assert np.allclose(k.point("B2").acceleration, kv.point("B2").acceleration[i], rtol=0, atol=1e-15)
            assert k.effort("q") == pytest.approx(float(kv.effort("q")[i]), rel=1e-13, abs=1e-15)


def test_analogs_against_finite_differences(scenes: tuple[solver.Scene, solver.Scene]) -> None:
    coupled, _ = scenes
    q, h = 0.9, 1e-4
    z = [complex(*coupled.solve(q + i * h).point("B2").position) for i in (-2, -1, 0, 1, 2)]
    d1 = (z[0] - 8 * z[1] + 8 * z[3] - z[4]) / (12 * h)
    d2 = (-z[0] + 16 * z[1] - 30 * z[2] + 16 * z[3] - z[4]) / (12 * h * h)
    k = coupled.solve(q)
    assert abs(complex(*k.point("B2").velocity) - d1) < 1e-9
    assert abs(complex(*k.point("B2").acceleration) - d2) < 1e-6


def test_equation_of_motion_sees_the_coupling(scenes: tuple[solver.Scene, solver.Scene]) -> None:
    coupled, free = scenes
    q, b = 0.6, SG * C1
    m = np.asarray(coupled.reduced().mass(np.array([[q]])), float).reshape(1, 1)
    mf = np.asarray(free.reduced().mass(np.array([[q, _theta(q)]])), float).reshape(2, 2)
    expected = mf[0, 0] + 2 * b * mf[0, 1] + b * b * mf[1, 1]
    assert m[0, 0] == pytest.approx(expected, rel=1e-12)


def test_follows_an_input_crank_only() -> None:
    data = _pair(True)
    data["groups"][2]["follows"]["joint"] = "nope"
    with pytest.raises(solver.SceneError, match=r"crank 'crank2' follows 'nope', no input joint: .*input cranks: q"):
        build(data)
    data["groups"][2]["follows"] = {"joint": "q", "ratio": 0}
    with pytest.raises(solver.SceneError, match=r"follows.ratio: must be a non-zero finite ratio"):
        build(data)


@settings(max_examples=40, deadline=None)
@given(ratio=st.floats(-3.0, 3.0).filter(lambda r: abs(r) > 1e-3), shift=st.floats(-3.0, 3.0),
       q=st.floats(-3.0, 3.0), sign=st.sampled_from([1, -1]))
def test_any_linear_coupling_is_the_free_pair_driven_along_it(ratio: float, shift: float, q: float,
                                                             sign: int) -> None:
    data = _pair(True)
    data["units"]["angle"] = "rad"
    data["groups"][2] |= {"offset": 0.5, "sign": sign, "follows": {"joint": "q", "ratio": ratio, "offset": shift}}
    coupled = build(data)
    free = build(_pair(False))
    theta = 0.5 + sign * (shift + ratio * q)
    k = coupled.solve(np.array([q]), mask=True)
    kf = free.solve(np.array([[q, theta]]), mask=True)
    assert bool(k.valid[0]) == bool(kf.valid[0])
    if k.valid[0]:
        b = sign * ratio
        np.testing.assert_allclose(k.point("B2").position, kf.point("B2").position, rtol=0, atol=1e-15)
        j = np.asarray(kf.point("B2").jacobian)[0]  # (2, 2): ∂B2/∂(q, t2)
        np.testing.assert_allclose(np.asarray(k.point("B2").velocity)[0], j[:, 1] * b, rtol=0, atol=1e-13)
