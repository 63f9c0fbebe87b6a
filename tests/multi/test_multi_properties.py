"""Property-based checks over random five-bars and input vectors (bounded, finite ranges).

For every assemblable, well-conditioned sample (conditioning ≥ REGULAR): both loops close, the
jacobian and hessian satisfy the differentiated loop constraints, the real motion equals
J·ω and J·ε + ωᵀHω for random ω and ε, and one instant on the per-tick path equals the sweep.
"""

from __future__ import annotations

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from multi_builders import five_bar

REGULAR = 0.05
CLOSURE_TOL = 1e-12
CONSTRAINT_TOL = 1e-11
MOTION_TOL = 1e-12
SETTINGS = settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])

angle = st.floats(-np.pi, np.pi)
rate = st.floats(-5.0, 5.0)


@st.composite
def five_bars(draw: st.DrawFn) -> tuple:  # type: ignore[type-arg]
    crank = draw(st.floats(0.05, 0.5))
    distal = draw(st.floats(0.1, 1.0))
    base = draw(st.floats(0.0, 0.6))
    mode = draw(st.sampled_from([1, -1]))
    q = np.array([[draw(angle), draw(angle)] for _ in range(6)])
    return five_bar(crank=crank, distal=distal, base=base, mode=mode, points=("P", "A1", "A2")), distal, q


@SETTINGS
@given(five_bars(), st.lists(rate, min_size=4, max_size=4))
def test_loops_close_and_derivatives_obey_the_differentiated_constraints(case: tuple, rates: list) -> None:  # type: ignore[type-arg]
    scene, distal, q = case
    w, e = np.array(rates[:2]), np.array(rates[2:])
    k = scene.solve(q, omega=w, epsilon=e, mask=True)
    good = k.valid & (k.min_conditioning >= REGULAR)
    assume(good.any())
    p = k.point("P")
    for end in ("A1", "A2"):
        a = k.point(end)
        r = (p.position - a.position)[good]
        dj = (p.jacobian - a.jacobian)[good]
        dh = (p.hessian - a.hessian)[good]
        assert np.abs(np.hypot(r[:, 0], r[:, 1]) - distal).max() <= CLOSURE_TOL * distal
        scale_j = np.abs(dj).max() * distal
        assert np.abs(np.einsum("nd,ndi->ni", r, dj)).max() <= CONSTRAINT_TOL * max(scale_j, distal**2)
        second = np.einsum("nd,ndij->nij", r, dh) + np.einsum("ndi,ndj->nij", dj, dj)
        scale_h = max(np.abs(dh).max() * distal, np.abs(dj).max() ** 2, distal**2)
        assert np.abs(second).max() <= CONSTRAINT_TOL * scale_h
    v = np.einsum("ndi,i->nd", p.jacobian, w)
    acc = np.einsum("ndi,i->nd", p.jacobian, e) + np.einsum("ndij,i,j->nd", p.hessian, w, w)
    size_v = max(np.abs(v[good]).max(), 1e-300)
    size_a = max(np.abs(acc[good]).max(), 1e-300)
    assert np.abs(p.velocity - v)[good].max() <= MOTION_TOL * size_v
    assert np.abs(p.acceleration - acc)[good].max() <= MOTION_TOL * size_a


@SETTINGS
@given(five_bars())
def test_one_instant_equals_its_row_of_the_sweep(case: tuple) -> None:  # type: ignore[type-arg]
    scene, distal, q = case
    k = scene.solve(q, mask=True)
    good = np.flatnonzero(k.valid & (k.min_conditioning >= REGULAR))
    assume(len(good))
    i = int(good[0])
    tick = scene.solve((float(q[i, 0]), float(q[i, 1])))
    for attr in ("position", "jacobian", "hessian"):
        want = getattr(k.point("P"), attr)[i]
        got = getattr(tick.point("P"), attr)
        assert np.abs(got - want).max() <= 1e-13 * max(np.abs(want).max(), distal)
