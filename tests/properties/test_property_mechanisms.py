"""Property-based checks over random assemblable four-bars, slider-cranks and slotted links.

Bounded, finite dimensions; moderate example counts (the whole file runs in a few seconds).
Derivatives are checked against 5-point central differences: of the positions for the velocity
analogs (truncation ~h⁴, rounding ~EPS/h) and of the exact velocity analogs for the
acceleration analogs — both far below the 1e-8 relative tolerance at h = 1e-3 when the sweep
stays away from singular positions (conditioning ≥ 0.05, enforced by construction/assume).
"""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scene_builders import four_bar, slider_crank, slotted

import solver

#: loop closure relative to the mechanism's scale.
CLOSURE_TOL = 1e-12
#: analogs against central differences, relative to the analog's largest magnitude.
ANALOG_TOL = 1e-8
#: the same positions from another sweep (direction, start, length): rounding only.
SWEEP_TOL = 1e-14
#: conditioning that keeps a sweep away from singular positions.
REGULAR = 0.05
STEP = 1e-3

SETTINGS = settings(max_examples=50, deadline=None, suppress_health_check=[HealthCheck.too_slow])
PHI = np.linspace(0.0, 2 * math.pi, 61)

scale = st.floats(1e-3, 1e2)
unit = st.floats(0.0, 1.0)
mode = st.sampled_from([1, -1])


@st.composite
def crank_rockers(draw: st.DrawFn) -> tuple[solver.Scene, float, int]:
    """Grashof four-bars with the crank shortest and a margin: the crank turns fully."""
    s = draw(scale)
    crank = 1.0
    others = [draw(st.floats(1.3, 4.0)) for _ in range(3)]  # coupler, rocker, ground
    longest = max(others)
    assume(crank + longest < sum(others) - longest - 0.2)
    m = draw(mode)
    return four_bar(crank * s, others[0] * s, others[1] * s, others[2] * s, mode=m), s, m


def _deriv(f, phi: np.ndarray, *, wrap: bool = False) -> np.ndarray:  # type: ignore[no-untyped-def]
    """5-point central difference of f at phi (of an angle: of its change, taken in (−π, π])."""
    f0 = f(phi)

    def rel(x: np.ndarray) -> np.ndarray:
        d = x - f0
        return (d + math.pi) % (2 * math.pi) - math.pi if wrap else d

    return (rel(f(phi - 2 * STEP)) - 8 * rel(f(phi - STEP)) + 8 * rel(f(phi + STEP)) - rel(f(phi + 2 * STEP))) / (
        12 * STEP
    )


def _check_analogs(scene: solver.Scene, name: str, is_point: bool, *, angle: bool = False) -> None:
    def get(phi: np.ndarray, attr: str) -> np.ndarray:
        k = scene.solve(phi)
        m = k.point(name) if is_point else k.joint(name)
        return getattr(m, attr)

    pos_fd = _deriv(lambda p: get(p, "position"), PHI, wrap=angle)
    vel = get(PHI, "velocity")
    acc_fd = _deriv(lambda p: get(p, "velocity"), PHI)
    acc = get(PHI, "acceleration")
    # φ is dimensionless: both analogs share the quantity's unit, and one scale
    size = max(np.abs(vel).max(), np.abs(acc).max())
    assert np.abs(vel - pos_fd).max() <= ANALOG_TOL * size
    assert np.abs(acc - acc_fd).max() <= ANALOG_TOL * size


def _sweep_independence(scene: solver.Scene, name: str, length_scale: float) -> None:
    phi = np.linspace(-math.pi, 3 * math.pi, 203)
    ref = scene.solve(phi).point(name)
    tol = SWEEP_TOL * length_scale
    back = scene.solve(phi[::-1]).point(name)
    rolled = scene.solve(np.roll(phi, 57)).point(name)
    for attr in ("position", "velocity", "acceleration"):
        r = getattr(ref, attr)
        bound = tol * max(1.0, np.abs(r).max() / length_scale)
        assert np.abs(getattr(back, attr)[::-1] - r).max() <= bound
        assert np.abs(np.roll(getattr(rolled, attr), -57, axis=0) - r).max() <= bound
    for n in (1, 2, 17):  # shorter arrays, element by element the same
        part = scene.solve(phi[:n]).point(name)
        assert np.abs(part.position - ref.position[:n]).max() <= tol
    single = scene.solve(float(phi[100])).point(name)
    assert np.abs(single.position - ref.position[100]).max() <= tol


@SETTINGS
@given(crank_rockers())
def test_four_bar_closes_its_loop_and_keeps_its_assembly_mode(case: tuple[solver.Scene, float, int]) -> None:
    scene, s, m = case
    k = scene.solve(PHI)
    a, b = k.point("A").position, k.point("B").position
    ground = scene.fixed_points["C"]
    coupler, rocker = scene._data.groups[1].lengths  # type: ignore[attr-defined]
    assert np.abs(np.hypot(*(b - a).T) - coupler).max() <= CLOSURE_TOL * s
    assert np.abs(np.hypot(*(b - ground).T) - rocker).max() <= CLOSURE_TOL * s
    # seed 003: M = sign of the signed area of A, B, C, at every sample of the sweep
    area = (b - a)[:, 0] * (ground - a)[:, 1] - (b - a)[:, 1] * (ground - a)[:, 0]
    assert np.all(np.sign(area) == m)


@SETTINGS
@given(crank_rockers())
def test_four_bar_analogs_match_central_differences(case: tuple[solver.Scene, float, int]) -> None:
    scene, _, _ = case
    assume(scene.solve(PHI).min_conditioning.min() > REGULAR)
    _check_analogs(scene, "B", True)
    _check_analogs(scene, "rocker", False, angle=True)


@SETTINGS
@given(crank_rockers())
def test_four_bar_results_do_not_depend_on_the_sweep(case: tuple[solver.Scene, float, int]) -> None:
    scene, s, _ = case
    _sweep_independence(scene, "B", s)


@st.composite
def slider_cranks(draw: st.DrawFn) -> tuple[solver.Scene, float, int, float]:
    s = draw(scale)
    offset = draw(st.floats(-0.8, 0.8))
    rod = draw(st.floats(1.4, 5.0)) + abs(offset)  # always assemblable, away from the toggle
    m = draw(mode)
    angle = draw(st.floats(-math.pi, math.pi))
    return slider_crank(s, rod * s, offset * s, mode=m, angle=angle), s, m, angle


@SETTINGS
@given(slider_cranks())
def test_slider_crank_closes_and_keeps_its_mode(case: tuple[solver.Scene, float, int, float]) -> None:
    scene, s, m, angle = case
    k = scene.solve(PHI)
    a, b = k.point("A").position, k.point("B").position
    rod = scene._data.groups[1].length  # type: ignore[attr-defined]
    e = np.array([math.cos(angle), math.sin(angle)])
    offset = scene._data.groups[1].origin  # type: ignore[attr-defined]
    assert np.abs(np.hypot(*(b - a).T) - rod).max() <= CLOSURE_TOL * s
    rel = b - [offset.real, offset.imag]
    assert np.abs(rel[:, 0] * e[1] - rel[:, 1] * e[0]).max() <= CLOSURE_TOL * s  # on the guide
    assert np.all(np.sign((b - a) @ e) == m)


@SETTINGS
@given(slider_cranks())
def test_slider_crank_analogs_match_central_differences(case: tuple[solver.Scene, float, int, float]) -> None:
    scene, s, _, _ = case
    _check_analogs(scene, "B", True)
    _check_analogs(scene, "slide", False)
    _sweep_independence(scene, "B", s)


@st.composite
def slotted_links(draw: st.DrawFn) -> tuple[solver.Scene, float]:
    s = draw(scale)
    inside = draw(st.booleans())
    distance = draw(st.floats(0.0, 0.7)) if inside else draw(st.floats(1.3, 4.0))
    bearing = draw(st.floats(-math.pi, math.pi))
    tip = draw(st.floats(0.2, 5.0)) * draw(st.sampled_from([1.0, -1.0]))
    pivot = (distance * s * math.cos(bearing), distance * s * math.sin(bearing))
    return slotted(s, pivot, tip * s), s


@SETTINGS
@given(slotted_links())
def test_slotted_link_passes_through_its_eyelet(case: tuple[solver.Scene, float]) -> None:
    scene, s = case
    k = scene.solve(PHI)
    p = scene.fixed_points["P"]
    b, c = k.point("B").position - p, k.point("C").position - p
    tip = abs(scene._data.groups[1].points[0][1])  # type: ignore[attr-defined]
    assert np.abs(np.hypot(*c.T) - tip).max() <= CLOSURE_TOL * max(s, tip)
    cross = (b[:, 0] * c[:, 1] - b[:, 1] * c[:, 0]) / (np.hypot(*b.T) * tip)
    assert np.abs(cross).max() <= CLOSURE_TOL * 10


@SETTINGS
@given(slotted_links())
def test_slotted_link_analogs_match_central_differences(case: tuple[solver.Scene, float]) -> None:
    scene, s = case
    assume(scene.solve(PHI).min_conditioning.min() > REGULAR)
    _check_analogs(scene, "C", True)
    _check_analogs(scene, "finger", False, angle=True)
    _sweep_independence(scene, "C", s)


@SETTINGS
@given(scale, st.floats(0.05, 0.9), st.floats(-math.pi, math.pi))
def test_random_parallelograms_stay_parallel_through_their_change_points(s: float, ratio: float, start: float) -> None:
    # crank r = ratio·g, coupler = ground g: change points at φ = 0 and π, both among the samples
    g, r = s, ratio * s
    scene = four_bar(r, g, r, g, mode=-1, through="continuous")
    phi = start + np.linspace(0.0, 4 * math.pi, 81)
    phi = np.concatenate([phi, [0.0, math.pi, -math.pi]])
    k = scene.solve(phi)
    a, b = k.point("A"), k.point("B")
    # parallel to 1e-9 of the scale (the figure): within ~1e-6 rad of a change point the
    # rounding of A alone moves B by up to sqrt(EPS·r·g) (a toggle's square-root sensitivity)
    assert np.abs(b.position - a.position - [g, 0.0]).max() <= 1e-9 * s
    assert np.abs(b.velocity - a.velocity).max() <= 1e-9 * s
    assert np.abs(b.acceleration - a.acceleration).max() <= 1e-9 * s
    assert k.singular[-3:].all()
    backward = scene.solve(phi[::-1]).point("B")
    assert np.abs(backward.velocity[::-1] - b.velocity).max() <= 1e-15 * s
