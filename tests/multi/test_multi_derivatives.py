"""Jacobians and Hessians in several inputs, checked two ways, and the API's shapes and paths.

* against 5-point central differences of the positions (jacobian) and of the exact jacobian
  (hessian), step STEP: truncation ~STEP⁴, rounding ~EPS/STEP — far below FD_TOL relative to the
  largest entry, on samples conditioned at least 0.05;
* against the differentiated loop constraint |P − A_i|² = l²:
  (P − A)·(∂P − ∂A) = 0 and (P − A)·(∂²P − ∂²A) + (∂_iP − ∂_iA)·(∂_jP − ∂_jA) = 0.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from multi_builders import five_bar

import solver

STEP = 1e-4
FD_TOL = 1e-8
CONSTRAINT_TOL = 1e-13
"""Residual of the differentiated constraint, relative to l² (exact algebra: rounding only)."""
TICK_TOL = 4e-15
"""Per tick (math) against vectorised (numpy), relative to the value's size (at least 1):
libm's and numpy's cos/sin may differ by an ulp."""

DEG = math.pi / 180
Q = np.array([[a, b] for a in np.arange(45, 140, 15) * DEG for b in np.arange(42, 140, 13) * DEG])
OMEGA = np.array([2.0, -1.5])
EPSILON = np.array([0.7, 3.0])


def _dot(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    return (u * v).sum(axis=-1)


@pytest.fixture(scope="module")
def scene() -> solver.Scene:
    return five_bar(points=("P", "A1", "A2"))


def test_jacobian_and_hessian_agree_with_central_differences(scene: solver.Scene) -> None:
    k = scene.solve(Q)
    regular = k.min_conditioning >= 0.05
    assert regular.sum() > 0.8 * len(Q)
    jac, hess = k.point("P").jacobian, k.point("P").hessian
    for i in range(2):
        dq = np.zeros(2)
        dq[i] = STEP

        def at(shift: float, dq: np.ndarray = dq) -> solver.Kinematics:
            return scene.solve(Q + shift * dq)

        fd_j = (at(-2).point("P").position - 8 * at(-1).point("P").position + 8 * at(1).point("P").position
                - at(2).point("P").position) / (12 * STEP)
        fd_h = (at(-2).point("P").jacobian - 8 * at(-1).point("P").jacobian + 8 * at(1).point("P").jacobian
                - at(2).point("P").jacobian) / (12 * STEP)
        scale_j = np.abs(jac[regular]).max()
        scale_h = np.abs(hess[regular]).max()
        assert np.abs(fd_j - jac[..., i])[regular].max() <= FD_TOL * scale_j
        assert np.abs(fd_h - hess[..., i])[regular].max() <= FD_TOL * scale_h


def test_derivatives_satisfy_the_differentiated_loop_constraint(scene: solver.Scene) -> None:
    k = scene.solve(Q)
    p = k.point("P")
    for a in ("A1", "A2"):
        end = k.point(a)
        r = p.position - end.position
        dj = p.jacobian - end.jacobian  # (N, 2, k)
        dh = p.hessian - end.hessian  # (N, 2, k, k)
        first = np.einsum("nd,ndi->ni", r, dj)
        second = np.einsum("nd,ndij->nij", r, dh) + np.einsum("ndi,ndj->nij", dj, dj)
        assert np.abs(first).max() <= CONSTRAINT_TOL * 0.25**2 * 10
        scale = np.abs(np.einsum("ndi,ndj->nij", dj, dj)).max(axis=(1, 2))
        assert (np.abs(second).max(axis=(1, 2)) <= CONSTRAINT_TOL * 1e2 * np.maximum(scale, 0.25**2)).all()


def test_real_motion_is_jacobian_times_omega_plus_hessian_form(scene: solver.Scene) -> None:
    k = scene.solve(Q, omega=OMEGA, epsilon=EPSILON)
    p = k.point("P")
    v = np.einsum("ndi,i->nd", p.jacobian, OMEGA)
    a = np.einsum("ndi,i->nd", p.jacobian, EPSILON) + np.einsum("ndij,i,j->nd", p.hessian, OMEGA, OMEGA)
    np.testing.assert_allclose(p.velocity, v, rtol=1e-13, atol=1e-15)
    np.testing.assert_allclose(p.acceleration, a, rtol=1e-13, atol=1e-14)


def test_per_sample_rates_give_each_row_its_own_motion(scene: solver.Scene) -> None:
    rng = np.random.default_rng(14)
    w, e = rng.uniform(-3, 3, Q.shape), rng.uniform(-3, 3, Q.shape)
    k = scene.solve(Q, omega=w, epsilon=e)
    for i in (0, 7, len(Q) - 1):
        one = scene.solve(Q[i : i + 1], omega=w[i], epsilon=e[i])
        # the same arithmetic with per-row arrays or broadcast floats (numpy's loops: an ulp or two)
        np.testing.assert_allclose(k.point("P").velocity[i], one.point("P").velocity[0], rtol=1e-14, atol=1e-16)
        np.testing.assert_allclose(k.point("P").acceleration[i], one.point("P").acceleration[0], rtol=1e-14, atol=1e-15)
    assert k.omega.shape == k.epsilon.shape == Q.shape


def test_shapes_of_every_output_form() -> None:
    scene = solver.load_scene("five_bar")
    k = scene.solve(Q[:5], omega=OMEGA, epsilon=EPSILON)
    p, j = k.point("P"), k.joint("left_distal")
    assert p.position.shape == p.velocity.shape == p.acceleration.shape == (5, 2)
    assert p.jacobian.shape == (5, 2, 2) and p.hessian.shape == (5, 2, 2, 2)
    assert j.position.shape == (5,) and j.jacobian.shape == (5, 2) and j.hessian.shape == (5, 2, 2)
    assert k.phi.shape == (5, 2) and k.valid.shape == k.singular.shape == (5,)
    assert k.conditioning["distal"].shape == (5,)
    one = scene.solve(Q[0], omega=OMEGA, epsilon=EPSILON)
    assert one.point("P").position.shape == (2,) and one.point("P").jacobian.shape == (2, 2)
    assert one.point("P").hessian.shape == (2, 2, 2) and one.joint("q2").hessian.shape == (2, 2)
    assert isinstance(one.conditioning["distal"], float)


def test_hessians_are_symmetric_and_input_joints_are_the_identity() -> None:
    k = solver.load_scene("five_bar").solve(Q)
    h = k.point("P").hessian
    np.testing.assert_array_equal(h, np.swapaxes(h, -1, -2))
    np.testing.assert_array_equal(k.joint("q1").jacobian, np.broadcast_to([1.0, 0.0], (len(Q), 2)))
    np.testing.assert_array_equal(k.joint("q2").jacobian, np.broadcast_to([0.0, 1.0], (len(Q), 2)))
    assert not k.joint("q1").hessian.any()
    np.testing.assert_array_equal(k.joint("q1").position, Q[:, 0])


def test_per_tick_path_equals_the_vectorised_path() -> None:
    scene = solver.load_scene("five_bar")
    sweep = scene.solve(Q, omega=OMEGA, epsilon=EPSILON)
    for i in range(0, len(Q), 5):
        tick = scene.solve((float(Q[i, 0]), float(Q[i, 1])), omega=(2.0, -1.5), epsilon=(0.7, 3.0))
        for name in ("P",):
            a, b = tick.point(name), sweep.point(name)
            for attr in ("position", "velocity", "acceleration", "jacobian", "hessian"):
                want = getattr(b, attr)[i]
                np.testing.assert_allclose(getattr(a, attr), want, rtol=0, atol=TICK_TOL * max(1.0, np.abs(want).max()))
            (x, y), (vx, vy), (ax, ay) = tick.floats(name)
            assert all(type(f) is float for f in (x, y, vx, vy, ax, ay))
        for name in scene.output_joints:
            np.testing.assert_allclose(tick.joint(name).position, sweep.joint(name).position[i], rtol=0, atol=TICK_TOL)
            np.testing.assert_allclose(tick.joint(name).acceleration, sweep.joint(name).acceleration[i],
                                       rtol=TICK_TOL, atol=TICK_TOL)


@pytest.mark.parametrize("name", ["four_bar", "slider_crank", "harvester_finger", "spherical_converter"])
def test_single_input_jacobian_and_hessian_are_the_analogs_reshaped(name: str) -> None:
    scene = solver.load_scene(name)
    phi = np.linspace(0.1, 6.0, 25)
    analogs = scene.solve(phi)
    moving = scene.solve(phi, omega=2.5, epsilon=-0.7)
    assert scene.inputs == (scene.input_joint,)
    for p in scene.output_points:
        m = moving.point(p)
        assert m.jacobian.shape == (*m.position.shape, 1) and m.hessian.shape == (*m.position.shape, 1, 1)
        np.testing.assert_array_equal(m.jacobian[..., 0], analogs.point(p).velocity)
        np.testing.assert_array_equal(m.hessian[..., 0, 0], analogs.point(p).acceleration)
    for j in scene.output_joints:
        np.testing.assert_array_equal(moving.joint(j).jacobian[:, 0], analogs.joint(j).velocity)
        np.testing.assert_array_equal(moving.joint(j).hessian[:, 0, 0], analogs.joint(j).acceleration)
    tick = scene.solve(0.7, omega=2.0, epsilon=0.3)
    ref = scene.solve(0.7)
    for p in scene.output_points:  # one instant: k.derivatives (its InstantMotion holds floats only)
        jacobian, hessian = tick.derivatives(p)
        np.testing.assert_array_equal(jacobian[..., 0], ref.point(p).velocity)
        np.testing.assert_array_equal(hessian[..., 0, 0], ref.point(p).acceleration)


def test_bad_shapes_of_phi_and_rates_are_named() -> None:
    scene = solver.load_scene("five_bar")
    with pytest.raises(solver.SolverError, match=r"five_bar has 2 inputs \(q1, q2\): phi must have shape \(N, 2\)"):
        scene.solve(np.zeros(5))
    with pytest.raises(solver.SolverError, match=r"omega of shape \(3,\) must be a scalar, \(2,\) or \(4, 2\)"):
        scene.solve(Q[:4], omega=[1.0, 2.0, 3.0])
    with pytest.raises(solver.SolverError, match=r"phi must be finite"):
        scene.solve([0.5, math.nan])
    with pytest.raises(solver.SolverError, match=r"epsilon must be finite"):
        scene.solve(Q[:2], epsilon=[0.0, math.inf])


def test_jacobian_and_hessian_are_evaluated_on_first_access_only(monkeypatch: pytest.MonkeyPatch) -> None:
    import solver.multi as multi

    calls: list[int] = []
    real = multi._sweep_derivatives

    def counting(scene: solver.Scene, phi: np.ndarray) -> object:
        calls.append(len(phi))
        return real(scene, phi)

    monkeypatch.setattr(multi, "_sweep_derivatives", counting)
    k = solver.load_scene("five_bar").solve(Q, omega=OMEGA, epsilon=EPSILON)
    k.point("P").velocity, k.joint("left_distal").acceleration
    assert calls == []
    k.point("P").jacobian, k.joint("left_distal").hessian, k.point("P").hessian
    assert calls == [len(Q)]
