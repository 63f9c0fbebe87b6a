"""Independent 50-digit reference kinematics of the shipped seed scenes (mpmath only).

This module never imports the solver. Positions come from the closed-form geometry of each
mechanism (the contract in issue 2 and docs/architecture.md), evaluated in mpmath at
``mp.dps = 50``; the velocity and acceleration analogs d/dφ and d²/dφ² come from mpmath's
high-precision numerical differentiation ``mp.diff`` of those position functions. That route
shares nothing with the solver's analytic derivatives, so agreement is evidence for both.

Run ``python tests/reference/mp_reference.py`` to rewrite ``tests/data/reference_<scene>.json``,
``--check`` to regenerate in memory and compare with the stored files instead.

Every φ in the data is an exactly representable binary64 number: its string is its exact value
rounded to 50 significant digits, so ``float(s)`` recovers the very double the reference was
computed at. The module also holds the exact maxima of seed 001's Tables 1–2.
"""

from __future__ import annotations

import argparse
import datetime
import json
import sys
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

import mpmath
from mpmath import mp, mpf

__all__ = [
    "DPS",
    "FIVE_BAR",
    "build_five_bar_reference",
    "five_bar_grid",
    "SCENES",
    "SceneSpec",
    "build_reference",
    "main",
    "reference_phi",
    "self_check",
    "spherical_alpha",
    "spherical_max_cage_epsilon",
    "spherical_max_cage_omega",
    "spherical_max_psi_ddot",
]

DPS = 50
"""Decimal digits of working precision (mp.dps)."""
DIGITS = 50
"""Significant digits written for every number."""
MOTION_OMEGA = "2.5"
MOTION_EPSILON = "-0.7"
IRREGULAR_PHI = (0.1234567, 1e-6, -0.5, 7.0, 3.14159, 100.0)
"""Angles (rad) beyond the 7.5° grid: small, negative, past 2π, near π, large."""
SELF_CHECK_TOL = mpf("1e-40")

DATA_DIR = Path(__file__).resolve().parent.parent / "data"
SCRIPT = "tests/reference/mp_reference.py"

Vec = tuple[mpf, ...]


@dataclass(frozen=True)
class Geometry:
    """One configuration: output points (2-D or 3-D) and output joints.

    ``angles`` maps an angle joint to the vector whose atan2 it is; ``slides`` maps a
    length joint to its value (m).
    """

    points: dict[str, Vec]
    angles: dict[str, tuple[mpf, mpf]]
    slides: dict[str, mpf]


@dataclass(frozen=True)
class SceneSpec:
    name: str
    source: str
    dim: int
    input_joint: str
    scale_length: str
    """Largest link length (m): the scale of point analogs for relative tolerances."""
    geometry: Callable[[mpf], Geometry]
    points: tuple[str, ...]
    joints: tuple[str, ...]


def _unit(x: mpf, y: mpf) -> tuple[mpf, mpf]:
    n = mp.hypot(x, y)
    return x / n, y / n


# --- the mechanisms (constants are built inside, at the working precision of the call) ---


def harvester_finger(phi: mpf) -> Geometry:
    """Seed 000, illustrative dims: crank OB, slotted link AC through B, points C, E on it."""
    ax, ay = mpf("0.04"), mpf("-0.03")
    l_ob, l_ac, l_ae = mpf("0.20"), mpf("0.30"), mpf("0.22")
    bx, by = l_ob * mp.cos(phi), l_ob * mp.sin(phi)
    ux, uy = _unit(bx - ax, by - ay)
    c = (ax + l_ac * ux, ay + l_ac * uy)
    e = (ax + l_ae * ux, ay + l_ae * uy)
    return Geometry({"B": (bx, by), "C": c, "E": e}, {"finger": (c[0] - ax, c[1] - ay)}, {})


def _four_bar(phi: mpf, mode: int) -> Geometry:
    """Seed 003: crank OA, coupler AB, rocker CB; B by circle intersection, mode M = ±1."""
    oa, ab, cb = mpf("0.1"), mpf("0.4"), mpf("0.3")
    cx, cy = mpf("0.4"), mpf(0)
    ax, ay = oa * mp.cos(phi), oa * mp.sin(phi)
    d = mp.hypot(cx - ax, cy - ay)
    ex, ey = (cx - ax) / d, (cy - ay) / d
    along = (ab**2 - cb**2 + d**2) / (2 * d)
    across = mp.sqrt(ab**2 - along**2)
    # cross(B - A, C - A) = -s * across * d for B = A + along*e + s*across*perp(e), perp(e) = (-ey, ex);
    # M = +1 (A -> B -> C counter-clockwise, cross > 0) therefore takes s = -1.
    s = -mode
    bx = ax + along * ex - s * across * ey
    by = ay + along * ey + s * across * ex
    return Geometry(
        {"A": (ax, ay), "B": (bx, by)},
        {"coupler": (bx - ax, by - ay), "rocker": (bx - cx, by - cy)},
        {},
    )


def four_bar(phi: mpf) -> Geometry:
    return _four_bar(phi, +1)


def four_bar_crossed(phi: mpf) -> Geometry:
    return _four_bar(phi, -1)


def slider_crank(phi: mpf) -> Geometry:
    """Crank OA; slider B on the line y = 0.01, to the right of A."""
    oa, ab, guide_y = mpf("0.05"), mpf("0.20"), mpf("0.01")
    ax, ay = oa * mp.cos(phi), oa * mp.sin(phi)
    bx = ax + mp.sqrt(ab**2 - (guide_y - ay) ** 2)
    return Geometry({"A": (ax, ay), "B": (bx, guide_y)}, {}, {"slider": bx})


def spherical_alpha() -> mpf:
    """Seed 001: angle between the groove plane and the shaft axis, 40°, at working precision."""
    return mp.pi * 40 / 180


def spherical_converter(phi: mpf) -> Geometry:
    """Seed 001 (corrected): ψ = atan(sin φ / tan α); K = (0, R sin ψ, R cos ψ)."""
    radius = mpf("0.05")
    psi = mp.atan(mp.sin(phi) / mp.tan(spherical_alpha()))
    k = (mpf(0), radius * mp.sin(psi), radius * mp.cos(psi))
    return Geometry({"K": k}, {"cage": (mp.cos(psi), mp.sin(psi))}, {})


SCENES: dict[str, SceneSpec] = {
    spec.name: spec
    for spec in (
        SceneSpec(
            "harvester_finger",
            "seed 000 (illustrative dims)",
            2,
            "drum",
            "0.30",
            harvester_finger,
            ("B", "C", "E"),
            ("finger",),
        ),
        SceneSpec("four_bar", "seed 003, M = +1", 2, "crank", "0.4", four_bar, ("A", "B"), ("coupler", "rocker")),
        SceneSpec(
            "four_bar_crossed",
            "seed 003, M = -1",
            2,
            "crank",
            "0.4",
            four_bar_crossed,
            ("A", "B"),
            ("coupler", "rocker"),
        ),
        SceneSpec(
            "slider_crank", "RRP dyad, offset guide y = 0.01", 2, "crank", "0.20", slider_crank, ("A", "B"), ("slider",)
        ),
        SceneSpec(
            "spherical_converter",
            "seed 001 (corrected eq. 5, 13, 15)",
            3,
            "shaft",
            "0.05",
            spherical_converter,
            ("K",),
            ("cage",),
        ),
    )
}


# --- scalar functions of φ and their derivatives ---


def _point_component(spec: SceneSpec, point: str, axis: int) -> Callable[[mpf], mpf]:
    return lambda t: spec.geometry(t).points[point][axis]


def _angle_near(spec: SceneSpec, joint: str, phi: mpf) -> Callable[[mpf], mpf]:
    """The joint angle on the branch continuous through φ, minus its value at φ.

    Measuring from the vector at φ keeps the function smooth where atan2 would jump at ±π, so
    mp.diff never straddles the branch cut.
    """
    vx0, vy0 = spec.geometry(phi).angles[joint]

    def relative(t: mpf) -> mpf:
        vx, vy = spec.geometry(t).angles[joint]
        return mp.atan2(vx0 * vy - vy0 * vx, vx0 * vx + vy0 * vy)

    return relative


def _slide(spec: SceneSpec, joint: str) -> Callable[[mpf], mpf]:
    return lambda t: spec.geometry(t).slides[joint]


def _jet(f: Callable[[mpf], mpf], phi: mpf, **options: object) -> tuple[mpf, mpf]:
    return mp.diff(f, phi, 1, **options), mp.diff(f, phi, 2, **options)


def _fmt(x: mpf) -> str:
    return mp.nstr(x, DIGITS, strip_zeros=False, min_fixed=-4, max_fixed=5)


def reference_phi() -> list[float]:
    """k·7.5° for k = 0..47 (each rounded to the nearest double), then IRREGULAR_PHI."""
    with mp.workdps(DPS):
        grid = [float(mp.pi * k / 24) for k in range(48)]
    return grid + list(IRREGULAR_PHI)


def _evaluate(spec: SceneSpec, phi: mpf) -> dict[str, dict[str, object]]:
    """Position, d/dφ and d²/dφ² of every output at one exact φ."""
    geometry = spec.geometry(phi)
    points: dict[str, object] = {}
    for name in spec.points:
        jets = [_jet(_point_component(spec, name, axis), phi) for axis in range(spec.dim)]
        points[name] = (geometry.points[name], tuple(j[0] for j in jets), tuple(j[1] for j in jets))
    joints: dict[str, object] = {}
    for name in spec.joints:
        if name in geometry.angles:
            vx, vy = geometry.angles[name]
            joints[name] = ("angle", mp.atan2(vy, vx), *_jet(_angle_near(spec, name, phi), phi))
        else:
            joints[name] = ("length", geometry.slides[name], *_jet(_slide(spec, name), phi))
    return {"points": points, "joints": joints}


def build_reference(name: str, phis: Sequence[float] | None = None, *, date: str | None = None) -> dict:
    """The JSON-ready reference of one scene (all numbers as 50-digit decimal strings)."""
    spec = SCENES[name]
    phis = reference_phi() if phis is None else list(phis)
    with mp.workdps(DPS):
        rows = [_evaluate(spec, mpf(p)) for p in phis]  # mpf(float) is exact
        points = {
            p: {
                key: [[_fmt(c) for c in row["points"][p][i]] for row in rows]
                for i, key in enumerate(("position", "d_dphi", "d2_dphi2"))
            }
            for p in spec.points
        }
        joints = {}
        for j in spec.joints:
            kind = rows[0]["joints"][j][0]
            joints[j] = {"kind": kind} | {
                key: [_fmt(row["joints"][j][i + 1]) for row in rows]
                for i, key in enumerate(("position", "d_dphi", "d2_dphi2"))
            }
        phi_strings = [_fmt(mpf(p)) for p in phis]
    when = date or datetime.date.today().isoformat()
    return {
        "provenance": (
            f"{SCRIPT} (mpmath {mpmath.__version__}, mp.dps={DPS}), {when}: positions from the closed-form "
            f"geometry of {name} ({spec.source}) evaluated in mpmath; analogs d/dphi and d2/dphi2 by mpmath's "
            "high-precision numerical differentiation mp.diff of the position functions, an independent route "
            "from the solver's analytic derivatives. phi values are exact binary64 numbers."
        ),
        "scene": name,
        "dim": spec.dim,
        "input_joint": spec.input_joint,
        "scale_length": spec.scale_length,
        "units": "m and rad; angle joints in (-pi, pi]; d_dphi per rad, d2_dphi2 per rad^2",
        "motion": {
            "omega": MOTION_OMEGA,
            "epsilon": MOTION_EPSILON,
            "law": "v = v_q*omega, a = a_q*omega^2 + v_q*epsilon (seed 000 eq. 11-12)",
        },
        "phi": phi_strings,
        "points": points,
        "joints": joints,
    }


# --- the five-bar (two inputs, issue 14): exact Jacobians and Hessians ---

FIVE_BAR = "five_bar"
FIVE_BAR_OMEGA = ("2", "-1.5")
FIVE_BAR_EPSILON = ("0.7", "3")
FIVE_BAR_DEGREES = tuple(range(40, 141, 10))
"""q1 and q2 on this grid (degrees, each rounded to the nearest double in rad): 11 × 11 samples."""
_FIVE_BAR_ORDERS = {"d_dq1": (1, 0), "d_dq2": (0, 1), "d2_dq1dq1": (2, 0), "d2_dq1dq2": (1, 1), "d2_dq2dq2": (0, 2)}


def five_bar(q1: mpf, q2: mpf) -> Geometry:
    """Generic five-bar: O1 = (0, 0), O2 = (0.2, 0); cranks 0.15 at angles q1, q2; distal links
    0.25 meeting at P on the left of A1 → A2 (above the line when A1 is left of A2)."""
    crank, distal, o2x = mpf("0.15"), mpf("0.25"), mpf("0.2")
    a1 = (crank * mp.cos(q1), crank * mp.sin(q1))
    a2 = (o2x + crank * mp.cos(q2), crank * mp.sin(q2))
    dx, dy = a2[0] - a1[0], a2[1] - a1[1]
    d = mp.hypot(dx, dy)
    h = mp.sqrt(distal**2 - (d / 2) ** 2)
    p = ((a1[0] + a2[0]) / 2 - h * dy / d, (a1[1] + a2[1]) / 2 + h * dx / d)
    return Geometry(
        {"P": p},
        {"left_distal": (p[0] - a1[0], p[1] - a1[1]), "right_distal": (p[0] - a2[0], p[1] - a2[1])},
        {"q1": q1, "q2": q2},
    )


def five_bar_grid() -> list[tuple[float, float]]:
    """(q1, q2) over FIVE_BAR_DEGREES², q1 the slow index (rad, exact binary64 values)."""
    with mp.workdps(DPS):
        angles = [float(mp.pi * deg / 180) for deg in FIVE_BAR_DEGREES]
    return [(a, b) for a in angles for b in angles]


def _five_bar_scalar(name: str, q0: tuple[mpf, mpf]) -> Callable[[mpf, mpf], mpf]:
    """One output coordinate as a function of (q1, q2); angles relative to their value at q0."""
    if name in ("left_distal", "right_distal"):
        vx0, vy0 = five_bar(*q0).angles[name]

        def relative(a: mpf, b: mpf) -> mpf:
            vx, vy = five_bar(a, b).angles[name]
            return mp.atan2(vx0 * vy - vy0 * vx, vx0 * vx + vy0 * vy)

        return relative
    if name in ("q1", "q2"):
        return lambda a, b: five_bar(a, b).slides[name]
    axis = {"P.x": 0, "P.y": 1}[name]
    return lambda a, b: five_bar(a, b).points["P"][axis]


def _five_bar_entry(name: str, q: tuple[mpf, mpf]) -> dict[str, mpf]:
    g = five_bar(*q)
    if name in ("left_distal", "right_distal"):
        vx, vy = g.angles[name]
        value = mp.atan2(vy, vx)
    elif name in ("q1", "q2"):
        value = g.slides[name]
    else:
        value = g.points["P"][{"P.x": 0, "P.y": 1}[name]]
    f = _five_bar_scalar(name, q)
    out = {"position": value}
    for key, order in _FIVE_BAR_ORDERS.items():
        out[key] = mp.diff(f, q, order)
    w = [mpf(x) for x in FIVE_BAR_OMEGA]
    e = [mpf(x) for x in FIVE_BAR_EPSILON]
    jac = (out["d_dq1"], out["d_dq2"])
    hess = ((out["d2_dq1dq1"], out["d2_dq1dq2"]), (out["d2_dq1dq2"], out["d2_dq2dq2"]))
    out["velocity"] = jac[0] * w[0] + jac[1] * w[1]
    quadratic = sum(w[i] * hess[i][j] * w[j] for i in range(2) for j in range(2))
    out["acceleration"] = jac[0] * e[0] + jac[1] * e[1] + quadratic
    return out


def build_five_bar_reference(samples: Sequence[tuple[float, float]] | None = None, *, date: str | None = None) -> dict:
    """The five-bar's reference: per sample (q1, q2), every output's value, its first and second
    partial derivatives in (q1, q2), and the real motion for ω = FIVE_BAR_OMEGA, ε = FIVE_BAR_EPSILON."""
    samples = five_bar_grid() if samples is None else [tuple(map(float, s)) for s in samples]
    names = ("P.x", "P.y", "q1", "q2", "left_distal", "right_distal")
    keys = ("position", *_FIVE_BAR_ORDERS, "velocity", "acceleration")
    with mp.workdps(DPS):
        rows = [{n: _five_bar_entry(n, (mpf(a), mpf(b))) for n in names} for a, b in samples]
        table = {n: {key: [_fmt(row[n][key]) for row in rows] for key in keys} for n in names}
        q_strings = [[_fmt(mpf(a)), _fmt(mpf(b))] for a, b in samples]
    when = date or datetime.date.today().isoformat()
    points = {"P": {key: [[x, y] for x, y in zip(table["P.x"][key], table["P.y"][key])] for key in keys}}
    joints = {
        n: {"kind": "angle" if n.endswith("distal") else "input angle"} | table[n]
        for n in ("q1", "q2", "left_distal", "right_distal")
    }
    return {
        "provenance": (
            f"{SCRIPT} (mpmath {mpmath.__version__}, mp.dps={DPS}), {when}: positions from the closed-form "
            "geometry of a generic five-bar (O1 = (0, 0), O2 = (0.2, 0) m, cranks 0.15 m, distal links 0.25 m, "
            "P on the left of A1 -> A2; illustrative dimensions, issue 14) evaluated in mpmath; first and second "
            "partial derivatives in (q1, q2) by mpmath's high-precision numerical differentiation mp.diff of the "
            "position functions, an independent route from the solver's jets. q values are exact binary64 numbers."
        ),
        "scene": FIVE_BAR,
        "dim": 2,
        "inputs": ["q1", "q2"],
        "scale_length": "0.25",
        "units": "m and rad; angle joints in (-pi, pi]; d_dqi per rad, d2_dqidqj per rad^2",
        "motion": {
            "omega": list(FIVE_BAR_OMEGA),
            "epsilon": list(FIVE_BAR_EPSILON),
            "law": "v = J*omega, a = J*epsilon + omega^T*H*omega",
        },
        "q": q_strings,
        "points": points,
        "joints": joints,
    }


# --- seed 001, Tables 1-2: exact maxima ---


def spherical_max_psi_ddot() -> tuple[mpf, mpf]:
    """(max |ψ''|, the φ in (0, π/2) where it occurs), in closed form.

    With t = tan²α and u = sin φ, |ψ''| = tan α · u (t + 2 − u²) / (t + u²)²; its derivative in u
    vanishes where u⁴ − 6(t + 1) u² + t (t + 2) = 0, whose smaller root in u² is the maximum.
    """
    alpha = spherical_alpha()
    tan_a = mp.tan(alpha)
    t = tan_a**2
    u2 = 3 * (t + 1) - mp.sqrt(9 * (t + 1) ** 2 - t * (t + 2))
    u = mp.sqrt(u2)
    return tan_a * u * (t + 2 - u2) / (t + u2) ** 2, mp.asin(u)


def _rpm_to_rad_s(rpm: float | str) -> mpf:
    return 2 * mp.pi * mpf(rpm) / 60


def spherical_max_cage_omega(rpm: float | str) -> mpf:
    """max ω_cage = ω / tan α (at φ = 0), ω the shaft speed from rpm."""
    return _rpm_to_rad_s(rpm) / mp.tan(spherical_alpha())


def spherical_max_cage_epsilon(rpm: float | str) -> mpf:
    """max |ε_cage| = ω² · max |ψ''| at constant shaft speed."""
    return _rpm_to_rad_s(rpm) ** 2 * spherical_max_psi_ddot()[0]


# --- independent checks of the generator itself ---


def self_check(phis: Iterable[float] | None = None) -> dict[str, mpf]:
    """Check the reference against facts it was not computed from; raise AssertionError if off.

    Returns the largest discrepancy found in each check (all should be < 1e-40).
    """
    phis = reference_phi() if phis is None else list(phis)
    worst: dict[str, mpf] = {}

    def note(key: str, value: mpf) -> None:
        worst[key] = max(worst.get(key, mpf(0)), abs(value))

    with mp.workdps(DPS):
        alpha = spherical_alpha()
        tan_a = mp.tan(alpha)
        sph = SCENES["spherical_converter"]
        fb = {m: SCENES[n] for m, n in ((+1, "four_bar"), (-1, "four_bar_crossed"))}
        for p in map(mpf, phis):
            s, c = mp.sin(p), mp.cos(p)
            # seed 001: digest's analytic ψ', ψ'' and the corrected eq. (5) for K
            d1, d2 = _jet(_angle_near(sph, "cage", p), p)
            den = tan_a**2 + s**2
            note("spherical psi'", d1 - tan_a * c / den)
            note("spherical psi''", d2 + tan_a * s * (tan_a**2 + s**2 + 2 * c**2) / den**2)
            k = sph.geometry(p).points["K"]
            dd = mp.sqrt(s**2 + mp.sin(alpha) ** 2 * c**2)
            note(
                "spherical K eq. (5)",
                mp.hypot(k[1] - mpf("0.05") * s * mp.cos(alpha) / dd, k[2] - mpf("0.05") * mp.sin(alpha) / dd),
            )
            # crank point: analytic derivatives of A = OA (cos φ, sin φ)
            for axis, (v1, v2) in enumerate(((-s, -c), (c, -s))):
                j1, j2 = _jet(_point_component(fb[1], "A", axis), p)
                note("crank A analogs", mpf("0.1") * v1 - j1)
                note("crank A analogs", mpf("0.1") * v2 - j2)
            # seed 003: loop closure and assembly mode sign
            for mode, spec in fb.items():
                g = spec.geometry(p).points
                (ax, ay), (bx, by) = g["A"], g["B"]
                note("four-bar closure", mp.hypot(bx - ax, by - ay) - mpf("0.4"))
                note("four-bar closure", mp.hypot(bx - mpf("0.4"), by) - mpf("0.3"))
                cross = (bx - ax) * (0 - ay) - (by - ay) * (mpf("0.4") - ax)
                assert mp.sign(cross) == mode, f"assembly mode {mode} violated at phi={p}"
            # mp.diff converged: another step size gives the same analogs
            f = _point_component(SCENES["harvester_finger"], "C", 1)
            h = mp.ldexp(1, -mp.prec - 40)
            a1, a2 = _jet(f, p)
            b1, b2 = _jet(f, p, h=h)
            note("mp.diff step independence", max(abs(a1 - b1), abs(a2 - b2)))
        # the five-bar: loop closure, the differentiated closure (P - A1).(dP/dq1 - dA1/dq1) = 0,
        # and mp.diff's mixed partial independent of its step
        for a, b in five_bar_grid()[::17]:
            q = (mpf(a), mpf(b))
            p5 = five_bar(*q).points["P"]
            a1 = (mpf("0.15") * mp.cos(q[0]), mpf("0.15") * mp.sin(q[0]))
            note("five-bar closure", mp.hypot(p5[0] - a1[0], p5[1] - a1[1]) - mpf("0.25"))
            px, py = (_five_bar_scalar(n, q) for n in ("P.x", "P.y"))
            jx, jy = mp.diff(px, q, (1, 0)), mp.diff(py, q, (1, 0))
            note("five-bar differentiated closure", (p5[0] - a1[0]) * (jx + a1[1]) + (p5[1] - a1[1]) * (jy - a1[0]))
            step = mp.ldexp(1, -mp.prec - 40)
            note("five-bar mixed partial step", mp.diff(px, q, (1, 1)) - mp.diff(px, q, (1, 1), h=step))
        # seed 001 maximum of |ψ''|: closed form against a root of ψ''' = 0
        value, where = spherical_max_psi_ddot()

        def psi(t: mpf) -> mpf:
            return mp.atan(mp.sin(t) / tan_a)

        root = mp.findroot(lambda t: mp.diff(psi, t, 3), mpf("0.45"))
        note("max |psi''| location", root - where)
        note("max |psi''| value", abs(mp.diff(psi, root, 2)) - value)
    for key, value in worst.items():
        assert value < SELF_CHECK_TOL, f"self-check {key}: discrepancy {mp.nstr(value, 5)}"
    return worst


def _angle_margin(ref: dict) -> float:
    """Smallest distance (rad) of any reference angle from the ±π branch cut."""
    angles = [
        abs(abs(mpf(v)) - mp.pi)
        for joint in ref["joints"].values()
        if joint["kind"] == "angle"
        for v in joint["position"]
    ]
    return float(min(angles)) if angles else float("inf")


def _compare(stored: dict, fresh: dict, path: str = "") -> mpf:
    """Largest absolute difference between two references (provenance date ignored)."""
    if isinstance(stored, dict):
        keys = set(stored) | set(fresh)
        return max((_compare(stored[k], fresh[k], f"{path}/{k}") for k in keys if k != "provenance"), default=mpf(0))
    if isinstance(stored, list):
        assert len(stored) == len(fresh), f"{path}: length differs"
        return max((_compare(a, b, path) for a, b in zip(stored, fresh, strict=True)), default=mpf(0))
    if isinstance(stored, str) and stored[:1] in "-0123456789":
        return abs(mpf(stored) - mpf(fresh))
    assert stored == fresh, f"{path}: {stored!r} != {fresh!r}"
    return mpf(0)


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=DATA_DIR, help="folder for reference_<scene>.json")
    parser.add_argument("--check", action="store_true", help="compare with the stored files, write nothing")
    parser.add_argument("scenes", nargs="*", default=[*SCENES, FIVE_BAR], help="scene names (default: all)")
    args = parser.parse_args(argv)
    mp.dps = DPS
    worst = self_check()
    print("self-check, largest discrepancies:", {k: mp.nstr(v, 3) for k, v in worst.items()})
    status = 0
    for name in args.scenes:
        ref = build_five_bar_reference() if name == FIVE_BAR else build_reference(name)
        target = args.out / f"reference_{name}.json"
        if args.check:
            diff = _compare(json.loads(target.read_text()), ref)
            ok = diff < SELF_CHECK_TOL
            status |= not ok
            print(f"{target}: max difference {mp.nstr(diff, 3)} {'ok' if ok else 'MISMATCH'}")
            continue
        text = json.dumps(ref, indent=1) + "\n"
        target.write_text(text)
        print(
            f"{target}: {len(ref.get('phi', ref.get('q', [])))} samples, {len(text) / 1024:.0f} KiB, "
            f"angle margin from ±pi {_angle_margin(ref):.3g} rad"
        )
    return status


if __name__ == "__main__":
    sys.exit(main())
