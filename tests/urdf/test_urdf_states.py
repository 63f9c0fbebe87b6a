"""Tree joint states: velocities are the time derivatives of the positions, one frame agrees with
a sweep, and the driving crank follows φ unwrapped."""

from __future__ import annotations

import math
import types

import numpy as np
import pytest
from urdf_scene_lists import SINGLE_INPUT

import solver
from linkage_ros.urdf import (
    build_model,
    frame_tree_joint_states,
    kinematics_tree_joint_states,
    tree_joint_states,
)

EPS = float(np.finfo(float).eps)
#: Step of the central differences (s) and their tolerance, relative to the largest joint speed:
#: the truncation error is O(h²·q'''), about 1e-10 here.
H = 1e-5
TOL_DIFF = 1e-7
#: One frame against the same sample of a sweep: the same formulas, scalar against numpy.
TOL_SAME = 64 * EPS

SCENES = SINGLE_INPUT  # several inputs: tests/multi/test_multi_urdf.py


def _exportable(name: str) -> solver.Scene:
    return solver.load_scene(name)


def _law(t: np.ndarray, phi0: float, omega0: float, eps: float) -> tuple[np.ndarray, np.ndarray]:
    return phi0 + omega0 * t + 0.5 * eps * t * t, omega0 + eps * t


@pytest.mark.parametrize("name", SCENES)
def test_tree_joint_velocities_are_time_derivatives_of_their_positions(name: str) -> None:
    scene = _exportable(name).everything()
    model = build_model(scene)
    omega0, eps = 1.3, -0.4
    t = np.linspace(0.0, 4.0, 97)
    phi, omega = _law(t, 0.1, omega0, eps)
    k = scene.solve(phi, omega=omega, epsilon=np.full_like(phi, eps), mask=True)
    here = kinematics_tree_joint_states(model, k)
    plus_phi, _ = _law(t + H, 0.1, omega0, eps)
    minus_phi, _ = _law(t - H, 0.1, omega0, eps)
    plus = kinematics_tree_joint_states(model, scene.solve(plus_phi, mask=True)).position
    minus = kinematics_tree_joint_states(model, scene.solve(minus_phi, mask=True)).position
    step = plus - minus
    for i, joint in enumerate(model.joints):
        if joint.type == "continuous":
            step[:, i] = np.angle(np.exp(1j * step[:, i]))  # an angle's difference, modulo 2π
    diff = step / (2 * H)
    valid = np.asarray(k.valid, bool)
    scale = np.abs(here.velocity[valid]).max()
    assert np.abs(diff[valid] - here.velocity[valid]).max() <= TOL_DIFF * scale


@pytest.mark.parametrize("name", SCENES)
def test_one_frame_gives_the_states_of_the_same_sample_of_a_sweep(name: str) -> None:
    from linkage_ros.engine import Engine
    from linkage_ros.motion import Motion

    scene = _exportable(name)
    model = build_model(scene)
    span = scene.input_ranges[0]  # an actuator: from its closed length, in m/s
    motion = Motion(phi0=0.3, omega=2.5, epsilon=0.7) if span is None else Motion(phi0=span[0], omega=0.25,
                                                                                  epsilon=0.7)
    engine = Engine(scene, motion)
    frame = engine.frame(0.2)
    one = frame_tree_joint_states(model, frame)
    k = scene.everything().solve(np.array([frame.phi]), omega=frame.omega, epsilon=frame.epsilon)
    sweep = kinematics_tree_joint_states(model, k)
    assert one.names == sweep.names == model.joint_names
    assert np.allclose(one.position, sweep.position[0], rtol=0, atol=TOL_SAME * 10)
    assert np.allclose(one.velocity, sweep.velocity[0], rtol=TOL_SAME, atol=TOL_SAME * 10)
    assert tree_joint_states(model, frame) == one


@pytest.mark.parametrize("name", ["four_bar", "harvester_finger", "slider_crank"])
def test_driving_crank_joint_follows_phi_unwrapped(name: str) -> None:
    scene = solver.load_scene(name).everything()
    model = build_model(scene)
    phi = np.array([-7.0, 0.0, 3.0, 9.5, 40.0])
    states = tree_joint_states(model, scene.solve(phi, omega=2.0))
    assert states.names[0] == f"{scene.input_joint}_joint"
    assert np.allclose(states.position[:, 0], phi, rtol=0, atol=64 * EPS * 40)
    assert np.all(states.velocity[:, 0] == 2.0)


def test_four_bar_joint_angles_are_relative_to_the_parent_link() -> None:
    scene = solver.load_scene("four_bar").everything()
    model = build_model(scene)
    k = scene.solve(np.linspace(0.0, 2 * math.pi, 36, endpoint=False))
    states = tree_joint_states(model, k)
    coupler = k.joint("coupler").position  # absolute angle of AB
    rocker = k.joint("rocker").position  # absolute angle of CB
    relative = np.angle(np.exp(1j * (coupler - k.phi)))
    assert np.allclose(states.position[:, 1], relative, atol=64 * EPS)
    assert np.allclose(states.position[:, 2], rocker, atol=64 * EPS)


def test_harvester_eyelet_slide_is_the_distance_from_pivot_to_eyelet() -> None:
    scene = solver.load_scene("harvester_finger").everything()
    model = build_model(scene)
    k = scene.solve(np.linspace(0.0, 2 * math.pi, 36, endpoint=False), omega=3.0)
    states = tree_joint_states(model, k)
    assert np.allclose(states.position[:, 2], k.joint("eyelet").position, rtol=0, atol=64 * EPS)
    assert np.allclose(states.velocity[:, 2], k.joint("eyelet").velocity, rtol=0, atol=64 * EPS)


def test_frame_without_fixed_points_reads_them_from_the_model() -> None:
    from linkage_ros.engine import Engine
    from linkage_ros.motion import Motion

    scene = solver.load_scene("harvester_finger")
    model = build_model(scene)
    frame = Engine(scene, Motion(omega=1.0)).frame(0.4)
    moving = {n: p for n, p in frame.points.items() if n not in scene.fixed_points}
    bare = types.SimpleNamespace(points=moving, joints=frame.joints)
    assert frame_tree_joint_states(model, bare) == frame_tree_joint_states(model, frame)
