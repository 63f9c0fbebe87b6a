"""The slider triad's two other one-prismatic variants (solver.groups.slider_triad): the swinging
block (``block_at: A``: a block pinned at A slides along a line fixed in the ternary link), A fixed
or moving, and the guide carried by a moving link (``guide: {on: [P, Q]}``).

* tests/data/reference_slider_triad_variants.json (tests/reference/slider_triad_variants_mp.py:
  mpmath findroot continuation from a random drawn pose, 50 digits, analogs by mpmath.diff):
  positions ≤ TOL_POS of the size and velocity analogs ≤ TOL_VEL at ±30° of the drawn input, on
  the vectorised, per-tick and compiled paths;
* every real mode against a brute-force multi-start count; G's Laurent span w^{−3} … w³ with the
  θ-dependent guide direction (the DFT at 14 roots of unity: nothing beyond);
* acceleration analogs against central differences and the twice differentiated loop; J and H
  of two inputs against central differences;
* hard cases: no real mode (the φ intervals named), a branch point (a mode jump refused), near a
  dead point (the conditioning small); scene mistakes in one line.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from scene_builders import build, slider_triad_variant_cases
from scene_builders import slider_triad_variant as variant_scene
from scipy.optimize import least_squares
from triad_checks import (
    TOL_POS,
    TOL_VEL,
    assert_dense_match,
    assert_joints_match,
    assert_points_match,
    complex_of,
    dense_sweep,
)

from solver.errors import AssemblyError, SceneError
from solver.groups._slider_triad_math import slider_coefficients, slider_roots
from solver.jet import Jet

DATA = Path(__file__).resolve().parents[1] / "data" / "reference_slider_triad_variants.json"
TOL_FD = 1e-6  # analogs vs central differences (step 1e-6 / 1e-5)
BRUTE_STARTS = 150
BRUTE_SAME = 1e-6  # rad: two least-squares solutions are one mode


_c = complex_of


def _cases() -> list[dict]:
    return slider_triad_variant_cases()


def _size(case: dict) -> float:
    return float(case["r"]) + abs(_c(case["O"])) + abs(_c(case["C"])) + 0.6 + max(float(x) for x in case["lengths"])


def test_reference_file_has_provenance_and_every_kind() -> None:
    data = json.loads(DATA.read_text())
    assert data["provenance"].startswith("tests/reference/slider_triad_variants_mp.py (mpmath")
    assert sorted({c["kind"] for c in data["cases"]}) == ["carried", "swing_fixed", "swing_moving"]


@pytest.mark.parametrize("i", range(12))
def test_reference_positions_and_analogs(i: int) -> None:
    case = _cases()[i]
    scene = variant_scene(case)
    phi = np.array([float(s["phi"]) for s in case["samples"]])
    k = scene.solve(phi)
    size = _size(case)
    assert_points_match(k, case["samples"], size)
    assert_joints_match(k, case["samples"], size)


@pytest.mark.parametrize("i", [0, 5, 9])
def test_reference_per_tick_and_compiled_paths(i: int) -> None:
    """One tick at a time from the drawn input outwards, on the scalar path and through the
    compiled instant: the reference's values."""
    case = _cases()[i]
    size = _size(case)
    samples = case["samples"]
    mid = len(samples) // 2
    for order in (samples[mid:], samples[mid::-1]):
        scene, again = variant_scene(case), variant_scene(case)
        layout = again.instant_layout()
        for s in order:
            k = scene.solve(float(s["phi"]))
            for name in "DF":
                got = complex(*np.asarray(k.point(name).position, float))
                assert abs(got - _c(s[name])) <= TOL_POS * size
                vel = complex(*np.asarray(k.point(name).velocity, float))
                assert abs(vel - _c(s["d" + name])) <= TOL_VEL * size
            flat = again.instant(float(s["phi"]))
            inst = complex(flat[layout.index("D.x")], flat[layout.index("D.y")])
            vel = complex(flat[layout.index("D.vx")], flat[layout.index("D.vy")])
            assert abs(inst - _c(s["D"])) <= TOL_POS * size
            assert abs(vel - _c(s["dD"])) <= TOL_VEL * size


@pytest.mark.parametrize("i", [0, 4, 8, 11])
def test_reference_in_a_dense_sweep_through_the_anchors_shortcut(i: int) -> None:
    """0.05° apart a variant's sweep takes the anchors' shortcut (solver.groups._slider_triad_sweep,
    the moving guide at every sample): the reference's accuracy at its φ, and the full path's root
    at every sample."""
    case = _cases()[i]
    size = _size(case)
    k, full, where, calls = dense_sweep(variant_scene, case)
    assert calls and calls[-1]
    assert_dense_match(k, full, where, case["samples"], size)
    for name in "DEF":
        acc = k.point(name).acceleration - full.point(name).acceleration
        assert np.abs(acc).max() <= 1e-9 * size, name


def _swing_instance(rng: np.random.Generator) -> tuple[Any, ...]:
    """A swinging-block triad at one instant, drawn at a random pose: (A, B, C, lengths, u, v, p,
    e_t, θ)."""
    a = complex(*rng.uniform(-0.5, 0.5, 2))
    theta, s = rng.uniform(-np.pi, np.pi), rng.uniform(-0.3, 0.3)
    p, et = complex(0.0, rng.uniform(-0.1, 0.1)), complex(np.exp(1j * rng.uniform(-1.5, 1.5)))
    u, v = complex(rng.uniform(0.3, 1.0), 0.0), complex(*rng.uniform(-1, 1, 2))
    w = np.exp(1j * theta)
    d = a - (p + s * et) * w
    b_, c_ = complex(*rng.uniform(-1, 1, 2)), complex(*rng.uniform(-1, 1, 2))
    return a, b_, c_, (abs(d + u * w - b_), abs(d + v * w - c_)), u, v, p, et, theta


def _brute_swing(a: complex, b_: complex, c_: complex, lengths: tuple, u: complex, v: complex, p: complex,
                 et: complex, rng: np.random.Generator) -> list[float]:
    def f(x: np.ndarray) -> list[float]:
        w = np.exp(1j * x[1])
        d = a - (p + x[0] * et) * w
        return [abs(d + u * w - b_) - lengths[0], abs(d + v * w - c_) - lengths[1]]
    found: list[float] = []
    reach = abs(a) + abs(b_) + abs(c_) + sum(lengths) + abs(u) + abs(v)
    for _ in range(BRUTE_STARTS):
        r = least_squares(f, np.r_[rng.uniform(-reach, reach), rng.uniform(-np.pi, np.pi)], xtol=1e-15, ftol=1e-15,
                          gtol=1e-15)
        if np.max(np.abs(r.fun)) < 1e-10:
            t = math.remainder(r.x[1], 2 * math.pi)
            if all(abs(math.remainder(t - s, 2 * math.pi)) > BRUTE_SAME for s in found):
                found.append(t)
    return sorted(found)


@pytest.mark.parametrize("seed", range(2))
def test_swinging_block_every_mode_against_brute_force(seed: int) -> None:
    rng = np.random.default_rng(seed)
    a, b_, c_, lengths, u, v, p, et, theta = _swing_instance(rng)
    got, s = slider_roots(a, 0j, b_, c_, lengths, u, v, line=(-p, -et))
    real = np.isfinite(got)
    want = _brute_swing(a, b_, c_, lengths, u, v, p, et, rng)
    assert real.sum() == len(want) and len(want) % 2 == 0
    np.testing.assert_allclose(np.sort(got[real]), want, atol=1e-8)
    assert np.min(np.abs(got[real] - theta)) <= 1e-13  # the drawn pose is one of them
    w = np.exp(1j * got[real])
    d = a - (p + s[real] * et) * w
    assert np.abs(np.abs(d + u * w - b_) - lengths[0]).max() <= 1e-14
    assert np.abs(np.abs(d + v * w - c_) - lengths[1]).max() <= 1e-14


def test_swinging_block_polynomial_spans_w_minus_3_to_3() -> None:
    """With the guide's direction e(w) = −e_t·w, G is still a Laurent polynomial of w^{−3} … w³:
    its DFT at 14 roots of unity has nothing beyond (so the DFT at 7 is exact), and the degree-6
    polynomial's roots on the circle are the loop's modes (brute force, above)."""
    rng = np.random.default_rng(7)
    a, b_, c_, lengths, u, v, p, et, _ = _swing_instance(rng)
    w14 = np.exp(2j * np.pi * np.arange(14) / 14)
    b, c = lengths
    o, e = a - p * w14, -et * w14
    p1, p2 = o - b_ + u * w14, o - c_ + v * w14
    k1, k2 = np.abs(p1) ** 2 - b * b, np.abs(p2) ** 2 - c * c
    n, dn, ep = k2 - k1, 2 * np.real(np.conj(e) * (p1 - p2)), np.real(np.conj(e) * p1)
    f = np.fft.fft(n * n + 2 * n * dn * ep + k1 * dn * dn) / 14  # f[m]: the coefficient of w^m (m mod 14)
    scale = np.abs(f).max()
    assert np.abs(f[4:11]).max() <= 1e-14 * scale  # w^4 … w^10 ≡ w^{−10} … w^{−4}: none
    coef = slider_coefficients(a, 0j, b_, c_, lengths, u, v, line=(-p, -et))
    np.testing.assert_allclose(coef, np.r_[f[11:], f[:4]], rtol=0, atol=1e-14 * scale)
    assert abs(coef[6]) > 1e-3 * scale  # degree 6


def _two_input_scene(kind: str) -> Any:
    """Two cranks: O–B drives B, P–Q drives the swinging block's pivot Q or carries the guide."""
    d, e, f = complex(-0.45, -0.8), complex(-0.39, 0.09), complex(-0.06, 0.3)
    c0 = complex(0.39, 0.5)
    theta = np.angle(e - d)
    tri: dict[str, Any] = {"type": "slider_triad", "name": "t", "ends": ["B", "C"], "points": ["D", "E", "F"],
                           "lengths": [abs(e - 0.1), abs(f - c0)], "angle": float(theta), "slide": "s",
                           "shape": {k: [z.real, z.imag] for k, z in zip("DEF", (d, e, f))}}
    if kind == "swing":  # the line through D at 0.3 rad from D→E, offset 0.02: Q on it at the drawn pose
        et = np.exp(1j * (0.3 + theta))
        pp = d + 0.02j * et + 0.1 * et - 0.05
        tri.update(block_at="Q", guide={"angle": 0.3, "offset": 0.02})
    else:  # the guide on P–Q through P at 1.2 rad from P→Q, D on it
        pp = d - 0.15 * np.exp(1.2j)
        tri["guide"] = {"on": ["P", "Q"], "angle": 1.2}
    return build({
        "scene": "two_inputs", "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0, 0], "P": [pp.real, pp.imag], "C": [c0.real, c0.imag]},
        "groups": [{"type": "crank", "name": "c1", "center": "O", "point": "B", "length": 0.1},
                   {"type": "crank", "name": "c2", "center": "P", "point": "Q", "length": 0.05}, tri],
        "outputs": {"points": ["D", "E", "F"], "joints": ["s"]},
    })


@pytest.mark.parametrize("kind", ["swing", "carried"])
def test_two_inputs_jacobian_and_hessian_against_central_differences(kind: str) -> None:
    scene = _two_input_scene(kind)
    q = np.stack([np.linspace(0.0, 0.3, 11), np.linspace(0.0, 0.4, 11)], axis=1)
    k = scene.solve(q)
    h = 1e-5
    for i in range(2):
        dq = np.zeros(2)
        dq[i] = h
        kp, km = scene.solve(q + dq), scene.solve(q - dq)
        for name in "DEF":
            fd = (kp.point(name).position - km.point(name).position) / (2 * h)
            assert np.abs(k.point(name).jacobian[..., i] - fd).max() <= TOL_FD
            fd2 = (kp.point(name).jacobian - km.point(name).jacobian) / (2 * h)
            assert np.abs(k.point(name).hessian[..., i] - fd2).max() <= TOL_FD
    one = scene.solve((0.15, 0.2))  # one instant of two inputs (the per-tick path): the sweep's row
    np.testing.assert_allclose(np.asarray(one.point("F").jacobian), k.point("F").jacobian[5], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(one.point("F").hessian), k.point("F").hessian[5], rtol=0, atol=1e-11)


@pytest.mark.parametrize("i", [1, 6, 10])
def test_acceleration_analogs_against_differences_and_the_differentiated_loop(i: int) -> None:
    """Central differences of the velocity analogs (step 1e-6), and the loop differentiated twice:
    |E' − B'|² + (E − B)·(E'' − B'') = 0 (F, C alike) to round-off."""
    case = _cases()[i]
    scene = variant_scene(case)
    phi_d, h = float(case["phi_d"]), 1e-6
    k = scene.solve(np.array([phi_d - h, phi_d, phi_d + h]))
    for name in "DEF":
        vel, acc = (getattr(k.point(name), a) @ [1, 1j] for a in ("velocity", "acceleration"))
        assert abs((vel[2] - vel[0]) / (2 * h) - acc[1]) <= TOL_FD
    r = float(case["r"])
    rb = r * np.exp(1j * phi_d)
    b = [_c(case["O"]) + rb, 1j * rb, -rb]
    c0 = _c(case["C"])
    e, f = (k.point(n) for n in "EF")
    for pt, end in ((e, b), (f, [c0, 0, 0])):
        z, z1, z2 = (getattr(pt, a)[1] @ [1, 1j] for a in ("position", "velocity", "acceleration"))
        q = z - end[0]
        first = np.real(np.conj(q) * (z1 - end[1]))
        second = abs(z1 - end[1]) ** 2 + np.real(np.conj(q) * (z2 - end[2]))
        assert abs(first) <= 1e-13 and abs(second) <= 1e-12


def _branch_scene(kind: str, *, r: float = 0.1, angle: float | None = None, at: float | None = None,
                  nth: int = 0) -> tuple[Any, float]:
    """The reference's ``nth`` case of ``kind`` (its crank ``r`` long): the scene and its drawn input."""
    case = dict([c for c in _cases() if c["kind"] == kind][nth])
    case["r"] = repr(r)
    return variant_scene(case, angle=angle, at=at), float(case["phi_d"])


def _counter(scene: Any) -> Any:
    """The number of real modes (and the roots) at an input: the group's roots at the crank's B
    (A and the carrier O–B as the scene has them)."""
    tri = next(g for g in scene.plan.groups if g.kind == "slider_triad")
    crank = next(g for g in scene.plan.groups if g.kind == "crank")
    fixed = {n: Jet(complex(*np.asarray(z, float)[:2]), 0.0, 0.0) for n, z in scene.fixed_points.items()}

    def roots(p: Any) -> Any:
        """The real roots at one input; at an array of inputs, the count of real roots at each."""
        b_ = fixed["O"].value + crank.length * np.exp(1j * np.asarray(p))
        theta = tri.roots({**fixed, "B": Jet(b_, 0.0, 0.0)})[0]
        return np.isfinite(theta).sum(axis=-1) if np.ndim(p) else theta[np.isfinite(theta)]
    return roots


@pytest.mark.parametrize("kind", ["swing_fixed", "carried"])
def test_a_branch_point_is_refused_as_a_mode_jump_and_conditioning_falls(kind: str) -> None:
    """The first input from a stored case's drawn one (0.01 rad steps, then bisected to 1e-10)
    where two real modes merge: 1e-6 before it the merging mode's conditioning is small; a sweep
    in that mode across the merge is refused (a mode jump, or no real mode left)."""
    found = None
    for nth, direction in ((n, d) for n in range(4) for d in (1.0, -1.0)):
        scene, phi_d = _branch_scene(kind, nth=nth)
        roots = _counter(scene)
        n0 = len(roots(phi_d))
        counts = roots(phi_d + direction * 0.01 * np.arange(1, 301))
        drop = np.flatnonzero(counts < n0)
        if drop.size:
            k = int(drop[0]) + 1
            found = (nth, direction, phi_d + direction * 0.01 * (k - 1), phi_d + direction * 0.01 * k)
        if found:
            break
    assert found is not None, "no branch point within 3 rad of any stored case"
    nth, direction, lo, hi = found
    n0 = len(roots(lo))
    while abs(hi - lo) > 1e-10:
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if len(roots(mid)) == n0 else (lo, mid)
    pre = hi - direction * 1e-6
    th = np.sort(roots(pre))
    gaps = np.abs(np.angle(np.exp(1j * (np.roll(th, -1) - th))))
    pair = th[int(np.argmin(gaps))]  # one of the two modes about to merge
    scene, _ = _branch_scene(kind, nth=nth, angle=float(pair), at=pre)
    k = scene.solve(np.array([pre]))
    assert abs(k.joint("ternary").position[0] - pair) <= 1e-9
    assert k.conditioning["tri"][0] < 0.05
    fresh, _ = _branch_scene(kind, nth=nth, angle=float(pair), at=pre)
    with pytest.raises(AssemblyError, match=r"group 'tri' (would jump assembly mode|has no real assembly mode)"):
        fresh.solve(np.linspace(pre, pre + direction * 0.05, 26))


@pytest.mark.parametrize(("kind", "r"), [("carried", 0.6), ("swing_moving", 1.0)])
def test_no_real_mode_names_the_intervals(kind: str, r: float) -> None:
    """A long crank: the triad cannot close over part of the turn."""
    scene, _ = _branch_scene(kind, r=r)
    phi = np.linspace(0, 2 * np.pi, 181)
    with pytest.raises(AssemblyError, match=r"group 'tri' has no real assembly mode \(slider triad\) for φ in \("):
        scene.solve(phi)
    k = scene.solve(phi, mask=True)
    assert 0 < k.valid.sum() < len(phi)
    assert not np.isnan(k.point("D").position[k.valid]).any()


def test_scene_errors() -> None:
    def scene(extra: dict) -> dict:
        group = {"type": "slider_triad", "name": "t", "block_at": "A", "ends": ["B", "C"],
                 "points": ["D", "E", "F"], "lengths": [0.6, 0.6], "angle": 1.0,
                 "shape": {"D": [0, 0], "E": [0.3, 0], "F": [0.1, 0.3]}}
        return {"scene": "e", "units": {"length": "m", "angle": "rad"},
                "fixed": {"O": [0, 0], "A": [0.5, 0.0], "C": [0.23, 0.05]},
                "groups": [{"type": "crank", "name": "crank", "center": "O", "point": "B", "length": 0.1},
                           {**group, **extra}], "outputs": {"points": ["D"]}}
    with pytest.raises(SceneError, match=r"guide\.through: the swinging block's guide is a line in the ternary link"):
        build(scene({"guide": {"through": "A"}}))
    with pytest.raises(SceneError, match=r"guide\.on: give the guide either through: <fixed point> or on: \[P, Q\]"):
        build(scene({"block_at": None, "guide": {"through": "A", "on": ["O", "B"]}}))
    with pytest.raises(SceneError, match=r"guide\.on: \[B, B\]: two different points of the carrying link"):
        build(scene({"block_at": None, "guide": {"on": ["B", "B"]}}))
    with pytest.raises(SceneError, match=r"guide\.through: the guide is fixed; 'B' is not a fixed point \(a guide on "
                                         r"a moving link: on: \[P, Q\]\)"):
        build(scene({"block_at": None, "guide": {"through": "B"}}))
    with pytest.raises(SceneError, match=r"guide: unknown field 'angel'"):
        build(scene({"guide": {"angel": 0.2}}))
    build(scene({}))  # the line through D along D→E: no guide needed
