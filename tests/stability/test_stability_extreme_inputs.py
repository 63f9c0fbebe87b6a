"""Extreme inputs: scale, near-toggle dimensions, any φ, tiny arrays, any ω and ε, spherical α."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest
from scene_builders import build, four_bar, slider_crank

import solver
from solver.tolerances import EPS

#: results of a scaled mechanism, divided by the scale, against the unscaled ones.
SCALE_TOL = 64 * EPS
#: φ and φ + 2πk are the same position up to the rounding of φ itself (|φ|·EPS).
PERIOD_TOL = 1e-12
PHI = np.linspace(0.0, 2 * math.pi, 97)


@pytest.mark.parametrize("scale", [1e-6, 1e-3, 1.0, 1e3])
def test_link_lengths_from_micrometres_to_kilometres_keep_relative_accuracy(scale: float) -> None:
    ref = four_bar(0.1, 0.4, 0.3, 0.4).solve(PHI)
    k = four_bar(0.1 * scale, 0.4 * scale, 0.3 * scale, 0.4 * scale).solve(PHI)
    for attr in ("position", "velocity", "acceleration"):
        got = getattr(k.point("B"), attr) / scale
        want = getattr(ref.point("B"), attr)
        assert np.abs(got - want).max() <= SCALE_TOL * np.abs(want).max()
    np.testing.assert_allclose(k.joint("rocker").velocity, ref.joint("rocker").velocity, rtol=SCALE_TOL, atol=SCALE_TOL)


def test_mixed_scales_in_one_mechanism_close_the_loop() -> None:
    # a 1 µm crank against 1 km links: the coupler hardly moves, but the loop closes to rounding
    scene = four_bar(1e-6, 1e3, 1e3, 1e3)
    k = scene.solve(PHI)
    a, b = k.point("A").position, k.point("B").position
    assert np.abs(np.hypot(*(b - a).T) - 1e3).max() <= 4 * EPS * 1e3
    assert np.abs(np.hypot(*(b - [1e3, 0.0]).T) - 1e3).max() <= 4 * EPS * 1e3
    assert np.all(np.isfinite(k.point("B").acceleration))


@pytest.mark.parametrize("delta", [1e-9, -1e-9])
def test_near_toggle_dimensions_within_1e9_of_the_toggle(delta: float) -> None:
    # AB + CB = 0.5 + delta, the largest |C − A| is 0.5 (at φ = π)
    scene = four_bar(0.1, 0.25, 0.25 + delta, 0.4)
    phi = np.linspace(0, 2 * math.pi, 3601)
    if delta > 0:
        k = scene.solve(phi)
        a, b = k.point("A").position, k.point("B").position
        assert np.abs(np.hypot(*(b - a).T) - 0.25).max() < 1e-14
        assert np.all(np.isfinite(k.point("B").velocity))
        assert k.min_conditioning.min() > 0.0
    else:
        with pytest.raises(solver.AssemblyError, match=r"group 'dyad' cannot be assembled for φ in \(179\.99"):
            scene.solve(phi)
        k = scene.solve(phi, mask=True)
        assert (~k.valid).sum() == 1  # only φ = π of the samples falls in the 3e-4 rad wide gap


def test_phi_outside_one_turn_and_negative_gives_the_same_positions() -> None:
    scene = solver.load_scene("four_bar")
    ref = scene.solve(PHI)
    for turns in (-7, -1, 1, 50):
        k = scene.solve(PHI + 2 * math.pi * turns)
        tol = PERIOD_TOL * max(1.0, abs(turns))
        for p in ("A", "B"):
            for attr in ("position", "velocity", "acceleration"):
                assert np.abs(getattr(k.point(p), attr) - getattr(ref.point(p), attr)).max() < tol
        # the input joint is φ itself, unwrapped
        assert np.array_equal(k.joint("rocker").position.shape, PHI.shape)


@pytest.mark.parametrize(
    "name", ["four_bar", "slider_crank", "harvester_finger", "spherical_converter", "hard/parallelogram"]
)
def test_arrays_of_length_zero_and_one(name: str) -> None:
    scene = solver.load_scene(name)
    empty = scene.solve(np.array([]))
    one = scene.solve(np.array([0.3]))
    scalar = scene.solve(0.3)
    for p in scene.output_points:
        assert empty.point(p).position.shape == (0, scene.dim)
        assert one.point(p).velocity.shape == (1, scene.dim)
        np.testing.assert_allclose(one.point(p).acceleration[0], scalar.point(p).acceleration, rtol=1e-14, atol=1e-16)
    for j in scene.output_joints:
        assert empty.joint(j).velocity.shape == (0,)
        assert one.joint(j).position.shape == (1,)
    assert empty.singular.shape == (0,) and empty.valid.shape == (0,)


def test_empty_sweep_of_an_unassemblable_scene_does_not_raise() -> None:
    k = solver.load_scene("hard/double_rocker").solve(np.array([]), mask=False)
    assert k.point("B").position.shape == (0, 2)


def test_zero_negative_omega_and_large_epsilon_follow_seed_000_eq_11_12() -> None:
    scene = slider_crank(0.05, 0.2, 0.01)
    analog = scene.solve(PHI)
    vq, aq = analog.joint("slide").velocity, analog.joint("slide").acceleration
    for omega, epsilon in ((0.0, 0.0), (0.0, 5.0), (-3.0, 0.0), (-3.0, 1e9), (1e4, -1e12)):
        m = scene.solve(PHI, omega=omega, epsilon=epsilon).joint("slide")
        np.testing.assert_array_equal(m.position, analog.joint("slide").position)
        np.testing.assert_allclose(m.velocity, vq * omega, rtol=4 * EPS, atol=0)
        want = aq * omega**2 + vq * epsilon
        assert np.abs(m.acceleration - want).max() <= 8 * EPS * np.abs(want).max() + 0.0


def test_non_finite_inputs_are_refused_with_a_message() -> None:
    scene = solver.load_scene("four_bar")
    with pytest.raises(solver.SolverError, match=r"phi must be finite"):
        scene.solve(np.array([0.0, np.nan]))
    with pytest.raises(solver.SolverError, match=r"omega must be finite"):
        scene.solve(0.0, omega=math.inf)


def _spherical(alpha_deg: float) -> solver.Scene:
    return build({
        "scene": "spherical_test",
        "units": {"length": "m", "angle": "deg"},
        "fixed": {"O": [0.0, 0.0, 0.0]},
        "groups": [{"type": "spherical_crank_slider", "name": "converter", "center": "O", "point": "K",
                    "shaft": "shaft", "cage": "cage", "alpha": alpha_deg, "radius": 0.05}],
        "outputs": {"points": ["K"], "joints": ["cage"]},
    })


@pytest.mark.parametrize("alpha_deg", [1e-6, 1e-3, 1.0, 89.0, 90.0 - 1e-6])
def test_spherical_scene_near_zero_and_ninety_degrees(alpha_deg: float) -> None:
    scene = _spherical(alpha_deg)
    k = scene.solve(np.linspace(0, 2 * math.pi, 721))
    cage = k.joint("cage")
    assert all(np.all(np.isfinite(x)) for x in cage)
    # max ω_cage = ω / tan α, at φ = 0 (seed 001); exact to rounding even where it is 5.7e7
    t = mpmath.tan(mpmath.radians(mpmath.mpf(alpha_deg)))
    assert cage.velocity.max() == pytest.approx(float(1 / t), rel=1e-12)
    assert np.abs(cage.position).max() <= math.pi / 2 - math.radians(alpha_deg) + 1e-12


@pytest.mark.parametrize("alpha_deg", [0.0, 90.0, -5.0, 120.0])
def test_spherical_alpha_at_zero_or_ninety_degrees_is_rejected_with_the_reason(alpha_deg: float) -> None:
    with pytest.raises(
        solver.SceneError,
        match=r"groups\[0\]\.alpha: alpha must lie strictly between 0° and 90°.*at 0° the groove plane holds the "
        r"shaft axis.*at 90° the ring is square to the shaft and the cage does not move",
    ):
        _spherical(alpha_deg)
