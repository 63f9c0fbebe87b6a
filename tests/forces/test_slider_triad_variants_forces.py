"""The slider triad's variants' kinetostatics (solver.forces.slider_triad: the swinging block, fixed
or moving pivot, and the guide on a moving link) and dynamics, on the reference cases' scenes of
tests/solver/test_slider_triad_variants.py with masses, inertias, gravity and loads on every body:

* route 1 (virtual power, no reaction) against route 2 (the group's statics) at random (ω, ε),
  vectorised and per instant;
* the block and the ternary link each in equilibrium with the pin reactions and the prismatic
  pair's normal force and couple the solver gives (the normal force normal to the line);
* M(φ)·ε + h(φ, ω) is the kinetostatic effort (the generic dynamics path).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest
from scene_builders import build, slider_triad_variant_cases

from solver._backend import NUMPY
from solver.forces.frames import body_motion
from solver.forces.spec import PointForce, Torque
from solver.forces.virtual import virtual_efforts
from solver.groups import Context
from solver.tolerances import EPS

#: route 1 against route 2, relative to the largest effort of the sweep
ROUTES_AGREE = 1e-12
#: a body's equilibrium with the solver's reactions, relative to the largest force (torque) there
BALANCED = 1e-12
#: agreement of two evaluations of the same exact quantity, relative to the efforts' size
REL = 256 * EPS
KINDS = ("swing_fixed", "swing_moving", "carried")


def _c(pair: list[str]) -> complex:
    return complex(float(pair[0]), float(pair[1]))


def _cases() -> list[dict]:
    return slider_triad_variant_cases()


def loaded(kind: str) -> tuple[Any, float]:
    """The reference's first case of ``kind`` with bodies, gravity and loads: (scene, drawn φ)."""
    case = next(c for c in _cases() if c["kind"] == kind)
    fixed: dict[str, Any] = {"O": [float(x) for x in case["O"]], "C": [float(x) for x in case["C"]]}
    drawn = {k: _c(case["drawn"][k]) for k in "DEF"}
    tri: dict[str, Any] = {
        "type": "slider_triad", "name": "tri", "ends": ["B", "C"], "points": ["D", "E", "F"],
        "lengths": [float(x) for x in case["lengths"]], "shape": {k: [z.real, z.imag] for k, z in drawn.items()},
        "angle": float(np.angle(drawn["E"] - drawn["D"])), "at": float(case["phi_d"]), "slide": "s"}
    guide = {"angle": float(case["angle"]), "offset": float(case["offset"])}
    pin = {"swing_fixed": "A", "swing_moving": "H", "carried": "D"}[kind]
    if kind == "swing_fixed":
        fixed["A"] = [float(x) for x in case["A"]]
    if kind == "carried":
        tri["guide"] = {"on": ["O", "B"], **guide}
    else:
        tri.update(block_at=pin, guide=guide)
    scene = build({
        "scene": f"slider_triad_{kind}_loaded", "units": {"length": "m", "angle": "rad"}, "fixed": fixed,
        "groups": [{"type": "crank", "name": "crank", "center": "O", "point": "B", "length": float(case["r"])},
                   {"type": "attached", "name": "h", "point": "H", "base": "O", "along": ["O", "B"],
                    "distance": float(case["rho_h"]), "angle": float(case["beta_h"])}, tri],
        "outputs": {"points": ["D", "E", "F"], "joints": ["s"]},
        "bodies": {"crank": {"points": ["O", "B"], "mass": 0.3, "center": [0.05, 0.0], "inertia": 3e-4},
                   "arm_b": {"points": ["B", "E"], "mass": 0.7, "center": [0.25, 0.01], "inertia": 1.6e-2},
                   "arm_c": {"points": ["C", "F"], "mass": 0.6, "center": [0.24, -0.02], "inertia": 1.3e-2},
                   "plate": {"points": ["D", "E", "F"], "mass": 2.0, "center": [0.1, 0.05], "inertia": 6e-2},
                   "block": {"points": [pin], "mass": 1.5, "center": [0.02, 0.01], "inertia": 1e-3}},
        "gravity": [0.0, -9.81],
        "loads": [{"body": "block", "point": pin, "force": [3.0, 80.0]}, {"body": "arm_c", "torque": 1.5},
                  {"body": "plate", "point": "F", "force": [5.0, -3.0]}],
    })
    return scene, float(case["phi_d"])


@pytest.mark.parametrize("kind", KINDS)
def test_route_one_and_route_two_agree(kind: str) -> None:
    scene, phi_d = loaded(kind)
    rng = np.random.default_rng(len(kind))
    phi = phi_d + np.linspace(-0.5, 0.5, 101)
    omega, epsilon = rng.uniform(-6.0, 6.0), rng.uniform(-20.0, 20.0)
    route2 = scene.solve(phi, omega=omega, epsilon=epsilon).effort("crank")
    route1 = virtual_efforts(scene, phi, omega=omega, epsilon=epsilon)["crank"]
    assert np.abs(route2 - route1).max() <= ROUTES_AGREE * np.abs(route2).max()
    tick, _ = loaded(kind)  # per instant, ticking from the drawn input outwards
    for i in range(50, 101, 10):
        k = tick.solve(float(phi[i]), omega=omega, epsilon=epsilon)
        assert abs(float(k.effort("crank")) - route2[i]) <= ROUTES_AGREE * np.abs(route2).max()
    flat = tick.instant(float(phi[100]), float(omega), float(epsilon))  # the compiled instant's forces too
    assert any(abs(x - route2[100]) <= ROUTES_AGREE * np.abs(route2).max() for x in flat)


@pytest.mark.parametrize("kind", KINDS)
def test_block_and_ternary_link_are_in_equilibrium_with_their_reactions(kind: str) -> None:
    """d'Alembert loads, applied loads, pin reactions and the prismatic pair's normal force and
    couple (on the block; the opposite on the ternary link, at the block's pin, for the swinging
    block) sum to zero force and zero moment."""
    scene, phi_d = loaded(kind)
    phi = phi_d + np.linspace(-0.4, 0.4, 17)
    omega, epsilon = 2.5, -4.0
    k = scene.solve(phi, omega=omega, epsilon=epsilon)
    spec = scene.forces.spec
    jets = scene.plan.run(Context(phi=phi, xp=NUMPY, mask=True, owner=scene, seeds=None)).values
    sr = k.slide_reaction("block")
    normal = np.asarray(sr.force) @ [1, 1j]
    pin = next(b for b in spec.bodies if b.name == "block").link.points[0]
    turn = np.exp(1j * float(next(c for c in _cases() if c["kind"] == kind)["angle"]))
    line = turn * (jets["E"].value - jets["D"].value if kind != "carried" else jets["B"].value - jets["O"].value)
    assert np.abs(np.real(np.conj(line) * normal)).max() <= 1e-12 * np.abs(line * normal).max()  # ⊥ the line
    assert np.abs(normal).max() > 1.0
    for body in ("block", "plate"):
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
        if body == "block" or (body == "plate" and kind != "carried"):
            sign = 1.0 if body == "block" else -1.0
            force += sign * normal
            moment += sign * (np.imag(np.conj(jets[pin].value - origin) * normal) + sr.couple)
        m = body_motion(b, jets, NUMPY)
        inertial = b.mass * (spec.gravity - (m.center.d2 * omega**2 + m.center.d1 * epsilon))
        force += inertial
        moment += (np.imag(np.conj(m.center.value - origin) * inertial)
                   - b.inertia * (m.theta2 * omega**2 + m.theta1 * epsilon))
        for ld in spec.loads:
            if isinstance(ld, PointForce) and ld.body == body:
                force += ld.force
                moment += np.imag(np.conj(jets[ld.point].value - origin) * ld.force)
            elif isinstance(ld, Torque) and ld.body == body:
                moment += ld.torque
        scale = np.abs(normal).max() + np.abs(inertial).max() + 1.0
        assert np.abs(force).max() <= BALANCED * scale, body
        assert np.abs(moment).max() <= BALANCED * scale * 2.0, body


@pytest.mark.parametrize("kind", KINDS)
def test_m_eps_plus_h_is_the_effort(kind: str) -> None:
    scene, phi_d = loaded(kind)
    model = scene.reduced()
    phi = phi_d + np.linspace(-0.4, 0.4, 41)
    rng = np.random.default_rng(28)
    for _ in range(2):
        w, e = rng.uniform(-20.0, 20.0, 2)
        effort = scene.solve(phi, omega=w, epsilon=e).effort("crank")
        m, h = model.mass(phi), model.bias(phi, w)
        scale = max(1.0, float(np.abs(effort).max()))
        assert np.abs(m.ravel() * e + h.ravel() - effort).max() <= REL * scale
