"""The triad's kinetostatics (route 2, solver.forces.triad; issue 28) against independent checks.

* the 50-digit Newton–Euler reference (tests/reference/forces_mp.py: the triad's loop solved by
  findroot and continued from the drawn pose, every body's equations as one linear system) of
  tests/forces/scenes/ref_triad_press.yaml, stored in tests/data/triad/ (not among the generic
  ``forces_*.json`` of tests/data: a triad's mode at an input is the drawn one *followed* from
  ``at``, so its random instants are solved here inside one sorted sweep, as the reference
  continues them, not as unrelated samples);
* route 1 (virtual power, no reaction) at random (φ, ω, ε), vectorised and per instant;
* each of the four bodies of the triad in equilibrium with the reactions the solver gives.
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

ROOT = Path(__file__).resolve().parents[2]
REFERENCE = ROOT / "tests" / "data" / "triad" / "forces_ref_triad_press.json"
SCENE = ROOT / "tests" / "forces" / "scenes" / "ref_triad_press.yaml"
#: the sweep that carries the reference's instants: at most this far apart (rad), so that the mode
#: is followed as the reference's continuation follows it
SWEEP_STEP = 0.01
#: route 1 against route 2, relative to the largest effort of the sweep
ROUTES_AGREE = 1e-12
#: a body's equilibrium with the solver's reactions, relative to the largest force (torque) there
BALANCED = 1e-12


def _reference() -> tuple[solver.Scene, dict]:
    ref = json.loads(REFERENCE.read_text())
    digest = _reference_module().digest(SCENE)
    assert digest == ref["scene_mechanics_sha256"], (
        f"{SCENE.name}'s mechanics changed: python tests/reference/forces_mp.py {SCENE} --out tests/data/triad")
    return solver.load_scene(SCENE), ref


def _sweep(q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A sorted sweep from `at` = 0 over every q, with the q among its samples: (φ, where q sits)."""
    lo, hi = min(q.min(), 0.0), max(q.max(), 0.0)
    grid = np.linspace(lo, hi, int((hi - lo) / SWEEP_STEP) + 2)
    phi = np.unique(np.concatenate([grid, q, [0.0]]))
    return phi, np.searchsorted(phi, q)


def _rates(ref: dict, phi: np.ndarray, where: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """ω, ε over the sweep: the reference's at its instants, 0 elsewhere."""
    omega, epsilon = np.zeros_like(phi), np.zeros_like(phi)
    omega[where] = [float(r["omega"][0]) for r in ref["samples"]]
    epsilon[where] = [float(r["epsilon"][0]) for r in ref["samples"]]
    return omega, epsilon


class _At:
    """The result of a sweep read at the reference's instants only."""

    def __init__(self, k: Any, where: np.ndarray) -> None:
        self.k, self.where = k, where

    def effort(self, joint: str) -> np.ndarray:
        return np.asarray(self.k.effort(joint))[self.where]

    def reaction(self, point: str, *, on: str, by: str | None = None) -> np.ndarray:
        return np.asarray(self.k.reaction(point, on=on, by=by))[self.where]

    def slide_reaction(self, block: str) -> Any:  # the triad scene has no sliding pair
        raise AssertionError(block)


def test_vectorised_triad_forces_match_the_newton_euler_reference() -> None:
    scene, ref = _reference()
    q = np.array([float(r["q"][0]) for r in ref["samples"]])
    phi, where = _sweep(q)
    omega, epsilon = _rates(ref, phi, where)
    k = scene.solve(phi, omega=omega, epsilon=epsilon)
    expected = _expected(ref)
    assert ("reaction", "E", "ram") in expected and ("reaction", "A", "arm_a") in expected
    _check(scene, _At(k, where), expected, _scales(ref, expected), slice(None), "ref_triad_press (vectorised)")


def test_one_instant_triad_forces_match_the_newton_euler_reference() -> None:
    """Tick by tick along the same sweep (the per-tick path follows the mode from tick to tick)."""
    scene, ref = _reference()
    q = np.array([float(r["q"][0]) for r in ref["samples"]])
    phi, where = _sweep(q)
    omega, epsilon = _rates(ref, phi, where)
    expected = _expected(ref)
    scales = _scales(ref, expected)
    order = np.argsort(np.abs(phi), kind="stable")  # from at = 0 outward: both directions continued
    up = [i for i in order if phi[i] >= 0.0]
    down = [i for i in order if phi[i] < 0.0]
    sample = {int(w): n for n, w in enumerate(where)}
    for path in (up, down):
        scene = solver.load_scene(SCENE)  # a fresh per-tick state for each direction
        for i in path:
            k = scene.solve(float(phi[i]), omega=float(omega[i]), epsilon=float(epsilon[i]))
            n = sample.get(int(i))
            if n is not None:
                _check(scene, k, expected, scales, n, f"ref_triad_press (one instant, sample {n})")


@pytest.mark.parametrize("seed", range(3))
def test_route_one_and_route_two_agree_through_a_triad(seed: int) -> None:
    scene = solver.load_scene(SCENE)
    rng = np.random.default_rng(seed)
    phi = np.linspace(-1.0, 7.5, 600)
    omega, epsilon = rng.uniform(-6.0, 6.0), rng.uniform(-20.0, 20.0)
    route2 = scene.solve(phi, omega=omega, epsilon=epsilon).effort("crank")
    route1 = virtual_efforts(scene, phi, omega=omega, epsilon=epsilon)["crank"]
    assert np.abs(route2 - route1).max() <= ROUTES_AGREE * np.abs(route2).max()


def test_each_body_of_the_triad_is_in_equilibrium_with_its_reactions() -> None:
    """The four bodies' d'Alembert loads (from the bodies' kinematics, solver.forces.frames), their
    applied loads and the solver's pin reactions sum to zero force and zero moment."""
    scene = solver.load_scene(SCENE)
    phi = np.linspace(0.0, 2.0 * np.pi, 37)
    omega, epsilon = 2.5, -4.0
    k = scene.solve(phi, omega=omega, epsilon=epsilon)
    spec = scene.forces.spec  # type: ignore[union-attr]
    ctx = Context(phi=phi, xp=NUMPY, mask=True, owner=scene, seeds=None)
    jets = scene.plan.run(ctx).values
    g = spec.gravity
    for body in ("arm_a", "arm_b", "arm_c", "ram"):
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
        length = max(np.abs(jets[x].value - origin).max() for x in b.points)
        assert np.abs(force).max() <= BALANCED * scale, body
        assert np.abs(moment).max() <= BALANCED * scale * length, body
