"""The slider triad's kinetostatics (route 2, solver.forces.slider_triad) and dynamics against
independent checks, on tests/forces/scenes/slider_triad_press_loaded.yaml (the shipped
slider_triad_press with masses on every body, gravity, a force on the ram, a torque on a binary
link):

* the 50-digit Newton–Euler reference (tests/reference/forces_mp.py: the slider triad's loop
  solved by findroot and continued from the drawn pose, every body's equations as one linear
  system), stored in tests/data/slider_triad/ (its random instants solved inside one sorted sweep
  from ``at``, as the reference continues them — the RRR triad's arrangement);
* route 1 (virtual power, no reaction) at random (ω, ε), vectorised and per instant;
* each of the five bodies (crank, two binary links, the ternary link, the ram's block) in
  equilibrium with the pin reactions and the guide's normal force and couple the solver gives;
* M(φ)·ε + h(φ, ω) is the kinetostatic effort; a free run keeps its energy balance and its loop
  closed.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from test_forces_reference import _check, _expected, _reference_module, _scales

import solver
from solver._backend import NUMPY
from solver.forces.frames import body_motion
from solver.forces.spec import PointForce, Torque
from solver.forces.virtual import virtual_efforts
from solver.groups import Context
from solver.tolerances import EPS

SCENE = Path(__file__).resolve().parent / "scenes" / "slider_triad_press_loaded.yaml"
REFERENCE = Path(__file__).resolve().parents[1] / "data" / "slider_triad" / "forces_slider_triad_press_loaded.json"
#: the sweep that carries the reference's instants: at most this far apart (rad)
SWEEP_STEP = 0.01
#: route 1 against route 2, relative to the largest effort of the sweep
ROUTES_AGREE = 1e-12
#: a body's equilibrium with the solver's reactions, relative to the largest force (torque) there
BALANCED = 1e-12
#: agreement of two evaluations of the same exact quantity, relative to the efforts' size
REL = 256 * EPS
#: loop closure of the binary links along a free run (lengths about 0.5 m)
CLOSURE = 64 * EPS


def _reference() -> tuple[solver.Scene, dict]:
    ref = json.loads(REFERENCE.read_text())
    assert _reference_module().digest(SCENE) == ref["scene_mechanics_sha256"], (
        f"{SCENE.name}'s mechanics changed: python tests/reference/forces_mp.py {SCENE} --out tests/data/slider_triad")
    return solver.load_scene(SCENE), ref


def _sweep(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A sorted sweep from ``at`` = 0 over every q, with the q among its samples: (φ, where q sits)."""
    lo, hi = min(q.min(), 0.0), max(q.max(), 0.0)
    phi = np.unique(np.concatenate([np.linspace(lo, hi, int((hi - lo) / SWEEP_STEP) + 2), q, [0.0]]))
    return phi, np.searchsorted(phi, q)


class _At:
    """The result of a sweep read at the reference's instants only."""

    def __init__(self, k: Any, where: np.ndarray) -> None:
        self.k, self.where = k, where

    def effort(self, joint: str) -> np.ndarray:
        return np.asarray(self.k.effort(joint))[self.where]

    def reaction(self, point: str, *, on: str, by: str | None = None) -> np.ndarray:
        return np.asarray(self.k.reaction(point, on=on, by=by))[self.where]

    def slide_reaction(self, block: str) -> Any:
        r = self.k.slide_reaction(block)

        class _Pair:
            force = np.asarray(r.force)[self.where]
            couple = np.asarray(r.couple)[self.where]
        return _Pair()


def test_slider_triad_forces_match_the_newton_euler_reference() -> None:
    """Vectorised along the sweep, then tick by tick along it from at = 0 outward."""
    scene, ref = _reference()
    q = np.array([float(r["q"][0]) for r in ref["samples"]])
    phi, where = _sweep(q)
    omega, epsilon = np.zeros_like(phi), np.zeros_like(phi)
    omega[where] = [float(r["omega"][0]) for r in ref["samples"]]
    epsilon[where] = [float(r["epsilon"][0]) for r in ref["samples"]]
    expected = _expected(ref)
    assert ("slide force", "block") in expected and ("reaction", "D", "plate") in expected
    scales = _scales(ref, expected)
    k = scene.solve(phi, omega=omega, epsilon=epsilon)
    _check(scene, _At(k, where), expected, scales, slice(None), "slider_triad_press_loaded (vectorised)")
    sample = {int(w): n for n, w in enumerate(where)}
    order = np.argsort(np.abs(phi), kind="stable")
    for path in ([i for i in order if phi[i] >= 0.0], [i for i in order if phi[i] < 0.0]):
        tick = solver.load_scene(SCENE)
        for i in path:
            ki = tick.solve(float(phi[i]), omega=float(omega[i]), epsilon=float(epsilon[i]))
            n = sample.get(int(i))
            if n is not None:
                _check(tick, ki, expected, scales, n, f"slider_triad_press_loaded (one instant, sample {n})")


@pytest.mark.parametrize("seed", range(3))
def test_route_one_and_route_two_agree_through_a_slider_triad(seed: int) -> None:
    scene = solver.load_scene(SCENE)
    rng = np.random.default_rng(seed)
    phi = np.linspace(-1.0, 7.5, 600)
    omega, epsilon = rng.uniform(-6.0, 6.0), rng.uniform(-20.0, 20.0)
    route2 = scene.solve(phi, omega=omega, epsilon=epsilon).effort("crank")
    route1 = virtual_efforts(scene, phi, omega=omega, epsilon=epsilon)["crank"]
    assert np.abs(route2 - route1).max() <= ROUTES_AGREE * np.abs(route2).max()
    # per instant, ticking along the sweep from at = 0 (the per-tick path follows the mode)
    tick = solver.load_scene(SCENE)
    for i in np.flatnonzero(phi >= 0.0)[::25]:
        k = tick.solve(float(phi[i]), omega=omega, epsilon=epsilon)
        assert abs(float(k.effort("crank")) - route2[i]) <= ROUTES_AGREE * np.abs(route2).max()


def test_each_body_of_the_slider_triad_is_in_equilibrium_with_its_reactions() -> None:
    """Every body's d'Alembert loads, applied loads, pin reactions and (for the block) the guide's
    normal force and couple sum to zero force and zero moment."""
    scene = solver.load_scene(SCENE)
    phi = np.linspace(0.0, 2.0 * np.pi, 37)
    omega, epsilon = 2.5, -4.0
    k = scene.solve(phi, omega=omega, epsilon=epsilon)
    spec = scene.forces.spec  # type: ignore[union-attr]
    ctx = Context(phi=phi, xp=NUMPY, mask=True, owner=scene, seeds=None)
    jets = scene.plan.run(ctx).values
    g = spec.gravity
    names = {b.name for b in spec.bodies}
    assert {"arm_b", "arm_c", "plate", "block"} <= names
    for body in ("arm_b", "arm_c", "plate", "block"):
        b = next(x for x in spec.bodies if x.name == body)
        origin = jets[b.frame[0]].value
        force = np.zeros(len(phi), complex)
        moment = np.zeros(len(phi))
        for p in scene.pins:
            if body not in (p.body, p.other):
                continue
            r = np.asarray(k.reaction(p.point, on=body, by=p.other if p.body == body else p.body))
            f = r[..., 0] + 1j * r[..., 1]
            force += f
            moment += np.imag(np.conj(jets[p.point].value - origin) * f)
        if body == "block":
            sr = k.slide_reaction("block")
            normal = np.asarray(sr.force)
            n = normal[..., 0] + 1j * normal[..., 1]
            assert np.abs(n.real).max() > 1.0  # the vertical guide pushes sideways
            assert np.abs(n.imag).max() <= 1e-12 * np.abs(n).max()  # normal to the guide
            force += n
            moment += sr.couple
        m = body_motion(b, jets, NUMPY)
        a_g = m.center.d2 * omega**2 + m.center.d1 * epsilon
        alpha = m.theta2 * omega**2 + m.theta1 * epsilon
        inertial = b.mass * (g - a_g)
        force += inertial
        moment += np.imag(np.conj(m.center.value - origin) * inertial) - b.inertia * alpha
        for ld in spec.loads:
            if isinstance(ld, PointForce) and ld.body == body:
                force += ld.force
                moment += np.imag(np.conj(jets[ld.point].value - origin) * ld.force)
            elif isinstance(ld, Torque) and ld.body == body:
                moment += ld.torque
        scale = max(np.abs(f).max() for f in (force - inertial, inertial)) + 1.0
        length = max(max(np.abs(jets[x].value - origin).max() for x in b.points), 1.0)
        assert np.abs(force).max() <= BALANCED * scale, body
        assert np.abs(moment).max() <= BALANCED * scale * length, body


def test_m_eps_plus_h_is_the_effort_through_a_slider_triad() -> None:
    scene = solver.load_scene(SCENE)
    model = scene.reduced()
    rng = np.random.default_rng(28)
    phi = np.linspace(-1.0, 7.5, 400)
    for _ in range(3):
        w, e = rng.uniform(-20.0, 20.0, 2)
        effort = scene.solve(phi, omega=w, epsilon=e).effort("crank")
        m, h = model.mass(phi), model.bias(phi, w)
        scale = max(1.0, float(np.abs(effort).max()))
        assert np.abs(m.ravel() * e + h.ravel() - effort).max() <= REL * scale


def test_a_free_slider_triad_press_keeps_its_energy_balance_and_its_loop_closed() -> None:
    scene = solver.load_scene(SCENE)
    traj = scene.simulate(0.4, phi0=0.3, rtol=1e-11, atol=1e-11)
    assert traj.status == "done" and traj.t[-1] == 0.4
    e = traj.energy()
    swing = float(np.ptp(e["kinetic"]))
    assert swing > 0.01
    assert np.abs(e["balance"]).max() <= 1e-7 * swing
    k = traj.solve()
    b, d, e_, f = (k.point(p).position for p in "BDEF")
    c = np.array([0.39, 0.5])
    assert np.abs(np.hypot(*(e_ - b).T) - 0.498196748283246).max() <= CLOSURE
    assert np.abs(np.hypot(*(f - c).T) - 0.49244289008980524).max() <= CLOSURE
    assert np.abs(d[:, 0] + 0.45).max() <= CLOSURE  # D on the vertical guide x = −0.45
