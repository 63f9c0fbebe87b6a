"""Dynamics through a triad (issue 28): M(φ)·ε + h(φ, ω) is the kinetostatic effort, and a free
run keeps its energy balance and its loop closed.

The scene is tests/forces/scenes/ref_triad_press.yaml (a crank driving a triad, masses on every
link, gravity, a force on the ternary link and a torque on a binary link), whose efforts are
themselves checked against a 50-digit Newton–Euler reference (tests/forces/test_triad_forces.py).
A triad's mode is the drawn one followed from ``at`` = 0, so the states are taken along sweeps.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

import solver
from solver.tolerances import EPS

SCENE = Path(__file__).resolve().parents[1] / "forces" / "scenes" / "ref_triad_press.yaml"
#: agreement of two evaluations of the same exact quantity, relative to the efforts' size
REL = 256 * EPS
#: loop closure of the triad's binary links along a run (lengths of order 0.25–0.6 m)
CLOSURE = 64 * EPS


def test_m_eps_plus_h_is_the_effort_through_a_triad() -> None:
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
    # per instant (the compiled one-pass (M, h)), ticking along the sweep as a run does
    w, e = 3.0, -7.0
    effort = scene.solve(phi, omega=w, epsilon=e).effort("crank")
    for i in range(0, len(phi), 7):
        m1, h1, cond = model.instant((float(phi[i]),), (w,))
        assert cond > 0.0
        assert abs(m1 * e + h1[0] - effort[i]) <= REL * max(1.0, abs(effort[i]))


def test_a_free_triad_press_keeps_its_energy_balance_and_its_loop_closed() -> None:
    scene = solver.load_scene(SCENE)
    traj = scene.simulate(0.6, phi0=0.3, rtol=1e-11, atol=1e-11)
    assert traj.status == "done" and traj.t[-1] == 0.6
    e = traj.energy()
    swing = float(np.ptp(e["kinetic"]))
    assert swing > 0.01
    assert np.abs(e["balance"]).max() <= 1e-7 * swing
    k = traj.solve()
    a, d, e_, f = (k.point(p).position for p in "ADEF")
    b, c = np.array([0.5, 0.64]), np.array([0.23, 0.05])
    lengths = (0.24515301344262527, 0.6174139616173253, 0.6082762530298219)
    for (p, q), length in zip(((a, d), (b, e_), (c, f)), lengths):
        assert np.abs(np.hypot(*(q - p).T) - length).max() <= CLOSURE
