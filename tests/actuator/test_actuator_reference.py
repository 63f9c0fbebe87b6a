"""The actuator group against a 50-digit reference written here: the circle intersection of
seed 003 in mpmath (C at s from A and l from O), the attached points of the excavator in mpmath,
and every derivative by mpmath's ``diff`` (no formula of the solver reused). Positions, the
analogs d/ds and d²/ds², the Jacobians and Hessians of several inputs, and the real motion
v = J·ω, a = J·ε + ωᵀHω. Provenance: the shipped scenes tipper.yaml and excavator.yaml, their
numbers read from the files; expected values computed in the test at mp.dps = 50."""

from __future__ import annotations

import itertools
from collections.abc import Callable, Sequence
from typing import Any

import mpmath as mp
import numpy as np

import solver
from solver._yaml import load_yaml

mp.mp.dps = 50

#: Agreement asked of the doubles against the 50-digit values, relative to the mechanism's scale
#: (measured: 7e-16, 4e-15 and 1.2e-13 at most; conditioning ≥ 0.1 on these samples).
TOL = (2e-15, 2e-14, 1e-12)


def circle(a: Any, o: Any, s: Any, link: Any, mode: int) -> Any:
    """Seed 003's intersection in mpmath: |C − A| = s, |C − O| = l, A → C → O counter-clockwise for M = +1."""
    d = o - a
    dd = abs(d) ** 2
    ac = (s * s - link * link + dd) / (2 * dd)
    h = mp.sqrt(s * s / dd - ac * ac)
    return a + d * (ac - 1j * mode * h)


def attached(base: Any, r: Any, q: Any, distance: Any, angle_deg: Any) -> Any:
    v = q - r
    return base + distance * mp.expj(mp.radians(angle_deg)) * v / abs(v)


def _groups(name: str) -> tuple[dict[str, Any], dict[str, Any]]:
    data = load_yaml(solver.find_scene(name))
    fixed = {k: mp.mpc(*[mp.mpf(str(x)) for x in v]) for k, v in data["fixed"].items()}
    return data, fixed


def model(name: str) -> tuple[Callable[..., dict[str, Any]], list[str]]:
    """The scene's points as an mpmath function of its strokes (read from the scene file)."""
    data, fixed = _groups(name)
    inputs = [g["joint"] for g in data["groups"] if g["type"] == "actuator"]

    def points(*q: Any) -> dict[str, Any]:
        x = dict(fixed)
        stroke = dict(zip(inputs, q))
        for g in data["groups"]:
            m = lambda v: mp.mpf(str(v))
            if g["type"] == "actuator":
                x[g["point"]] = circle(x[g["base"]], x[g["pivot"]], stroke[g["joint"]], m(g["length"]), g["M"])
            elif g["type"] == "attached":
                x[g["point"]] = attached(x[g["base"]], x[g["along"][0]], x[g["along"][1]], m(g["distance"]),
                                         m(g["angle"]))
            elif g["type"] == "rrr":
                a, c = g["ends"]
                x[g["point"]] = circle(x[a], x[c], m(g["lengths"][0]), m(g["lengths"][1]), g["M"])
        return x

    return points, inputs


def _xy(z: Any) -> list[Any]:
    return [mp.re(z), mp.im(z)]


def _close(got: Any, want: Sequence[Any], tol: float, scale: float, what: str) -> None:
    err = max(abs(mp.mpf(float(g)) - w) for g, w in zip(np.ravel(got), want))
    assert err <= tol * scale, (what, float(err))


def test_tipper_positions_and_analogs_match_the_50_digit_reference() -> None:
    scene = solver.load_scene("tipper").everything()
    points, _ = model("tipper")
    lo, hi = scene.input_ranges[0]
    strokes = np.linspace(lo, hi, 9)
    k = scene.solve(strokes)
    for i, s in enumerate(strokes):
        sm = mp.mpf(float(s))
        for name in ("C", "F", "L"):
            for order in range(3):
                want = [mp.diff(lambda t, n=name, p=p: _xy(points(t)[n])[p], sm, order) for p in (0, 1)]
                got = (k.point(name).position, k.point(name).velocity, k.point(name).acceleration)[order][i]
                _close(got, want, TOL[order], 2.4, (name, s, order))
        tilt = lambda t: mp.atan2(*reversed(_xy(points(t)["F"])))
        for order in range(3):
            got = (k.joint("floor").position, k.joint("floor").velocity, k.joint("floor").acceleration)[order][i]
            _close([got], [mp.diff(tilt, sm, order)], TOL[order], 1.0, ("floor", s, order))
        assert k.joint("stroke").position[i] == s and k.joint("stroke").velocity[i] == 1.0


def test_the_per_tick_path_gives_the_real_motion_of_the_reference() -> None:
    scene = solver.load_scene("tipper")
    points, _ = model("tipper")
    s, w, e = 0.93, 0.07, -0.4  # m, m/s, m/s²
    k = scene.solve(s, omega=w, epsilon=e)
    sm = mp.mpf(s)
    for part in (0, 1):
        x = lambda t, p=part: _xy(points(t)["F"])[p]
        d1, d2 = mp.diff(x, sm, 1), mp.diff(x, sm, 2)
        pos, vel, acc = (m[part] for m in k.floats("F"))
        _close([pos, vel, acc], [x(sm), d1 * w, d2 * w * w + d1 * e], TOL[1], 2.4, ("F", part))


EXCAVATOR_SAMPLES = [(1.12, 1.41, 1.08), (1.3, 1.6, 1.2), (1.55, 1.85, 1.4)]


def test_excavator_tip_jacobian_hessian_and_motion_match_the_50_digit_reference() -> None:
    scene = solver.load_scene("excavator").with_outputs(points=["T", "E", "C2"], joints=[])
    points, inputs = model("excavator")
    assert tuple(inputs) == scene.inputs
    q = np.array(EXCAVATOR_SAMPLES)
    w, e = np.array([0.05, -0.08, 0.1]), np.array([0.3, 0.2, -0.5])
    k = scene.solve(q, omega=w, epsilon=e)
    for i, row in enumerate(EXCAVATOR_SAMPLES):
        qm = [mp.mpf(x) for x in row]
        for name in ("T", "E", "C2"):
            for part in (0, 1):
                f = lambda *t, n=name, p=part: _xy(points(*t)[n])[p]
                jac = [mp.diff(f, qm, tuple(int(j == m) for j in range(3))) for m in range(3)]
                hess = [[mp.diff(f, qm, tuple((j == a) + (j == b) for j in range(3))) for b in range(3)]
                        for a in range(3)]
                m = k.point(name)
                _close([m.position[i, part]], [f(*qm)], TOL[0], 4.0, (name, "position"))
                _close(m.jacobian[i, part], jac, TOL[1], 4.0, (name, "J"))
                _close(m.hessian[i, part].ravel(), list(itertools.chain(*hess)), TOL[2], 4.0, (name, "H"))
                v = sum(jac[a] * w[a] for a in range(3))
                acc = sum(jac[a] * e[a] for a in range(3)) + sum(
                    hess[a][b] * w[a] * w[b] for a in range(3) for b in range(3))
                _close([m.velocity[i, part]], [v], TOL[1], 4.0, (name, "v"))
                _close([m.acceleration[i, part]], [acc], TOL[2], 4.0, (name, "a"))
