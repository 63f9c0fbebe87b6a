"""The slider triad (the triad with one prismatic pair, solver.groups.slider_triad) against
independent references.

* tests/data/reference_slider_triad.json (tests/reference/slider_triad_mp.py: mpmath findroot
  continuation from a random drawn pose, 50 digits): positions ≤ TOL_POS of the mechanism's size
  and velocity analogs ≤ TOL_VEL at ±30° of the drawn input, on the vectorised, per-tick and
  compiled paths;
* every real assembly mode against a brute-force multi-start count (scipy least_squares);
* the polynomial's degree and its leading coefficient by hand; its values against G evaluated in
  mpmath;
* random instances in every mode; analogs against central differences; near-singular poses;
  errors (no real mode, a mode jump, scene mistakes).
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import mpmath
import numpy as np
import pytest
from scene_builders import build
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
from solver.groups._slider_triad_math import DEGREE, slider_coefficients, slider_roots

DATA = Path(__file__).resolve().parents[1] / "data" / "reference_slider_triad.json"
TOL_FD = 1e-6  # analogs vs central differences (step 1e-6: truncation ~1e-12, rounding ~1e-10)
BRUTE_STARTS = 150
BRUTE_SAME = 1e-6  # rad: two least-squares solutions are one mode


_c = complex_of


def _cases() -> list[dict]:
    return json.loads(DATA.read_text())["cases"]  # type: ignore[no-any-return]


def _size(case: dict) -> float:
    return (float(case["r"]) + max(abs(_c(case["C"])), abs(_c(case["G"]))) + 0.4
            + max(float(x) for x in case["lengths"]))


def slider_scene(*, r: float, c: complex, g: complex, gamma: float, drawn: dict[str, complex], phi_d: float,
                 at: float | None = None, angle: float | None = None) -> Any:
    """A crank OB driving a slider triad: D on the guide through G at γ, E–B, F–C binary links,
    the binary links' lengths the drawn distances, the mode the drawn one (or ``angle``)."""
    d, e, f = drawn["D"], drawn["E"], drawn["F"]
    b = r * complex(math.cos(phi_d), math.sin(phi_d))
    return build({
        "scene": "slider_triad_ref",
        "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0.0, 0.0], "C": [c.real, c.imag], "G": [g.real, g.imag]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "O", "point": "B", "length": r},
            {"type": "slider_triad", "name": "tri", "guide": {"through": "G", "angle": gamma},
             "ends": ["B", "C"], "points": ["D", "E", "F"], "lengths": [abs(e - b), abs(f - c)],
             "shape": {k: [z.real, z.imag] for k, z in drawn.items()},
             "angle": math.atan2((e - d).imag, (e - d).real) if angle is None else angle,
             "at": phi_d if at is None else at, "joint": "ternary", "slide": "s"},
        ],
        "outputs": {"points": ["D", "E", "F"], "joints": ["ternary", "s"]},
    })


def _scene(case: dict) -> Any:
    return slider_scene(r=float(case["r"]), c=_c(case["C"]), g=_c(case["G"]), gamma=float(case["gamma"]),
                        drawn={k: _c(case["drawn"][k]) for k in "DEF"}, phi_d=float(case["phi_d"]))


def test_reference_file_has_provenance() -> None:
    data = json.loads(DATA.read_text())
    assert data["provenance"].startswith("tests/reference/slider_triad_mp.py (mpmath")
    assert len(data["cases"]) == 12


@pytest.mark.parametrize("i", range(12))
def test_reference_positions_and_analogs(i: int) -> None:
    case = _cases()[i]
    scene = _scene(case)
    phi = np.array([float(s["phi"]) for s in case["samples"]])
    k = scene.solve(phi)
    size = _size(case)
    assert_points_match(k, case["samples"], size)
    assert_joints_match(k, case["samples"], size)


@pytest.mark.parametrize("i", [0, 5, 11])
def test_reference_per_tick_and_compiled_paths(i: int) -> None:
    """One tick at a time from the drawn input outwards (the previous tick carries the mode), on
    the scalar path and through the compiled instant: the same values."""
    case = _cases()[i]
    size = _size(case)
    samples = case["samples"]
    mid = len(samples) // 2
    for order in (samples[mid:], samples[mid::-1]):
        scene, again = _scene(case), _scene(case)
        layout = again.instant_layout()
        for s in order:
            k = scene.solve(float(s["phi"]))
            got = complex(*np.asarray(k.point("E").position, float))
            assert abs(got - _c(s["E"])) <= TOL_POS * size
            vel = complex(*np.asarray(k.point("E").velocity, float))
            assert abs(vel - _c(s["dE"])) <= TOL_VEL * size
            flat = again.instant(float(s["phi"]))
            inst = complex(flat[layout.index("E.x")], flat[layout.index("E.y")])
            assert abs(inst - _c(s["E"])) <= TOL_POS * size


def _brute_modes(o: complex, e: complex, b_: complex, c_: complex, lengths: tuple, u: complex, v: complex,
                 rng: np.random.Generator) -> list[float]:
    def f(x: np.ndarray) -> list[float]:
        d, w = o + x[0] * e, np.exp(1j * x[1])
        return [abs(d + u * w - b_) - lengths[0], abs(d + v * w - c_) - lengths[1]]
    found: list[float] = []
    reach = abs(o) + abs(b_) + abs(c_) + sum(lengths) + abs(u) + abs(v)
    for _ in range(BRUTE_STARTS):
        x0 = np.r_[rng.uniform(-reach, reach), rng.uniform(-np.pi, np.pi)]
        r = least_squares(f, x0, xtol=1e-15, ftol=1e-15, gtol=1e-15)
        if np.max(np.abs(r.fun)) < 1e-10:
            t = math.remainder(r.x[1], 2 * math.pi)
            if all(abs(math.remainder(t - s, 2 * math.pi)) > BRUTE_SAME for s in found):
                found.append(t)
    return sorted(found)


def _random_instance(rng: np.random.Generator) -> tuple[complex, complex, complex, complex, tuple, complex, complex,
                                                          float]:
    o = complex(*rng.uniform(-1, 1, 2))
    e = complex(np.exp(1j * rng.uniform(-np.pi, np.pi)))
    b_, c_ = (complex(*rng.uniform(-1, 1, 2)) for _ in range(2))
    d = o + rng.uniform(-0.8, 0.8) * e
    theta = rng.uniform(-3, 3)
    u, v = complex(rng.uniform(0.3, 1.0), 0.0), complex(*rng.uniform(-1, 1, 2))
    w = np.exp(1j * theta)
    return o, e, b_, c_, (abs(d + u * w - b_), abs(d + v * w - c_)), u, v, theta


@pytest.mark.parametrize("seed", range(6))
def test_every_mode_against_brute_force(seed: int) -> None:
    rng = np.random.default_rng(seed)
    o, e, b_, c_, lengths, u, v, theta = _random_instance(rng)
    got, s = slider_roots(o, e, b_, c_, lengths, u, v)
    got = got[np.isfinite(got)]
    want = _brute_modes(o, e, b_, c_, lengths, u, v, rng)
    assert len(got) == len(want) and len(got) % 2 == 0
    np.testing.assert_allclose(np.sort(got), want, atol=1e-8)
    assert np.min(np.abs(got - theta)) <= 1e-13  # the drawn pose is one of them, to round-off


def test_six_real_modes_exist() -> None:
    """The degree does not drop with the slider: an instance (seeded random search) with six real
    modes, each a closed loop, all found by brute force too."""
    rng = np.random.default_rng(0)
    for _ in range(20000):
        inst = _random_instance(rng)
        got, s = slider_roots(*inst[:-1])
        if np.isfinite(got).sum() == 6:
            break
    else:
        pytest.fail("no instance with six real modes")
    o, e, b_, c_, lengths, u, v, _ = inst
    want = _brute_modes(o, e, b_, c_, lengths, u, v, np.random.default_rng(1))
    assert len(want) == 6
    np.testing.assert_allclose(got, want, atol=1e-8)
    w = np.exp(1j * got)
    d = o + s * e
    assert np.abs(np.abs(d + u * w - b_) - lengths[0]).max() <= 1e-14
    assert np.abs(np.abs(d + v * w - c_) - lengths[1]).max() <= 1e-14


def test_polynomial_degree_and_coefficients() -> None:
    """w³·G(w) has degree 6: its leading coefficient is conj(e)²·u·v·(u − v)·conj(B − C) (hand
    expansion, solver.groups.slider_triad) and never 0 for a ternary link (u ≠ v, both ≠ 0) and
    B ≠ C; self-inversive (c₆₋ₖ = conj(cₖ)); and the polynomial equals w³·G(w) evaluated term
    by term in mpmath at points off the circle (where G's Laurent form, not its values on the
    circle, is checked)."""
    o, e = complex(0.1, -0.2), complex(np.exp(0.7j))
    b_, c_ = complex(0.9, 0.2), complex(0.1, 1.1)
    u, v, lengths = complex(0.7, 0.0), complex(0.2, 0.5), (0.8, 0.7)
    coef = slider_coefficients(o, e, b_, c_, lengths, u, v)
    assert coef.shape == (DEGREE + 1,)
    lead = np.conj(e) ** 2 * u * v * (u - v) * np.conj(b_ - c_)
    assert abs(coef[6] - lead) <= 1e-14 * abs(lead)
    np.testing.assert_allclose(coef[::-1], np.conj(coef), rtol=0, atol=1e-14 * np.abs(coef).max())
    mpmath.mp.dps = 30
    mpc = mpmath.mpc

    def laurent(w: mpmath.mpc) -> mpmath.mpc:
        """G at any w, its conjugates taken as Laurent polynomials (conj(w) → 1/w)."""
        wi = 1 / w
        p1, p2 = mpc(o) - mpc(b_) + mpc(u) * w, mpc(o) - mpc(c_) + mpc(v) * w
        p1c = mpmath.conj(mpc(o) - mpc(b_)) + mpmath.conj(mpc(u)) * wi
        p2c = mpmath.conj(mpc(o) - mpc(c_)) + mpmath.conj(mpc(v)) * wi
        ec = mpmath.conj(mpc(e))
        k1 = p1 * p1c - lengths[0] ** 2
        k2 = p2 * p2c - lengths[1] ** 2
        n = k2 - k1
        dn = ec * (p1 - p2) + mpc(e) * (p1c - p2c)
        ep = (ec * p1 + mpc(e) * p1c) / 2
        return n * n + 2 * n * dn * ep + k1 * dn * dn
    for w in (mpc(0.5, 0.3), mpc(-1.7, 0.4), mpc(0.2, -2.1)):
        want = complex(w**3 * laurent(w))
        got = np.polyval(coef[::-1], complex(w))
        assert abs(got - want) <= 1e-13 * np.abs(coef).max() * max(1.0, abs(complex(w))) ** 6


@pytest.mark.parametrize("seed", range(5))
def test_random_instances_in_every_mode(seed: int) -> None:
    """A random crank-driven slider triad: each real mode at the drawn input, named by its angle,
    is the mode the scene solves there; a short sweep in it closes its loop to round-off and its
    analogs match central differences (where the mode lives that far without a branch point)."""
    rng = np.random.default_rng(100 + seed)
    r, c, g, gamma = 0.1, complex(*rng.uniform(-0.6, 0.6, 2)), complex(*rng.uniform(-0.6, 0.6, 2)), 0.3
    ed = complex(np.exp(1j * gamma))
    drawn = {"D": g + 0.2 * ed, "E": complex(*rng.uniform(-0.6, 0.6, 2)), "F": complex(*rng.uniform(-0.6, 0.6, 2))}
    phi_d = float(rng.uniform(-3, 3))
    scene = slider_scene(r=r, c=c, g=g, gamma=gamma, drawn=drawn, phi_d=phi_d)
    tri = next(grp for grp in scene.plan.groups if grp.kind == "slider_triad")
    b_ = r * np.exp(1j * phi_d)
    theta, _ = slider_roots(tri.origin, tri.direction, b_, c, tri.lengths, *tri.shape)
    modes = theta[np.isfinite(theta)]
    assert len(modes) >= 2
    swept = 0
    for angle in modes:
        sc = slider_scene(r=r, c=c, g=g, gamma=gamma, drawn=drawn, phi_d=phi_d, angle=float(angle))
        k0 = sc.solve(np.array([phi_d]))
        assert abs(math.remainder(float(k0.joint("ternary").position[0]) - angle, 2 * math.pi)) <= 1e-14
        phi = phi_d + np.linspace(-0.05, 0.05, 21)
        try:
            k = sc.solve(phi)
        except AssemblyError as exc:
            assert "would jump assembly mode" in str(exc) or "no real assembly mode" in str(exc)
            continue
        swept += 1
        h = 1e-6
        kp, km = sc.solve(phi + h), sc.solve(phi - h)
        d = k.point("D").position @ [1, 1j]
        bb = r * np.exp(1j * phi)
        assert np.abs(np.abs(k.point("E").position @ [1, 1j] - bb) - tri.lengths[0]).max() <= 1e-14
        off = d - tri.origin
        assert np.abs(off.real * ed.imag - off.imag * ed.real).max() <= 1e-15  # D on the guide
        for name in "DEF":
            scale = max(1.0, float(np.abs(k.point(name).acceleration).max()))
            fd = (kp.point(name).position - km.point(name).position) / (2 * h)
            assert np.abs(fd - k.point(name).velocity).max() <= TOL_FD * scale
            fd2 = (kp.point(name).velocity - km.point(name).velocity) / (2 * h)
            assert np.abs(fd2 - k.point(name).acceleration).max() <= TOL_FD * scale
    assert swept >= 1


def _branch_case() -> tuple[dict, float, float]:
    """An instance (found by hand) whose drawn mode (θ ≈ 1.718 at φ = 0.3) merges with another
    near φ = 0.22: six real modes at φ = 0.3, four below the branch point."""
    return ({"D": complex(-0.2, -0.3) + 0.4 * complex(np.exp(0.2j)), "E": complex(0.1, 0.4),
             "F": complex(0.45, 0.1)}, 0.3, 0.2)


def test_a_sweep_through_a_branch_point_says_it_would_jump_mode() -> None:
    drawn, phi_d, gamma = _branch_case()
    scene = slider_scene(r=0.1, c=complex(0.5, -0.4), g=complex(-0.2, -0.3), gamma=gamma, drawn=drawn,
                         phi_d=phi_d)
    with pytest.raises(AssemblyError, match=r"group 'tri' would jump assembly mode \(a branch point: two of the "
                                            r"slider triad's modes merge"):
        scene.solve(np.linspace(phi_d - 0.3, phi_d, 61))
    k = scene.solve(np.linspace(phi_d, phi_d + 0.05, 11))  # inside the interval the mode lives in
    assert k.conditioning["tri"].min() > 0.0
    # tick by tick, the same refusal
    tick = slider_scene(r=0.1, c=complex(0.5, -0.4), g=complex(-0.2, -0.3), gamma=gamma, drawn=drawn, phi_d=phi_d)
    with pytest.raises(AssemblyError, match=r"would jump assembly mode"):
        for p in np.linspace(phi_d, phi_d - 0.3, 61):
            tick.solve(float(p))


def test_near_singular_pose_polishes_both_close_modes() -> None:
    """3e-13 rad of input inside the branch point (two modes ~1e-6 rad apart): both found, the
    loop closed to 1e-12 of the size (Newton's floor where the Jacobian is that close to
    singular: its steps carry the rounding divided by the conditioning), the conditioning small."""
    drawn, phi_d, gamma = _branch_case()
    scene = slider_scene(r=0.1, c=complex(0.5, -0.4), g=complex(-0.2, -0.3), gamma=gamma, drawn=drawn,
                         phi_d=phi_d)
    tri = next(grp for grp in scene.plan.groups if grp.kind == "slider_triad")

    def count(p: float) -> int:
        return int(np.isfinite(slider_roots(tri.origin, tri.direction, 0.1 * np.exp(1j * p), complex(0.5, -0.4),
                                            tri.lengths, *tri.shape)[0]).sum())
    lo, hi = phi_d, phi_d - 0.3
    n0 = count(lo)
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if count(mid) == n0 else (lo, mid)
    b_ = 0.1 * np.exp(1j * lo)
    theta, s = slider_roots(tri.origin, tri.direction, b_, complex(0.5, -0.4), tri.lengths, *tri.shape)
    real = np.isfinite(theta)
    assert real.sum() == n0
    th = theta[real]
    assert np.sort(np.abs(np.diff(np.sort(th)))).min() < 1e-4  # two modes about to merge
    w = np.exp(1j * th)
    d = tri.origin + s[real] * tri.direction
    u, v = tri.shape
    assert np.abs(np.abs(d + u * w - b_) - tri.lengths[0]).max() <= TOL_POS
    assert np.abs(np.abs(d + v * w - complex(0.5, -0.4)) - tri.lengths[1]).max() <= TOL_POS
    k = scene.solve(np.array([phi_d, lo]))
    assert k.conditioning["tri"][-1] < 1e-3 * k.conditioning["tri"][0]


def test_no_real_mode_names_the_intervals() -> None:
    drawn, phi_d, gamma = _branch_case()
    data = {"D": drawn["D"], "E": drawn["E"], "F": drawn["F"]}
    # the smoke instance with a longer crank: the triad cannot close over part of the turn
    scene = slider_scene(r=0.3, c=complex(0.5, -0.4), g=complex(-0.2, -0.3), gamma=gamma, drawn=data, phi_d=phi_d,
                         angle=0.1)
    phi = np.linspace(0, 2 * np.pi, 181)
    with pytest.raises(AssemblyError, match=r"group 'tri' has no real assembly mode \(slider triad\) for φ in \("):
        scene.solve(phi)
    k = scene.solve(phi, mask=True)
    assert 0 < k.valid.sum() < len(phi)
    assert not np.isnan(k.point("D").position[k.valid]).any()


def test_scene_errors() -> None:
    def scene(extra: dict, fixed: dict | None = None) -> dict:
        group = {"type": "slider_triad", "name": "t", "guide": {"through": "G", "angle": 0.0}, "ends": ["B", "C"],
                 "points": ["D", "E", "F"], "lengths": [0.6, 0.6], "angle": 1.0,
                 "shape": {"D": [0, 0], "E": [0.3, 0], "F": [0.1, 0.3]}}
        return {"scene": "e", "units": {"length": "m", "angle": "rad"},
                "fixed": fixed or {"O": [0, 0], "G": [0.5, 0.0], "C": [0.23, 0.05]},
                "groups": [{"type": "crank", "name": "crank", "center": "O", "point": "B", "length": 0.1},
                           {**group, **extra}], "outputs": {"points": ["D"]}}
    with pytest.raises(SceneError, match=r"guide\.through: the guide is fixed; 'B' is not a fixed point"):
        build(scene({"guide": {"through": "B"}}))
    with pytest.raises(SceneError, match=r"lengths: must be \[\|BE\|, \|CF\|\]"):
        build(scene({"lengths": [0.6, 0.6, 0.6]}))
    with pytest.raises(SceneError, match=r"three points are on one line"):
        build(scene({"shape": {"D": [0, 0], "E": [1, 0], "F": [2, 0]}}))
    with pytest.raises(SceneError, match=r"slider_triad 't' reads only fixed points \(G, C\)|reads only fixed points"):
        build(scene({"ends": ["G", "C"]}))


def test_ticks_follow_by_newton_and_agree_with_the_sweep() -> None:
    """Tick by tick (1e-3 rad apart) the root is Newton's from the predicted one — every root
    (the eigenvalues) only at the first tick and while the compiled instant is traced (its eager
    samples) — and each tick's values are the sweep's to round-off."""
    from unittest import mock

    import solver
    from solver.groups import _slider_triad_tick

    scene = solver.load_scene("slider_triad_press")
    phi = np.arange(0.0, 0.3, 1e-3)
    sweep = scene.solve(phi)
    calls = []
    real = _slider_triad_tick.slider_roots

    def spy(*args: Any, **kw: Any) -> Any:
        calls.append(1)
        return real(*args, **kw)
    with mock.patch.object(_slider_triad_tick, "slider_roots", spy):
        for i, p in enumerate(phi):
            k = scene.solve(float(p))
            assert np.abs(np.asarray(k.point("F").position) - sweep.point("F").position[i]).max() <= 1e-14
            assert abs(float(k.joint("ram").velocity) - sweep.joint("ram").velocity[i]) <= 1e-12
            if i == 10:
                calls.clear()
    assert not calls, len(calls)


@pytest.mark.parametrize("i", [0, 3, 7, 11])
def test_reference_in_a_dense_sweep_through_the_anchors_shortcut(i: int) -> None:
    """0.05° apart a sweep takes the anchors' shortcut (solver.groups._slider_triad_sweep): the
    same accuracy at the reference's φ, and the same root as the full path at every sample."""
    case = _cases()[i]
    size = _size(case)
    k, full, where, calls = dense_sweep(_scene, case)
    assert calls == [True]
    assert_dense_match(k, full, where, case["samples"], size)


def _spans_taken(scene: Any, phi: np.ndarray) -> tuple[Any, list[tuple[int, bool]]]:
    """The scene solved over ``phi``, and each anchors' stride the shortcut tried with its verdict."""
    from unittest import mock

    from solver.groups import _slider_triad_sweep

    seen: list[tuple[int, bool]] = []
    real = _slider_triad_sweep._through_anchors

    def spy(group: Any, step: Any, stride: int, *rest: Any) -> Any:
        out = real(group, step, stride, *rest)
        seen.append((stride, out is not None))
        return out
    with mock.patch.object(_slider_triad_sweep, "_through_anchors", spy):
        k = scene.solve(phi)
    return k, seen


def test_a_turn_of_the_shipped_press_takes_the_wide_anchors() -> None:
    """3600 samples over a turn: anchors SPANS[0] apart, two Newton steps from the quintic
    interpolation and no further step anywhere; the same roots as every sample's eigenvalues."""
    from unittest import mock

    import solver
    from solver.groups import _slider_triad_math, _slider_triad_sweep

    scene = solver.load_scene("slider_triad_press")
    phi = np.linspace(0.0, 2.0 * np.pi, 3600)
    steps: list[int] = []
    real = _slider_triad_math.slider_polish

    def spy(*args: Any, **kw: Any) -> Any:
        if np.size(args[1]) == phi.size or kw["steps"] == _slider_triad_sweep.EXTRA_STEPS:
            steps.append(kw["steps"])
        return real(*args, **kw)
    with mock.patch.object(_slider_triad_sweep, "slider_polish", spy):
        k, seen = _spans_taken(scene, phi)
    assert seen == [(int(_slider_triad_sweep.SPANS[0] / (phi[1] - phi[0])), True)]
    assert steps == [_slider_triad_sweep.SWEEP_STEPS]
    with mock.patch.object(_slider_triad_sweep, "fast_sweep", lambda *a, **kw: None):
        full = scene.solve(phi)
    for name in "DEF":
        assert np.abs(k.point(name).position - full.point(name).position).max() <= TOL_POS, name
        assert np.abs(k.point(name).velocity - full.point(name).velocity).max() <= TOL_VEL, name
    np.testing.assert_allclose(k.joint("ram").position, full.joint("ram").position, rtol=0, atol=TOL_POS)


def test_a_shortcut_refused_at_its_determinant_check_tries_the_narrower_anchors() -> None:
    """Refused at the group's determinant check (once its analogs are in), the sweep tries the
    next span of SPANS before every sample's eigenvalues."""
    from unittest import mock

    import solver
    from solver.groups import _slider_triad_sweep

    scene = solver.load_scene("slider_triad_press")
    phi = np.linspace(0.0, 2.0 * np.pi, 3600)
    real = _slider_triad_sweep.Shortcut.holds
    verdicts: list[bool] = []

    def holds(self: Any, det: np.ndarray) -> bool:
        ok = real(self, det) and bool(verdicts)  # the first one refused
        verdicts.append(ok)
        return ok
    with mock.patch.object(_slider_triad_sweep.Shortcut, "holds", holds):
        k, seen = _spans_taken(scene, phi)
    pitch = phi[1] - phi[0]
    assert verdicts == [False, True]
    assert seen == [(int(span / pitch), True) for span in _slider_triad_sweep.SPANS]
    full = scene.solve(phi)
    assert np.abs(k.point("F").position - full.point("F").position).max() <= TOL_POS


#: Random slider triads swept in the test below (kept small for CI's time budget).
RANDOM_SWEEPS = 16


def test_random_slider_triads_the_shortcut_gives_the_full_path_s_roots_and_refusals() -> None:
    """Random drawn slider triads (seeded), swept over half a radian to a turn around the drawn
    input: wherever the full path (every sample's roots and the branch rule) solves, the sweep
    with its anchors' shortcut gives the same roots (≤ 1e-12 of the size; analogs ≤ 1e-9), and
    where the full path refuses (no real root, a mode jump) so does the sweep; the shortcut is
    taken often."""
    from unittest import mock

    from solver.groups import _slider_triad_sweep

    rng = np.random.default_rng(28)
    taken = solved = 0
    for _ in range(RANDOM_SWEEPS):
        r = float(rng.uniform(0.05, 0.2))
        c, g = (complex(*rng.uniform(-0.8, 0.8, 2)) for _ in range(2))
        gamma = float(rng.uniform(0.0, np.pi))
        drawn = {"D": g + float(rng.uniform(-0.5, 0.5)) * complex(np.exp(1j * gamma)),
                 "E": complex(*rng.uniform(-0.8, 0.8, 2)), "F": complex(*rng.uniform(-0.8, 0.8, 2))}
        phi_d = float(rng.uniform(0.0, 2.0 * np.pi))
        b = r * complex(np.exp(1j * phi_d))
        d, e, f = drawn["D"], drawn["E"], drawn["F"]
        if min(abs(e - b), abs(f - c), abs(e - d), abs(f - e), abs(d - f)) < 0.05:
            continue
        span = float(rng.choice([0.5, 1.0, 2.0 * np.pi]))
        phi = np.linspace(phi_d - span / 2, phi_d + span / 2, 1200)
        scene = slider_scene(r=r, c=c, g=g, gamma=gamma, drawn=drawn, phi_d=phi_d)
        try:
            k, seen = _spans_taken(scene, phi)
        except AssemblyError:
            k, seen = None, []
        try:
            with mock.patch.object(_slider_triad_sweep, "fast_sweep", lambda *a, **kw: None):
                full = slider_scene(r=r, c=c, g=g, gamma=gamma, drawn=drawn, phi_d=phi_d).solve(phi)
        except AssemblyError:
            full = None
        assert (k is None) == (full is None)
        if full is None:
            continue
        solved += 1
        taken += any(ok for _, ok in seen)
        size = r + max(abs(c), abs(g)) + 0.5 + max(abs(e - b), abs(f - c))
        for name in "DEF":
            got, ref = k.point(name), full.point(name)
            assert np.abs(got.position - ref.position).max() <= TOL_POS * size, name
            assert np.abs(got.velocity - ref.velocity).max() <= TOL_VEL * size, name
    assert solved >= RANDOM_SWEEPS // 4 and taken >= 0.8 * solved, (solved, taken)


#: Two slider triads drawn where two of their modes share θ (found by a seeded search; below):
#: (slide apart δ, E's and F's offsets across the guide t_E, t_F, C, D), the crank at φ = 0.7.
SHARED = [(0.4, 0.35, -0.2, complex(-0.09, -0.69), complex(-0.21, 0.72)),   # these two modes only
          (0.37, -0.31, 0.29, complex(0.28, 0.29), complex(-0.06, -0.44))]  # and four more
PHI_SHARED = 0.7


def _shared(case: tuple[float, float, float, complex, complex], mode: int) -> tuple[dict[str, complex], Any]:
    """Two modes of one θ by construction: the guide vertical through D, mode 2 mode 1 slid up by δ
    (D, E, F all + jδ); B (the crank pin at φ = 0.7) on the perpendicular bisector of E₁E₂ (E₁ = B
    − t_E − jδ/2), C on that of F₁F₂ (F₁ = C − t_F − jδ/2), so that |BE| and |CF| are the same in
    both: the two circles' quadratics in s are one there (N = Dn = 0). The scene drawn in ``mode``."""
    delta, t_e, t_f, c, d = case
    b = 0.1 * complex(math.cos(PHI_SHARED), math.sin(PHI_SHARED))
    up = 0.0 if mode == 1 else delta * 1j
    drawn = {"D": d + up, "E": b - t_e - 0.5j * delta + up, "F": c - t_f - 0.5j * delta + up}
    return drawn, slider_scene(r=0.1, c=c, g=d, gamma=math.pi / 2, drawn=drawn, phi_d=PHI_SHARED)


@pytest.mark.parametrize("mode", [1, 2])
@pytest.mark.parametrize("case", range(len(SHARED)))
def test_two_modes_of_one_theta_the_drawn_one_is_returned_and_followed(case: int, mode: int) -> None:
    """Both modes of one θ are roots (the polynomial's double root polished from both roots of the
    quadratic in s); the mode rule names the drawn one (nearest the drawn pose: the drawn slide
    tells them apart) on every path, and a sweep through the shared pose follows it continuously
    (the full path: the anchors' shortcut refuses next to a θ so close to another), with its grid
    through that pose or not; ticks from the drawn input outwards follow it too."""
    from unittest import mock

    from solver.groups import _slider_triad_sweep

    drawn, scene = _shared(SHARED[case], mode)
    delta, c_ = SHARED[case][0], SHARED[case][3]
    tri = next(grp for grp in scene.plan.groups if grp.kind == "slider_triad")
    theta, s = slider_roots(tri.origin, tri.direction, 0.1 * np.exp(1j * PHI_SHARED), c_, tri.lengths, *tri.shape)
    real = np.isfinite(theta)
    assert real.sum() == (2 if case == 0 else 6)
    pair = np.flatnonzero(np.abs(theta - tri.angle) <= 1e-12)
    assert len(pair) == 2 and abs(abs(s[pair[0]] - s[pair[1]]) - delta) <= 1e-12
    assert tri.slide0 == pytest.approx(0.0 if mode == 1 else delta, abs=1e-15)
    want = np.array([drawn["D"].real, drawn["D"].imag])
    np.testing.assert_allclose(scene.solve(np.array([PHI_SHARED])).point("D").position[0], want, atol=1e-14)
    np.testing.assert_allclose(np.asarray(_shared(SHARED[case], mode)[1].solve(PHI_SHARED).point("D").position),
                               want, atol=1e-14)  # one instant (compiled)
    for shift in (0.0, 0.37e-3):  # the grid through the shared pose, and past it
        phi = np.linspace(PHI_SHARED - 0.3, PHI_SHARED + 0.3, 601) + shift
        k = scene.solve(phi)
        with mock.patch.object(_slider_triad_sweep, "fast_sweep", lambda *a, **kw: None):
            full = _shared(SHARED[case], mode)[1].solve(phi)
        assert np.abs(k.point("D").position - full.point("D").position).max() <= TOL_POS
        slide = k.joint("s").position
        assert np.abs(np.diff(slide)).max() < 2e-4 and np.abs(np.diff(k.joint("ternary").position)).max() < 2e-4
        i = int(np.argmin(np.abs(phi - PHI_SHARED)))
        assert abs(slide[i] - tri.slide0) < 1e-3  # the drawn mode, not the other one δ away
        e_ = k.point("E").position @ [1, 1j]
        assert np.abs(np.abs(e_ - 0.1 * np.exp(1j * phi)) - tri.lengths[0]).max() <= 1e-14
        assert np.abs(np.abs((k.point("F").position @ [1, 1j]) - c_) - tri.lengths[1]).max() <= 1e-14
    phi = np.linspace(PHI_SHARED - 0.3, PHI_SHARED + 0.3, 601)
    ticks = []
    for part in (phi[300::-1], phi[300:]):  # from the drawn input outwards, each way a fresh scene
        tick = _shared(SHARED[case], mode)[1]
        ticks.append([float(tick.solve(float(p)).joint("s").position) for p in part])
    got = np.array(ticks[0][::-1] + ticks[1][1:])
    assert np.abs(got - scene.solve(phi).joint("s").position).max() <= 1e-13


def test_a_sweep_longer_than_one_block_follows_its_mode_across_blocks() -> None:
    """The scene solves 8192 samples a block: the second block continues the first's root."""
    import solver

    scene = solver.load_scene("slider_triad_press")
    phi = np.linspace(0.0, 4 * np.pi, 9000)
    k = scene.solve(phi)
    np.testing.assert_allclose(k.point("D").position[:4000], scene.solve(phi[:4000]).point("D").position,
                               rtol=0.0, atol=1e-14)
    again = scene.solve(phi[8000:] - 2 * np.pi).point("D").position  # the same crank angles a turn earlier
    np.testing.assert_allclose(k.point("D").position[8000:], again, atol=1e-12)
    assert np.abs(np.diff(k.joint("ternary").position)).max() < 0.05


def test_two_inputs_jacobian_and_hessian_against_central_differences() -> None:
    """Two cranks drive B and C: the slider triad's exact J and H (solver.multi's directional
    jets through the group's linear system) against central differences of its positions."""
    d, e, f = complex(-0.45, -0.8), complex(-0.39, 0.09), complex(-0.06, 0.3)
    c0, p = complex(0.39, 0.5), complex(0.34, 0.5)
    scene = build({
        "scene": "two_inputs", "units": {"length": "m", "angle": "rad"},
        "fixed": {"O": [0, 0], "P": [p.real, p.imag], "G": [-0.45, -0.49]},
        "groups": [{"type": "crank", "name": "c1", "center": "O", "point": "B", "length": 0.1},
                   {"type": "crank", "name": "c2", "center": "P", "point": "C", "length": 0.05},
                   {"type": "slider_triad", "name": "t", "guide": {"through": "G", "angle": math.pi / 2},
                    "ends": ["B", "C"], "points": ["D", "E", "F"], "lengths": [abs(e - 0.1), abs(f - c0)],
                    "shape": {k: [z.real, z.imag] for k, z in zip("DEF", (d, e, f))},
                    "angle": float(np.angle(e - d)), "slide": "s"}],
        "outputs": {"points": ["E", "F"], "joints": ["s"]},
    })
    q = np.stack([np.linspace(0.0, 0.4, 21), np.linspace(0.0, 0.3, 21)], axis=1)
    k = scene.solve(q)
    h = 1e-5
    for i in range(2):
        dq = np.zeros(2)
        dq[i] = h
        kp, km = scene.solve(q + dq), scene.solve(q - dq)
        for name in "EF":
            fd = (kp.point(name).position - km.point(name).position) / (2 * h)
            assert np.abs(k.point(name).jacobian[..., i] - fd).max() <= TOL_FD
            fd2 = (kp.point(name).jacobian - km.point(name).jacobian) / (2 * h)
            assert np.abs(k.point(name).hessian[..., i] - fd2).max() <= TOL_FD
        fds = (kp.joint("s").position - km.joint("s").position) / (2 * h)
        assert np.abs(k.joint("s").jacobian[..., i] - fds).max() <= TOL_FD
    one = scene.solve((0.2, 0.15))  # one instant of two inputs (the per-tick path): the sweep's row
    np.testing.assert_allclose(np.asarray(one.point("E").jacobian), k.point("E").jacobian[10], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.asarray(one.point("E").hessian), k.point("E").hessian[10], rtol=0, atol=1e-11)


@pytest.mark.parametrize("seed", range(4))
def test_both_binary_links_on_one_pivot_drop_the_degree_to_four(seed: int) -> None:
    """B = C: w³·G's leading and constant coefficients vanish (conj(B − C) = 0), the polynomial
    has degree 4 in w (DEGREE_DROP): every mode still found (brute force), the drawn one to round-off."""
    rng = np.random.default_rng(50 + seed)
    o, e, b_, _, _, u, v, theta = _random_instance(rng)
    d = o + rng.uniform(-0.8, 0.8) * e
    w = np.exp(1j * theta)
    lengths = (abs(d + u * w - b_), abs(d + v * w - b_))
    coef = slider_coefficients(o, e, b_, b_, lengths, u, v)
    size = abs(b_ - o) * 2 + sum(lengths) + abs(u) + abs(v)
    assert abs(coef[6]) <= 1e-15 * size**4 and abs(coef[0]) <= 1e-15 * size**4  # rounding only
    got, _ = slider_roots(o, e, b_, b_, lengths, u, v)
    got = got[np.isfinite(got)]
    want = _brute_modes(o, e, b_, b_, lengths, u, v, rng)
    assert len(got) == len(want) <= 4
    np.testing.assert_allclose(np.sort(got), want, atol=1e-8)
    assert np.min(np.abs(got - theta)) <= 1e-13
