"""Forward dynamics: energy, closure, the small-oscillation period, stops and bad input."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml
from scipy.optimize import brentq

import solver
from solver.dynamics import Stepper, flywheel_for, run_up, steady_state
from solver.tolerances import EPS

#: loop closure of the points along a run: round-off of lengths of order 0.1–0.4 m
CLOSURE = 64 * EPS


def _data(name: str) -> dict[str, Any]:
    return yaml.safe_load(solver.find_scene(name).read_text(encoding="utf-8"))


def _load(tmp_path: Path, data: dict[str, Any]) -> solver.Scene:
    path = tmp_path / "scene.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return solver.load_scene(path)


@pytest.mark.slow
def test_a_conservative_scene_keeps_its_energy_over_100_oscillations_and_its_loop_closed() -> None:
    scene = solver.load_scene("four_bar_pendulum")
    traj = scene.simulate(130.0, phi0=0.3, rtol=1e-11, atol=1e-11)
    assert traj.status == "done" and traj.t[-1] == 130.0
    crossings = np.count_nonzero(np.diff(np.sign(traj.omega)) != 0)
    assert crossings >= 200  # ≥ 100 full oscillations
    e = traj.energy()
    swing = float(np.ptp(e["kinetic"]))
    assert np.abs(e["balance"]).max() <= 1e-7 * swing
    k = traj.solve()
    a, b = k.point("A").position, k.point("B").position
    c = np.array([0.4, 0.0])
    assert np.abs(np.hypot(*(b - a).T) - 0.4).max() <= CLOSURE
    assert np.abs(np.hypot(*(b - c).T) - 0.3).max() <= CLOSURE


def test_the_small_oscillation_period_is_two_pi_root_j_over_v2() -> None:
    scene = solver.load_scene("four_bar_pendulum")
    model = scene.reduced()

    def q_gravity(phi: float) -> float:
        return float(model.generalized_forces(np.array([phi]), 0.0)["gravity"][0])

    grid = np.linspace(-math.pi, math.pi, 73)
    values = [q_gravity(p) for p in grid]
    # the stable equilibrium: Q_gravity falls through zero (V has a minimum)
    a, b = next((x, y) for x, y, fa, fb in zip(grid, grid[1:], values, values[1:]) if fa > 0 >= fb)
    eq = brentq(q_gravity, a, b, xtol=1e-15)
    h = 1e-4
    stiffness = -(q_gravity(eq + h) - q_gravity(eq - h)) / (2 * h)  # V'' (truncation ~h², 1e-8 relative)
    j = float(model.mass(np.array([eq]))[0])
    expected = 2 * math.pi * math.sqrt(j / stiffness)
    traj = scene.simulate(5 * expected, phi0=eq + 1e-4, rtol=1e-12, atol=1e-14)
    up = [t for t0, t1, w0, w1 in zip(traj.t, traj.t[1:], traj.omega, traj.omega[1:]) if w0 < 0 <= w1
          for t in [brentq(lambda s: float(traj.at(s)[1]), t0, t1, xtol=1e-14)]]
    period = float(np.mean(np.diff(up)))
    assert period == pytest.approx(expected, rel=1e-6)


def test_mass_matrix_times_epsilon_plus_h_equals_drive_along_a_run() -> None:
    scene = solver.load_scene("five_bar")
    traj = scene.simulate(0.5, phi0=np.radians([60.0, 120.0]), omega0=(0.0, 0.0), drive=(0.05, -0.02),
                          on_singular="stop")
    k = traj.solve()
    for i, name in enumerate(scene.inputs):
        np.testing.assert_allclose(k.effort(name), traj.effort[:, i], rtol=0, atol=1e-9)


def test_a_stepper_follows_simulate() -> None:
    scene = solver.load_scene("four_bar_loaded")
    traj = scene.simulate(1.0, phi0=0.3, dt=0.01, rtol=1e-10, atol=1e-10)
    stepper = Stepper(scene, phi0=0.3, rtol=1e-10, atol=1e-10)
    got = np.array([stepper.advance(float(t))[:2] for t in traj.t])
    np.testing.assert_allclose(got[:, 0], traj.phi, rtol=0, atol=1e-7)
    np.testing.assert_allclose(got[:, 1], traj.omega, rtol=0, atol=1e-6)


def test_damping_dissipates_and_the_balance_counts_it(tmp_path: Path) -> None:
    data = _data("four_bar_pendulum")
    data["damping"] = {"rocker": 0.05}
    scene = _load(tmp_path, data)
    traj = scene.simulate(5.0, phi0=0.3, rtol=1e-10, atol=1e-10)
    e = traj.energy()
    assert traj.work_other[-1] < -0.01  # the damper took energy out
    assert np.abs(e["balance"]).max() <= 1e-7


def test_a_triple_rocker_stops_at_its_toggle_with_one_line(tmp_path: Path) -> None:
    data = _data("four_bar_pendulum")
    data["groups"][0]["length"] = 0.3  # s + l > p + q: the crank cannot turn fully
    data["fixed"]["C"] = [0.45, 0.0]
    scene = _load(tmp_path, data)
    with pytest.raises(solver.DynamicsError, match=r"t = .* s, crank = .* rad .*: reaches a singular position of "
                                                   r"group 'dyad'") as info:
        scene.simulate(20.0, phi0=1.2, omega0=-8.0)
    partial = info.value.trajectory  # type: ignore[attr-defined]
    assert partial.status == "toggle" and partial.t[-1] < 20.0
    stopped = scene.simulate(20.0, phi0=1.2, omega0=-8.0, on_singular="stop")
    assert stopped.status == "toggle" and "group 'dyad'" in stopped.message


def test_until_phi_stops_the_run_there() -> None:
    scene = solver.load_scene("harvester_finger")
    traj = scene.simulate(10.0, phi0=0.0, until_phi=2 * math.pi)
    assert traj.status == "until" and traj.phi[-1] == pytest.approx(2 * math.pi, abs=1e-9)


BAD_SCENES = [
    (lambda d: d.update(motor={"rocker": {"stall_torque": 1.0, "no_load_speed": 2.0}}),
     r"motor\.rocker: 'rocker' is not an input of the scene; inputs: crank"),
    (lambda d: d.update(motor={"crank": {"stall_torque": 1.0}}), r"motor\.crank: a motor needs stall_torque"),
    (lambda d: d.update(motor={"crank": {"speed": [0, 1], "torque": [1.0, 2.0, 3.0]}}), r"has 3 torques for 2 speeds"),
    (lambda d: d.update(motor={"crank": {"stall_torque": 1.0, "no_load_speed": 0}}), r"no_load_speed: must not be 0"),
    (lambda d: d.update(flywheel={"crank": -0.2}), r"flywheel\.crank: must not be negative, got -0.2 kg·m²"),
    (lambda d: d.update(flywheel={"crnk": 0.2}), r"'crnk' is not an input of the scene \(did you mean 'crank'\?\)"),
    (lambda d: d.update(damping={"rocker": -1.0}), r"damping\.rocker: must not be negative"),
    (lambda d: d.update(damping={"rockr": 1.0}), r"unknown joint 'rockr' \(did you mean 'rocker'\?\)"),
    (lambda d: d.update(damping=[1.0]), r"damping: must map joint names to values"),
]


@pytest.mark.parametrize(("edit", "message"), BAD_SCENES)
def test_bad_drive_keys_are_one_scene_error_line(tmp_path: Path, edit: Any, message: str) -> None:
    data = copy.deepcopy(_data("four_bar_pendulum"))
    edit(data)
    with pytest.raises(solver.SceneError, match=message) as info:
        _load(tmp_path, data)
    assert "\n" not in str(info.value)


def test_damping_on_a_slide_is_refused_with_the_reason(tmp_path: Path) -> None:
    data = _data("engine")
    data["damping"] = {"piston_x": 10.0}
    with pytest.raises(solver.SceneError, match=r"damping\.piston_x: 'piston_x' is a x coordinate; damping is "
                                                r"modelled in revolute joints"):
        _load(tmp_path, data)


def test_a_table_longer_than_its_period_is_refused(tmp_path: Path) -> None:
    data = _data("engine")
    data["loads"][0]["table"]["period"] = 360
    with pytest.raises(solver.SceneError, match=r"loads\[0\]\.table\.period: the table spans 720, more than one"):
        _load(tmp_path, data)


def test_bad_runs_are_one_clear_line(tmp_path: Path) -> None:
    scene = solver.load_scene("four_bar_pendulum")
    with pytest.raises(solver.DynamicsError, match=r"four_bar_pendulum: phi0 must be a finite number, got nan"):
        scene.simulate(1.0, phi0=float("nan"))
    with pytest.raises(solver.DynamicsError, match=r"t_end must be a positive number of seconds"):
        scene.simulate(-1.0)
    with pytest.raises(solver.SolverError, match=r"the drive gives \[1.0, 2.0\] where it must give 1 effort"):
        scene.simulate(1.0, drive=[1.0, 2.0])
    with pytest.raises(solver.SolverError, match=r"drive='motor' but the scene has no 'motor:'"):
        scene.simulate(1.0, drive="motor")
    massless = _data("four_bar_pendulum")
    for body in massless["bodies"].values():
        body["mass"], body["inertia"] = 0.0, 0.0
    with pytest.raises(solver.DynamicsError, match=r"every link is massless .* the reduced inertia is zero"):
        _load(tmp_path, massless).simulate(1.0)
    with pytest.raises(solver.DynamicsError, match=r"names no bodies, gravity or loads"):
        solver.load_scene("four_bar").simulate(1.0)
    with pytest.raises(solver.DynamicsError, match=r"five_bar: phi0 must be 2 finite numbers"):
        solver.load_scene("five_bar").simulate(1.0, phi0=[1.0, math.inf])


def test_harvester_runs_up_under_its_motor_to_its_steady_band() -> None:
    scene = solver.load_scene("harvester_finger")
    steady = steady_state(scene)
    assert 0.0 < steady.omega_min < steady.omega_mean < 8.0 < steady.omega_max  # gravity swings it past no-load
    assert steady.delta == pytest.approx((steady.omega_max - steady.omega_min) / steady.omega_mean)
    up = run_up(scene)
    assert 0.0 < up.time < 5.0
    assert up.trajectory.omega[-1] == pytest.approx(steady.omega_min, rel=1e-6)


@pytest.mark.slow
def test_the_engines_flywheel_gives_delta_one_80th() -> None:
    scene = solver.load_scene("engine")
    steady = steady_state(scene)
    assert steady.delta == pytest.approx(1 / 80, rel=1e-3)
    assert steady.cycle == pytest.approx(4 * math.pi)


def test_flywheel_for_a_looser_delta_needs_none() -> None:
    scene = solver.load_scene("harvester_finger")
    jf, state, _ = flywheel_for(scene, 0.9)
    assert jf == 0.0 and state.delta < 0.9


def test_a_cylinder_driven_by_a_force_stops_at_the_end_of_its_stroke() -> None:
    scene = solver.load_scene("tipper")  # a stroke input: its effort is the cylinder's force (N)
    (lo, hi), = scene.input_ranges
    m, h, _ = scene.reduced().instant(((lo + hi) / 2,), (0.0,))
    assert m > 0 and h[0] > 0  # a reduced mass (kg) and the load's weight along the stroke (N)
    run = scene.simulate(2.0, phi0=(lo + hi) / 2, drive=10 * h[0], on_singular="stop")
    assert run.status == "assembly" and run.phi[-1] == pytest.approx(hi, abs=1e-9)
    # the stroke's event, or the step beyond it rejected first: either way the limit and the group
    assert "stroke = 1.3 m" in run.message and "group 'lift'" in run.message and "[0.74, 1.3] m" in run.message
    k = run.solve()
    np.testing.assert_allclose(k.effort("stroke"), run.effort, rtol=1e-9)  # M·s̈ + h = the force applied
    with pytest.raises(solver.DynamicsError, match=r"t = .* s, stroke = 0.74 m: (stops at an assembly limit of group "
                                                   r"'lift' \(is outside its stroke|reaches an end of the stroke "
                                                   r"\[0.74, 1.3\] m of group 'lift')"):
        scene.simulate(2.0, phi0=(lo + hi) / 2, drive=0.0)
