"""The engine: frames equal the solver's values; unassemblable positions never give NaN."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

import solver
from linkage_ros.engine import Engine
from linkage_ros.frame import STATUS_NEAR_SINGULAR, STATUS_OK, STATUS_UNASSEMBLABLE, Frame
from linkage_ros.motion import Motion

EPS = np.finfo(float).eps
#: Frame values against the solver's public API: the same formulas, so a few ulps at most.
TOL_REL = 16 * EPS
SHIPPED = ("harvester_finger", "four_bar", "slider_crank", "spherical_converter")
ROCKING = Path(__file__).parent / "data" / "rocking_four_bar.yaml"
#: The rocking four-bar's input can swing in |φ| ≤ arccos(0.0475/0.24) (see the scene file).
ROCKING_LIMIT = math.acos((0.25 - 0.45**2) / 0.24)


def frame_values(frame: Frame) -> np.ndarray:
    parts = [
        np.concatenate([p.position, p.velocity, p.acceleration]) for p in frame.points.values()
    ]
    parts.append(
        np.array([x for j in frame.joints.values() for x in (j.position, j.velocity, j.acceleration)])
    )
    return np.concatenate(parts)


def assert_matches_solver(frame: Frame, scene: solver.Scene) -> None:
    k = scene.everything().solve(frame.phi, omega=frame.omega, epsilon=frame.epsilon)
    for name in scene.point_names:
        for field in ("position", "velocity", "acceleration"):
            np.testing.assert_allclose(
                getattr(frame.points[name], field), getattr(k.point(name), field),
                rtol=TOL_REL, atol=TOL_REL, err_msg=f"{name}.{field}",
            )
    for name in scene.joint_names:
        for field in ("position", "velocity", "acceleration"):
            assert getattr(frame.joints[name], field) == pytest.approx(
                float(getattr(k.joint(name), field)), rel=TOL_REL, abs=TOL_REL
            ), f"{name}.{field}"


@pytest.mark.parametrize("name", SHIPPED)
def test_frame_values_equal_the_solver_values(name: str) -> None:
    scene = solver.load_scene(name)
    engine = Engine(scene, Motion(phi0=0.4, omega=2.5, epsilon=-0.7))
    for t in (0.0, 0.013, 1.7, 12.25):
        frame = engine.frame(t)
        phi, omega, eps = engine.motion.state(t)
        assert (frame.phi, frame.omega, frame.epsilon) == (phi, omega, eps)
        assert set(frame.points) == set(scene.point_names)
        assert set(frame.joints) == set(scene.joint_names)
        assert all(len(p.position) == scene.dim for p in frame.points.values())
        assert frame.status == STATUS_OK and frame.message == ""
        assert 0.0 < frame.conditioning <= 1.0
        assert_matches_solver(frame, scene)


@pytest.mark.parametrize("name", SHIPPED)
def test_vectorised_frames_equal_single_frames(name: str) -> None:
    times = np.arange(0, 600) / 100.0
    one = Engine(name, Motion(phi0=-0.2, omega=1.3, epsilon=0.05))
    many = Engine(name, Motion(phi0=-0.2, omega=1.3, epsilon=0.05))
    singles = [one.frame(t) for t in times]
    batch = list(many.frames(times))
    assert len(batch) == len(singles)
    for a, b in zip(singles, batch):
        assert (a.t, a.phi, a.omega, a.epsilon, a.status) == (b.t, b.phi, b.omega, b.epsilon, b.status)
        np.testing.assert_allclose(frame_values(a), frame_values(b), rtol=TOL_REL, atol=TOL_REL)


def test_published_points_default_to_the_outputs_and_paths_close_a_cycle() -> None:
    engine = Engine("harvester_finger", Motion(phi0=0.0, omega=1.0))
    assert engine.published_points == ("B", "C", "E")
    for p, path in engine.paths.items():
        assert path.shape[1] == 2 and path.shape[0] > 300
        np.testing.assert_allclose(path[0], path[-1], atol=1e-12)  # a full turn is closed
        assert np.isfinite(path).all(), p


def test_unknown_points_and_policies_are_refused_with_a_reason() -> None:
    with pytest.raises(solver.SceneError, match="unknown point.*Z"):
        Engine("four_bar", Motion(), points=["A", "Z"])
    with pytest.raises(ValueError, match="on_unassemblable must be one of stop, reverse"):
        Engine("four_bar", Motion(), on_unassemblable="explode")


def test_a_start_angle_that_cannot_be_assembled_is_refused() -> None:
    with pytest.raises(solver.AssemblyError, match="dyad"):
        Engine(ROCKING, Motion(phi0=math.pi))


def run(mode: str, *, epsilon: float = 0.0, seconds: float = 8.0) -> tuple[Engine, list[Frame]]:
    engine = Engine(ROCKING, Motion(phi0=0.0, omega=1.0, epsilon=epsilon), on_unassemblable=mode)
    return engine, [engine.frame(t) for t in np.arange(0.0, seconds, 0.01)]


def test_stop_holds_the_last_valid_state_without_nan() -> None:
    engine, frames = run("stop")
    values = np.array([frame_values(f) for f in frames])
    assert np.isfinite(values).all()
    held = [f for f in frames if f.status == STATUS_UNASSEMBLABLE]
    assert held, "the input must reach the boundary within the run"
    first = held[0]
    assert first.t == pytest.approx(math.floor(ROCKING_LIMIT / 0.01) * 0.01 + 0.01, abs=1e-9)
    # Held: the last valid angle, at rest.
    assert all(f.phi == held[0].phi and f.omega == 0.0 and f.epsilon == 0.0 for f in held)
    assert held[0].phi < ROCKING_LIMIT
    assert all(v == 0.0 for f in held for p in f.points.values() for v in p.velocity)
    assert "cannot be assembled for φ in (78.58" in first.message and "stopped" in first.message
    assert np.degrees(engine.motion.state(100.0)[0]) < 78.6


def test_a_new_omega_releases_a_held_input() -> None:
    engine, frames = run("stop", seconds=3.0)
    assert frames[-1].status == STATUS_UNASSEMBLABLE
    engine.motion.set_omega(3.0, -1.0)
    frame = engine.frame(3.5)
    assert frame.status == STATUS_OK
    assert frame.phi == pytest.approx(frames[-1].phi - 0.5, abs=1e-12)


@pytest.mark.parametrize("epsilon", [0.0, 0.2])
def test_reverse_swings_between_the_boundaries_without_nan(epsilon: float) -> None:
    engine, frames = run("reverse", epsilon=epsilon, seconds=10.0)
    values = np.array([frame_values(f) for f in frames])
    assert np.isfinite(values).all()
    phis = np.array([f.phi for f in frames])
    assert phis.max() < ROCKING_LIMIT and phis.min() > -ROCKING_LIMIT
    assert phis.max() > ROCKING_LIMIT - 0.05 and phis.min() < -ROCKING_LIMIT + 0.05
    events = [f for f in frames if f.status == STATUS_UNASSEMBLABLE]
    assert len(events) >= 3
    assert all("reversed at t =" in f.message for f in events)
    # Between events the frames are ordinary ones.
    assert {f.status for f in frames} <= {STATUS_OK, STATUS_NEAR_SINGULAR, STATUS_UNASSEMBLABLE}
    signs = np.sign([f.omega for f in frames])
    assert (np.diff(signs) != 0).sum() == len(events)


def test_reverse_happens_where_phi_crosses_the_boundary() -> None:
    engine, frames = run("reverse", seconds=2.0)
    reversal = next(s for s in engine.motion.segments if s.tag == "reverse")
    assert reversal.phi0 == pytest.approx(ROCKING_LIMIT, abs=1e-6)
    assert reversal.t0 == pytest.approx(ROCKING_LIMIT, abs=1e-6)  # ω = 1 rad/s from φ = 0


@pytest.mark.parametrize("mode", ["stop", "reverse"])
def test_vectorised_runs_handle_the_boundary_like_single_frames(mode: str) -> None:
    times = np.arange(0.0, 10.0, 0.01)
    _, singles = run(mode, seconds=10.0)
    engine = Engine(ROCKING, Motion(phi0=0.0, omega=1.0), on_unassemblable=mode)
    batch = list(engine.frames(times))
    assert [f.status for f in batch] == [f.status for f in singles]
    np.testing.assert_allclose([f.phi for f in batch], [f.phi for f in singles], atol=1e-12)
    assert np.isfinite(np.array([frame_values(f) for f in batch])).all()


def test_rocking_paths_cover_only_the_reachable_swing() -> None:
    engine = Engine(ROCKING, Motion(phi0=0.0, omega=1.0))
    path = engine.paths["A"]
    angles = np.arctan2(path[:, 1], path[:, 0])
    assert np.abs(angles).max() < ROCKING_LIMIT
    assert path.shape[0] == pytest.approx(2 * math.degrees(ROCKING_LIMIT), abs=2)
    # Consecutive samples are neighbours (the run is not split at φ0).
    steps = np.linalg.norm(np.diff(path, axis=0), axis=1)
    assert steps.max() < 0.3 * math.radians(1.0) * 1.01
