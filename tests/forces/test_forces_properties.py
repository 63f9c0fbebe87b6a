"""Properties of efforts and reactions that catch real mistakes (docs/forces.md, "Checks").

Every body in equilibrium with its reactions in place (d'Alembert), Newton's third law at every
pin, route 1 (virtual power) equal to route 2 (the groups in reverse order), statics
Q = −J_Pᵀ·F, a point mass on a massless chain Q = J_Pᵀ·m·(a_P − g), the power balance
Σ Q·ω = dT/dt + dV/dt − P_loads, a millimetre scene equal to the metre scene, and the per-tick
path equal to the vectorised one. Bodies' motion is recomputed here from the points' real
motion (θ̇ = r × ṙ/|r|², θ̈ = r × r̈/|r|² − 2(r·ṙ)(r × ṙ)/|r|⁴), not from the solver's frames.
A damper (issue 22) is a viscous couple −c·(θ̇_body − θ̇_other) on its body and the opposite on
the other (ground: θ̇ = 0), from those recomputed rates; a flywheel must be in its crank body's
inertia as ``scene.bodies`` reports it (the file's inertia plus the flywheel's).
Hypothesis draws (φ, ω, ε) and geometries on bounded finite ranges.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scene_builders import build

import solver
from solver.forces import PointForce, Spring, TableForce, Torque
from solver.forces.spec import Damper
from solver.forces.virtual import virtual_efforts

#: relative to the instant's largest load: rounding of a few dozen operations
REL = 1e-11
SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
SHIPPED = ["four_bar_loaded", "engine", "harvester_finger", "five_bar", "harvester_block_spring"]


def _scene(name: str) -> solver.Scene:
    """A shipped scene, or the harvester finger with a massive eyelet block, a return spring, a
    flywheel on the drum and dampers in an angle joint (finger against ground) and a revolute
    joint between two bodies (finger against drum, its sign reversed)."""
    return solver.load_scene(name) if name != "harvester_block_spring" else build(_data(name))


def _data(name: str) -> dict[str, Any]:
    """The scene file's data (_scene's, of its harvester variant)."""
    import yaml

    data = yaml.safe_load(solver.find_scene(name.replace("_block_spring", "_finger")).read_text(encoding="utf-8"))
    if name != "harvester_block_spring":
        return dict(data)
    data["bodies"]["eyelet"] = {"points": ["B"], "mass": 0.1, "center": [0.01, 0.02], "inertia": 1.0e-4}
    data["loads"].append({"spring": [["finger", "E"], ["ground", "O"]], "stiffness": 150.0, "free_length": 0.05})
    data["loads"].append({"body": "eyelet", "torque": 0.3})
    data["joints"]["knuckle"] = {"revolute": {"parent": ["O", "B"], "child": ["A", "C"], "sign": -1}}
    data["flywheel"] = {"drum": 0.07}
    data["damping"] = {"finger": 0.4, "knuckle": 0.25, "drum": 0.1}
    return dict(data)

rate = st.floats(-20.0, 20.0)
angle = st.floats(0.0, 2 * math.pi)


def _c(v: np.ndarray) -> np.ndarray:
    return v[..., 0] + 1j * v[..., 1]


def _cross(a: Any, b: Any) -> Any:
    return (np.conj(a) * b).imag


def _dot(a: Any, b: Any) -> Any:
    return (np.conj(a) * b).real


class Motion:
    """Real motion of every point of a solve, as complex arrays (x + jy)."""

    def __init__(self, scene: solver.Scene, k: solver.Kinematics) -> None:
        self.p, self.v, self.a = {}, {}, {}
        for name in scene.point_names:
            m = k.point(name)
            self.p[name], self.v[name], self.a[name] = _c(m.position), _c(m.velocity), _c(m.acceleration)
        self.joints = {j: k.joint(j).position for j in scene.joint_names}


def _body_state(body: Any, m: Motion) -> tuple[Any, ...]:
    """(G, v_G, a_G, θ̇, θ̈) of a body from its frame points' motion."""
    link = body.link
    if link.block and link.guide is not None:
        b = link.points[0]
        return m.p[b] + body.center * link.guide, m.v[b], m.a[b], 0.0, 0.0
    o, x = (link.along[1], link.along[0]) if link.along else body.frame
    r, vr, ar = m.p[x] - m.p[o], m.v[x] - m.v[o], m.a[x] - m.a[o]
    if link.along:
        r, vr, ar = -r, -vr, -ar
    n2 = _dot(r, r)
    w = _cross(r, vr) / n2
    alpha = _cross(r, ar) / n2 - 2 * _dot(r, vr) * _cross(r, vr) / n2**2
    cu = body.center * r / np.sqrt(n2)
    return m.p[o] + cu, m.v[o] + 1j * w * cu, m.a[o] + (1j * alpha - w * w) * cu, w, alpha


def _spins(scene: solver.Scene, m: Motion) -> dict[str, Any]:
    """θ̇ of every body (ground: 0) from the points' real motion."""
    spec = scene.forces.spec  # type: ignore[union-attr]
    return {"ground": 0.0, **{b.name: _body_state(b, m)[3] for b in spec.bodies}}


def _loads_on(scene: solver.Scene, m: Motion) -> dict[str, list[tuple[Any, Any]]]:
    """Per body: (force, moment about the origin) of every applied load."""
    spec = scene.forces.spec  # type: ignore[union-attr]
    out: dict[str, list[tuple[Any, Any]]] = {b.name: [] for b in spec.bodies}
    out["ground"] = []
    spin = _spins(scene, m)
    for ld in spec.loads:
        if isinstance(ld, PointForce):
            out[ld.body].append((ld.force, _cross(m.p[ld.point], ld.force)))
        elif isinstance(ld, Torque):
            out[ld.body].append((0.0, ld.torque))
        elif isinstance(ld, TableForce):
            q = (m.joints[ld.joint] - ld.at[0]) % ld.period + ld.at[0] if ld.period else m.joints[ld.joint]
            f = np.interp(q, ld.at, ld.force) * ld.direction
            out[ld.body].append((f, _cross(m.p[ld.point], f)))
        elif isinstance(ld, Spring):
            (b0, p0), (b1, p1) = ld.ends
            d = m.p[p1] - m.p[p0]
            length = np.abs(d)
            f = ld.stiffness * (length - ld.free_length) * d / length
            out[b0].append((f, _cross(m.p[p0], f)))
            out[b1].append((-f, _cross(m.p[p1], -f)))
        elif isinstance(ld, Damper):  # viscous: against the relative turn of the two bodies
            couple = ld.coefficient * (spin[ld.body] - spin[ld.other])
            out[ld.body].append((0.0, -couple))
            out[ld.other].append((0.0, couple))
    return out


def _check_inertias(name: str, scene: solver.Scene) -> None:
    """Every body's inertia as ``scene.bodies`` reports it: the file's, plus the flywheel of the
    input crank whose centre and point it carries (a massless disc about the pivot), else 0."""
    data = _data(name)
    want = {str(b): float(v.get("inertia", 0.0)) for b, v in (data.get("bodies") or {}).items()}
    for joint, extra in (data.get("flywheel") or {}).items():
        crank = next(g for g in data["groups"] if g["type"] == "crank" and g.get("joint", g["name"]) == joint)
        body = next(b for b in scene.bodies if {crank["center"], crank["point"]} <= set(b.points))
        want[body.name] = want.get(body.name, 0.0) + float(extra)
    assert {b.name: b.inertia for b in scene.bodies} == {b.name: want.get(b.name, 0.0) for b in scene.bodies}


def _check_equilibrium(scene: solver.Scene, k: solver.Kinematics) -> None:
    m = Motion(scene, k)
    spec = scene.forces.spec  # type: ignore[union-attr]
    g = spec.gravity
    loads = _loads_on(scene, m)
    sums: dict[str, list[Any]] = {}
    for b in spec.bodies:
        G, _, a_g, _, alpha = _body_state(b, m)
        f = b.mass * (g - a_g)
        sums[b.name] = [f, _cross(G, f) - b.inertia * alpha]
        for force, moment in loads[b.name]:
            sums[b.name][0] = sums[b.name][0] + force
            sums[b.name][1] = sums[b.name][1] + moment
    for g in scene.ordered:  # the actuators' torques on the input cranks
        if g.drives:
            body = spec.names.get(g.name, g.name)
            sums[body][1] = sums[body][1] + k.effort(g.input_joint())
    scale = 1.0
    for pin in scene.pins:
        r = _c(k.reaction(pin.point, on=pin.body, by=pin.other))
        if pin.other != "ground":  # third law, exactly
            np.testing.assert_array_equal(_c(k.reaction(pin.point, on=pin.other, by=pin.body)), -r)
        scale = max(scale, float(np.abs(r).max()))
        for body, sign in ((pin.body, 1.0), (pin.other, -1.0)):
            if body != "ground":
                sums[body][0] = sums[body][0] + sign * r
                sums[body][1] = sums[body][1] + sign * _cross(m.p[pin.point], r)
    for s in scene.slides:
        pair = k.slide_reaction(s.body)
        f, c = _c(pair.force), pair.couple
        scale = max(scale, float(np.abs(f).max()))
        for body, sign in ((s.body, 1.0), (s.guide, -1.0)):
            if body != "ground":
                sums[body][0] = sums[body][0] + sign * f
                sums[body][1] = sums[body][1] + sign * (_cross(m.p[s.point], f) + c)
    size = max(abs(p) for pt in m.p.values() for p in np.atleast_1d(pt))
    for name, (force, moment) in sums.items():
        assert np.abs(force).max() <= REL * scale, (name, "ΣF", np.abs(force).max(), scale)
        assert np.abs(moment).max() <= REL * scale * max(size, 1.0), (name, "ΣM", np.abs(moment).max())


def _samples(scene: solver.Scene, data: st.DataObject, n: int = 16) -> tuple[Any, Any, Any]:
    k = len(scene.inputs)
    shape = (n,) if k == 1 else (n, k)
    low, high = (0.0, 2 * math.pi) if k == 1 else (math.radians(60), math.radians(120))
    draw = data.draw
    phi = np.array(draw(st.lists(st.floats(low, high), min_size=n * k, max_size=n * k))).reshape(shape)
    w = np.array(draw(st.lists(rate, min_size=n * k, max_size=n * k))).reshape(shape)
    e = np.array(draw(st.lists(rate, min_size=n * k, max_size=n * k))).reshape(shape)
    return phi, w, e


@SETTINGS
@given(st.sampled_from(SHIPPED), st.data())
def test_every_body_is_in_equilibrium_and_the_third_law_holds_at_every_pin(name: str, data: st.DataObject) -> None:
    scene = _scene(name).everything()
    _check_inertias(name, scene)
    phi, w, e = _samples(scene, data)
    k = scene.solve(phi, omega=w, epsilon=e, mask=True)
    assume(k.valid.all() and not k.singular.any())
    _check_equilibrium(scene, k)


@SETTINGS
@given(st.sampled_from(SHIPPED), st.data())
def test_route_one_virtual_power_equals_route_two_assur_groups(name: str, data: st.DataObject) -> None:
    scene = _scene(name)
    phi, w, e = _samples(scene, data)
    k = scene.solve(phi, omega=w, epsilon=e, mask=True)
    assume(k.valid.all() and not k.singular.any())
    virtual = virtual_efforts(scene, phi, omega=w, epsilon=e)
    for q in scene.inputs:
        size = max(1.0, float(np.abs(virtual[q]).max()))
        assert np.abs(k.effort(q) - virtual[q]).max() <= REL * size


def _four_bar(lengths: tuple[float, float, float, float], masses: list[float], extra: dict[str, Any]) -> solver.Scene:
    a, b, c, _ = lengths
    data = _raw(lengths)
    data["scene"] = "random_four_bar"
    data.update({
        "bodies": {
            "crank": {"points": ["O", "A"], "mass": masses[0], "center": [a * masses[3], a / 10], "inertia": masses[4]},
            "coupler": {"points": ["A", "B"], "mass": masses[1], "center": [b * 0.4, -b * masses[3]], "inertia": 0.01},
            "rocker": {"points": ["C", "B"], "mass": masses[2], "center": [c * 0.5, 0.01], "inertia": masses[4]},
        },
    })
    data.update(extra)
    return build(data)


@st.composite
def crank_rockers(draw: st.DrawFn) -> tuple[float, float, float, float]:
    a = draw(st.floats(0.05, 0.15))
    d = draw(st.floats(0.3, 0.6))
    b = draw(st.floats(0.3, 0.7))
    c = draw(st.floats(0.3, 0.7))
    assume(a + max(b, c, d) <= 0.97 * (b + c + d - max(b, c, d)))  # Grashof, crank shortest, margin
    return a, b, c, d


masses = st.lists(st.floats(0.0, 2.0), min_size=5, max_size=5)


@SETTINGS
@given(crank_rockers(), masses, st.data())
def test_route_one_equals_route_two_on_random_loaded_four_bars(
    lengths: tuple[float, float, float, float], m: list[float], data: st.DataObject
) -> None:
    spring = {"spring": [["coupler", "B"], ["ground", "O"]], "stiffness": 300.0 * m[0], "free_length": 0.2}
    scene = _four_bar(lengths, m, {"gravity": [0.3, -9.81], "loads": [
        {"body": "coupler", "point": "B", "force": [m[1], -m[2]]}, {"body": "rocker", "torque": m[3] - 1.0}, spring]})
    phi, w, e = _samples(scene, data)
    k = scene.solve(phi, omega=w, epsilon=e)
    assume(k.min_conditioning.min() > 0.05)
    virtual = virtual_efforts(scene, phi, omega=w, epsilon=e)["crank"]
    assert np.abs(k.effort("crank") - virtual).max() <= REL * max(1.0, float(np.abs(virtual).max()))
    _check_equilibrium(scene.everything(), scene.everything().solve(phi, omega=w, epsilon=e))


@SETTINGS
@given(crank_rockers(), st.floats(-50.0, 50.0), st.floats(-50.0, 50.0), st.data())
def test_statics_is_minus_the_jacobian_transpose_times_the_force(
    lengths: tuple[float, float, float, float], fx: float, fy: float, data: st.DataObject
) -> None:
    scene = _four_bar(lengths, [0.0] * 5, {"loads": [{"body": "rocker", "point": "B", "force": [fx, fy]}]})
    phi, _, _ = _samples(scene, data)
    k = scene.solve(phi, omega=0.0, epsilon=0.0)
    assume(k.min_conditioning.min() > 0.05)
    jac = scene.solve(phi).point("B").velocity  # ∂B/∂φ
    expected = -(jac[:, 0] * fx + jac[:, 1] * fy)
    assert np.abs(k.effort("crank") - expected).max() <= REL * max(1.0, float(np.abs(expected).max()))


@SETTINGS
@given(crank_rockers(), st.floats(0.1, 5.0), st.data())
def test_a_point_mass_on_a_massless_chain_is_the_jacobian_transpose_of_m_a_minus_g(
    lengths: tuple[float, float, float, float], mass: float, data: st.DataObject
) -> None:
    # the coupler's mass, all at B: its frame [B, A] with the centre at the origin B; no inertia
    scene = build({**_raw(lengths), "gravity": [0.0, -9.81],
                   "bodies": {"coupler": {"points": ["B", "A"], "mass": mass}}})
    phi, w, e = _samples(scene, data)
    k = scene.solve(phi, omega=w, epsilon=e)
    assume(k.min_conditioning.min() > 0.05)
    b = k.point("B")
    jac = scene.solve(phi).point("B").velocity
    rel = mass * (b.acceleration - np.array([0.0, -9.81]))
    expected = jac[:, 0] * rel[:, 0] + jac[:, 1] * rel[:, 1]
    assert np.abs(k.effort("crank") - expected).max() <= REL * max(1.0, float(np.abs(expected).max()))


def _raw(lengths: tuple[float, float, float, float]) -> dict[str, Any]:
    a, b, c, d = lengths
    return {
        "scene": "point_mass",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "C": [d, 0.0]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "A", "length": a},
            {"type": "rrr", "name": "dyad", "ends": ["A", "C"], "point": "B", "lengths": [b, c], "M": 1},
        ],
        "outputs": {"points": ["A", "B"]},
    }


def _power_terms(scene: solver.Scene, k: solver.Kinematics) -> tuple[Any, Any]:
    """(Σ Q·ω, dT/dt + dV/dt − P_loads) from the points' real motion."""
    m = Motion(scene, k)
    spec = scene.forces.spec  # type: ignore[union-attr]
    g = spec.gravity
    rhs: Any = 0.0
    omega = spin = _spins(scene, m)
    for b in spec.bodies:
        _, v_g, a_g, w, alpha = _body_state(b, m)
        rhs = rhs + b.mass * _dot(v_g, a_g) + b.inertia * w * alpha - b.mass * _dot(g, v_g)
    for ld in spec.loads:
        if isinstance(ld, PointForce):
            rhs = rhs - _dot(ld.force, m.v[ld.point])
        elif isinstance(ld, Torque):
            rhs = rhs - ld.torque * omega[ld.body]
        elif isinstance(ld, TableForce):
            q = (m.joints[ld.joint] - ld.at[0]) % ld.period + ld.at[0] if ld.period else m.joints[ld.joint]
            rhs = rhs - _dot(np.interp(q, ld.at, ld.force) * ld.direction, m.v[ld.point])
        elif isinstance(ld, Spring):  # dV/dt = k(ℓ − ℓ₀)·dℓ/dt
            (_, p0), (_, p1) = ld.ends
            d, vd = m.p[p1] - m.p[p0], m.v[p1] - m.v[p0]
            length = np.abs(d)
            rhs = rhs + ld.stiffness * (length - ld.free_length) * _dot(d, vd) / length
        elif isinstance(ld, Damper):  # the damper's power −c·(θ̇_body − θ̇_other)², dissipated
            rhs = rhs + ld.coefficient * (spin[ld.body] - spin[ld.other]) ** 2
    w_in = np.atleast_2d(np.asarray(k.omega).T).T if len(scene.inputs) > 1 else np.asarray(k.omega)
    lhs: Any = 0.0
    for i, q in enumerate(scene.inputs):
        lhs = lhs + k.effort(q) * (w_in[:, i] if len(scene.inputs) > 1 else w_in)
    return lhs, rhs


@SETTINGS
@given(st.sampled_from(SHIPPED), st.data())
def test_the_input_power_balances_kinetic_and_potential_energy_and_the_loads(name: str, data: st.DataObject) -> None:
    scene = _scene(name).everything()
    phi, w, e = _samples(scene, data)
    k = scene.solve(phi, omega=w, epsilon=e, mask=True)
    assume(k.valid.all() and not k.singular.any())
    lhs, rhs = _power_terms(scene, k)
    assert np.abs(lhs - rhs).max() <= REL * max(1.0, float(np.abs(rhs).max()), float(np.abs(lhs).max()))


@settings(max_examples=15, deadline=None)
@given(angle, rate, rate)
def test_a_millimetre_scene_gives_the_forces_of_the_metre_scene(phi: float, w: float, e: float) -> None:
    import yaml

    data = yaml.safe_load(solver.find_scene("engine").read_text(encoding="utf-8"))
    # the gas table is of the crank angle: a table of the piston's position (mm) is scaled too
    piston_table = {"of": "piston_x", "at": [110.0, 150.0, 200.0], "force": [0.0, 300.0, 500.0]}
    data["loads"].append({"body": "piston", "point": "B", "direction": [-1.0, 0.0], "table": piston_table})
    metres = yaml.safe_load(yaml.safe_dump(data))
    metres["units"]["length"] = "m"
    metres["groups"][0]["length"] /= 1000.0
    metres["groups"][1]["length"] /= 1000.0
    for body in metres["bodies"].values():
        if "center" in body:
            body["center"] = [x / 1000.0 for x in body["center"]]
    for load in metres["loads"]:  # a table of a length joint is in mm; of an angle, unchanged
        table = load.get("table")
        joint = metres.get("joints", {}).get(table["of"]) if table else None
        if joint is not None and not {"angle", "revolute"} & set(joint):
            table["at"] = [x / 1000.0 for x in table["at"]]
    assert [ld["table"]["at"][-1] for ld in metres["loads"]] == [720, 0.2]
    mm, m = build(data), build(metres)
    a, b = mm.solve(phi, omega=w, epsilon=e), m.solve(phi, omega=w, epsilon=e)
    scale = max(1.0, abs(b.effort("crankshaft")))
    assert abs(a.effort("crankshaft") - b.effort("crankshaft")) <= 1e-12 * scale * 10
    for pin in m.pins:
        ra, rb = a.reaction(pin.point, on=pin.body), b.reaction(pin.point, on=pin.body)
        assert np.abs(ra - rb).max() <= 1e-12 * max(1.0, float(np.abs(rb).max())) * 10


@SETTINGS
@given(st.sampled_from(SHIPPED), st.data())
def test_one_instant_per_tick_equals_the_vectorised_sweep(name: str, data: st.DataObject) -> None:
    scene = _scene(name)
    phi, w, e = _samples(scene, data, n=4)
    sweep = scene.solve(phi, omega=w, epsilon=e, mask=True)
    for i in range(4):
        if not sweep.valid[i]:
            continue
        if len(scene.inputs) == 1:
            one = scene.solve(float(phi[i]), omega=float(w[i]), epsilon=float(e[i]))
        else:
            one = scene.solve(tuple(phi[i]), omega=tuple(map(float, w[i])), epsilon=tuple(map(float, e[i])))
        for q in scene.inputs:
            assert isinstance(one.effort(q), float)
            np.testing.assert_allclose(one.effort(q), sweep.effort(q)[i], rtol=1e-13, atol=1e-12)
        for pin in scene.pins:
            np.testing.assert_allclose(one.reaction(pin.point, on=pin.body, by=pin.other),
                                       sweep.reaction(pin.point, on=pin.body, by=pin.other)[i], rtol=1e-13, atol=1e-12)
