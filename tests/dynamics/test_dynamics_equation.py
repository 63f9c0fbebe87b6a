"""The equation of motion in the inputs: M(q)·q̈ + h(q, q̇) is the kinetostatic effort, exactly.

Checks that need no trust in the new code: the effort of ``Scene.solve`` (route 2, itself checked
against a 50-digit Newton–Euler reference) at random states; M symmetric positive definite with
several inputs; damping and flywheel in route 1 (virtual power) against route 2.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import solver
from solver.forces.virtual import virtual_efforts
from solver.tolerances import EPS

#: agreement of two evaluations of the same exact quantity, relative to the efforts' size
REL = 256 * EPS

ONE_INPUT = ["four_bar_loaded", "engine", "harvester_finger", "four_bar_pendulum"]

angle = st.floats(-math.pi, math.pi, allow_nan=False)
rate = st.floats(-50.0, 50.0, allow_nan=False)


@settings(max_examples=25, deadline=None)
@given(st.sampled_from(ONE_INPUT), angle, rate, rate)
def test_m_eps_plus_h_is_the_effort_one_input(name: str, phi: float, w: float, e: float) -> None:
    scene = solver.load_scene(name)
    model = scene.reduced()
    m, h, _ = model.instant((phi,), (w,))
    effort = scene.solve(phi, omega=w, epsilon=e).effort(scene.inputs[0])
    scale = max(1.0, abs(effort), abs(h[0]), abs(m * e))
    assert abs(m * e + h[0] - effort) <= REL * scale
    # the vectorised evaluation gives the same numbers
    assert model.mass(np.array([phi]))[0] == pytest.approx(m, rel=REL, abs=REL)
    assert model.bias(np.array([phi]), w)[0] == pytest.approx(h[0], rel=REL, abs=REL * scale)


@settings(max_examples=20, deadline=None)
@given(st.floats(60.0, 120.0), st.floats(60.0, 120.0), rate, rate, rate, rate)
def test_m_eps_plus_h_is_the_effort_and_m_is_spd_with_two_inputs(
    a: float, b: float, w1: float, w2: float, e1: float, e2: float
) -> None:
    scene = solver.load_scene("five_bar")
    q = (math.radians(a), math.radians(b))
    model = scene.reduced()
    m, h, _ = model.instant(q, (w1, w2))
    mm = np.array(m)
    k = scene.solve(np.array(q), omega=(w1, w2), epsilon=(e1, e2))
    lhs = mm @ np.array([e1, e2]) + np.array(h)
    rhs = np.array([k.effort("q1"), k.effort("q2")])
    assert np.abs(lhs - rhs).max() <= REL * max(1.0, float(np.abs(rhs).max()), float(np.abs(mm).max()) * 50)
    assert np.abs(mm - mm.T).max() <= REL * np.abs(mm).max()
    assert np.linalg.eigvalsh(mm).min() > 0.0
    np.testing.assert_allclose(model.mass(np.array([q]))[0], mm, rtol=REL, atol=REL * np.abs(mm).max())


def test_generalised_forces_add_up_to_minus_h() -> None:
    scene = solver.load_scene("engine")
    model = scene.reduced()
    phi = np.linspace(0.0, 4 * math.pi, 97)
    parts = model.generalized_forces(phi, 200.0)
    assert set(parts) == {"gravity", "loads[0]", "damping.crankshaft", "velocity"}
    total = sum(parts.values())
    np.testing.assert_allclose(total, -model.bias(phi, 200.0), rtol=0, atol=1e-9 * np.abs(total).max())
    np.testing.assert_allclose(parts["damping.crankshaft"], -0.11 * 200.0, rtol=1e-14)


def test_the_engines_gas_force_does_net_work_over_its_720_degree_cycle() -> None:
    scene = solver.load_scene("engine")
    phi = np.linspace(0.0, 4 * math.pi, 14401)
    gas = scene.reduced().generalized_forces(phi, 0.0)["loads[0]"]
    work = float(np.sum(0.5 * (gas[1:] + gas[:-1]) * np.diff(phi)))
    assert 295.0 < work < 312.0  # J per cycle (bench/engine_cycle.py's indicator diagram: about 304 J)
    one_turn = float(np.sum(0.5 * (gas[1:7201] + gas[:7200]) * np.diff(phi[:7201])))
    assert one_turn > 0.9 * work  # the power stroke is in the first turn


def test_damping_and_flywheel_agree_by_virtual_power() -> None:
    scene = solver.load_scene("engine")  # a flywheel and a damper on the crankshaft
    phi = np.linspace(0.0, 4 * math.pi, 50)
    w, e = 210.0 + 5 * np.sin(phi), 30 * np.cos(phi)
    route2 = scene.solve(phi, omega=w, epsilon=e).effort("crankshaft")
    route1 = virtual_efforts(scene, phi, omega=w, epsilon=e)["crankshaft"]
    np.testing.assert_allclose(route1, route2, rtol=0, atol=1e-9 * np.abs(route2).max())


def test_a_revolute_damper_acts_between_its_two_links(tmp_path: object) -> None:
    base = solver.load_scene("four_bar_pendulum")
    import yaml

    data = yaml.safe_load(solver.find_scene("four_bar_pendulum").read_text(encoding="utf-8"))
    data["joints"]["knee"] = {"revolute": {"parent": ["A", "B"], "child": ["C", "B"], "sign": -1}}
    data["damping"] = {"knee": 0.3, "rocker": 0.2}
    from scene_builders import build

    scene = build(data)
    phi = np.linspace(0.0, 2 * math.pi, 40)
    k = scene.solve(phi, omega=2.5, epsilon=0.4)
    np.testing.assert_allclose(virtual_efforts(scene, phi, omega=2.5, epsilon=0.4)["crank"], k.effort("crank"),
                               rtol=0, atol=1e-11)
    assert np.abs(k.effort("crank") - base.solve(phi, omega=2.5, epsilon=0.4).effort("crank")).max() > 1e-3
