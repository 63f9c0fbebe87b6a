"""Independent 50-digit references for the slider triad's two other one-prismatic variants
(solver.groups.slider_triad): the swinging block (a block pinned at A slides along a line fixed in
the ternary link) with A fixed or moving, and the guide carried by a moving link. mpmath only.

Never imports the solver. Each case is a crank O–B (length r, angle φ) with a point H attached to
it (distance ρ_h at the angle β_h from O→B), a fixed pivot C, the ternary link D, E, F (E–B and
F–C binary links, their lengths the drawn distances) and

* ``swing_fixed``: the block at the fixed point A on the line through D at the angle α from D→E,
  offset δ along its normal: A = D + (p + s·e_t)·w, p = δ·j·e^{jα}, e_t = e^{jα};
* ``swing_moving``: the same with the block at H (a moving pivot);
* ``carried``: D on the guide carried by the crank link O–B: through O (offset δ) at the angle γ
  from O→B, D = O + δ·j·e_k + s·e_k, e_k = e^{j(φ + γ)}.

Every scene input is a double (drawn at random, seeded, then rounded: the test builds the same
scene from the stored decimal strings exactly). The loop |E − B| = b, |F − C| = c is solved by
``mpmath.findroot`` in (s, θ) from the drawn pose, continued in steps of 0.25° to ±30° (linear
extrapolation of the two previous solutions); the velocity analogs solve J·x' = −∂f/∂φ with J and
∂f/∂φ by ``mpmath.diff`` of the loop functions (numerical differentiation at 50 digits: independent
of the solver's hand-derived linear system). Every 5° is stored with the case's geometry in
tests/data/reference_slider_triad_variants.json. A case whose normalised determinant
|det J|/(b·c·(|R_E| + |R_F|)) falls below 0.02 or whose θ swings by more than 0.05 rad in a step
is skipped.

Run ``python tests/reference/slider_triad_variants_mp.py`` to rewrite the file.
"""

from __future__ import annotations

import datetime
import json
import random
import sys
from pathlib import Path

import mpmath
from mpmath import mp, mpf

DPS = 50
STEP_DEG = 0.25
SPAN_DEG = 30
STORE_EVERY = 20  # steps: 5°
PER_KIND = 4
KINDS = ("swing_fixed", "swing_moving", "carried")
SEED = 2877
MIN_COND = 0.02
OUT = Path(__file__).resolve().parents[1] / "data" / "reference_slider_triad_variants.json"
J = mpmath.mpc(0, 1)


def _cis(t: mpf) -> mpmath.mpc:
    return mpmath.mpc(mpmath.cos(t), mpmath.sin(t))


def _d(x: float | mpf) -> mpf:
    return mpf(float(x))


def _z(z: complex | mpmath.mpc) -> mpmath.mpc:
    return mpmath.mpc(float(z.real), float(z.imag))


def _case(rng: random.Random, kind: str) -> dict | None:
    u01 = rng.uniform
    cs: dict = {"kind": kind, "r": _d(u01(0.05, 0.15)), "rho_h": _d(u01(0.2, 0.4)), "beta_h": _d(u01(-3, 3)),
                "C": _z(complex(u01(-0.6, 0.6), u01(-0.6, 0.6))), "phi_d": _d(u01(-3.1, 3.1)),
                "angle": _d(u01(-1.5, 1.5)), "offset": _d(u01(-0.1, 0.1)), "s_d": _d(u01(-0.3, 0.3))}
    d, e, f = (_z(complex(u01(-0.6, 0.6), u01(-0.6, 0.6))) for _ in range(3))
    if min(abs(e - d), abs(f - e), abs(f - d)) < 0.1:
        return None
    theta = mpmath.arg(e - d)
    w = _cis(theta)
    if kind.startswith("swing"):
        et = _cis(cs["angle"])
        a = d + (cs["offset"] * J * et + cs["s_d"] * et) * w
        if kind == "swing_fixed":
            cs["A"] = _z(a)
            cs["O"] = _z(complex(u01(-0.3, 0.3), u01(-0.3, 0.3)))
        else:  # the crank's centre placed so that H is at A in the drawn pose
            cs["O"] = _z(a - cs["rho_h"] * _cis(cs["phi_d"] + cs["beta_h"]))
    else:
        ek = _cis(cs["phi_d"] + cs["angle"])
        cs["O"] = _z(d - cs["offset"] * J * ek - cs["s_d"] * ek)
    b = cs["O"] + cs["r"] * _cis(cs["phi_d"])
    cs["lengths"] = (_d(abs(e - b)), _d(abs(f - cs["C"])))
    if min(cs["lengths"]) < 0.1:
        return None
    cs.update(D=d, E=e, F=f, u=abs(e - d), v=(f - d) * _cis(-theta), theta=theta)
    if abs(cs["v"].imag) < 0.05:
        return None
    return cs


def _pivot(cs: dict, phi: mpf) -> mpmath.mpc:
    return cs["A"] if cs["kind"] == "swing_fixed" else cs["O"] + cs["rho_h"] * _cis(phi + cs["beta_h"])


def _points(cs: dict, phi: mpf, s: mpf, t: mpf) -> tuple[mpmath.mpc, mpmath.mpc, mpmath.mpc]:
    w = _cis(t)
    if cs["kind"].startswith("swing"):
        et = _cis(cs["angle"])
        d = _pivot(cs, phi) - (cs["offset"] * J * et + s * et) * w
    else:
        ek = _cis(phi + cs["angle"])
        d = cs["O"] + cs["offset"] * J * ek + s * ek
    return d, d + cs["u"] * w, d + cs["v"] * w


def _loop(cs: dict, phi: mpf, s: mpf, t: mpf) -> list[mpf]:
    b_ = cs["O"] + cs["r"] * _cis(phi)
    lb, lc = cs["lengths"]
    _, e, f = _points(cs, phi, s, t)
    return [abs(e - b_) ** 2 - lb**2, abs(f - cs["C"]) ** 2 - lc**2]


def _velocity(cs: dict, phi: mpf, x: list) -> tuple[mpf, mpf, mpf]:
    """(s', θ', normalised |det|) from J·x' = −∂f/∂φ, every derivative by mpmath.diff."""
    s, t = x
    cols = [[mpmath.diff(lambda y, i=i: _loop(cs, phi, y, t)[i], s) for i in range(2)],
            [mpmath.diff(lambda y, i=i: _loop(cs, phi, s, y)[i], t) for i in range(2)]]
    dphi = [mpmath.diff(lambda y, i=i: _loop(cs, y, s, t)[i], phi) for i in range(2)]
    mat = mpmath.matrix([[cols[0][0], cols[1][0]], [cols[0][1], cols[1][1]]])
    sol = mpmath.lu_solve(mat, mpmath.matrix([-dphi[0], -dphi[1]]))
    _, e, f = _points(cs, phi, s, t)
    base = _pivot(cs, phi) if cs["kind"].startswith("swing") else _points(cs, phi, s, t)[0]
    lb, lc = cs["lengths"]
    cond = abs(mpmath.det(mat)) / 4 / (lb * lc * (abs(e - base) + abs(f - base)))
    return sol[0], sol[1], cond


def continue_case(cs: dict) -> list[dict] | None:
    out = []
    for sign in (1, -1):
        x = [cs["s_d"], cs["theta"]]
        prev = list(x)
        for k in range(0, int(SPAN_DEG / STEP_DEG) + 1):
            phi = cs["phi_d"] + sign * mpmath.radians(k * STEP_DEG)
            start = [2 * x[i] - prev[i] for i in range(2)] if k > 1 else x
            try:
                sol = mpmath.findroot(lambda s, t, phi=phi: _loop(cs, phi, s, t), start,
                                      tol=mpf(10) ** (-2 * DPS + 10))
            except (ValueError, ZeroDivisionError):
                return None
            prev, x = x, [sol[0], sol[1]]
            if abs(x[1] - prev[1]) > 0.05:
                return None
            if k % STORE_EVERY == 0 and not (sign == -1 and k == 0):
                s1, t1, cond = _velocity(cs, phi, x)
                if cond < MIN_COND:
                    return None
                pts = _points(cs, phi, x[0], x[1])
                h = mpf(10) ** -20
                ahead = _points(cs, phi + h, x[0] + s1 * h, x[1] + t1 * h)
                back = _points(cs, phi - h, x[0] - s1 * h, x[1] - t1 * h)
                smp = {"phi": phi, "theta": x[1], "s": x[0], "dtheta": t1, "ds": s1}
                for name, p, pa, pb in zip("DEF", pts, ahead, back):
                    smp[name] = p
                    smp["d" + name] = (pa - pb) / (2 * h)  # the chain rule through (s, θ)(φ): exact to ~1e-40
                out.append(smp)
    return sorted(out, key=lambda s: s["phi"])


def _s(x: mpf) -> str:
    return mpmath.nstr(x, DPS, strip_zeros=False)


def _c(z: mpmath.mpc) -> list[str]:
    return [_s(z.real), _s(z.imag)]


def _r(x: mpf) -> str:
    return repr(float(x))  # a double scene input: its shortest exact decimal


def _rc(z: mpmath.mpc) -> list[str]:
    return [_r(z.real), _r(z.imag)]


def build() -> dict:
    mp.dps = DPS
    rng = random.Random(SEED)
    cases = []
    for kind in KINDS:
        done = 0
        while done < PER_KIND:
            cs = _case(rng, kind)
            if cs is None:
                continue
            samples = continue_case(cs)
            if samples is None:
                continue
            done += 1
            case = {"kind": kind, "r": _r(cs["r"]), "rho_h": _r(cs["rho_h"]), "beta_h": _r(cs["beta_h"]),
                    "O": _rc(cs["O"]), "C": _rc(cs["C"]), "angle": _r(cs["angle"]), "offset": _r(cs["offset"]),
                    "phi_d": _r(cs["phi_d"]), "lengths": [_r(x) for x in cs["lengths"]],
                    "drawn": {k: _rc(cs[k]) for k in "DEF"}, "theta_d": _s(cs["theta"]),
                    "samples": [{k: (_c(v) if isinstance(v, mpmath.mpc) else _s(v)) for k, v in smp.items()}
                                for smp in samples]}
            if "A" in cs:
                case["A"] = _rc(cs["A"])
            cases.append(case)
    return {
        "provenance": (f"tests/reference/slider_triad_variants_mp.py (mpmath {mpmath.__version__}, mp.dps={DPS}), "
                       f"{datetime.date.today().isoformat()}: seed {SEED}, {PER_KIND} cases each of "
                       f"{', '.join(KINDS)}; "
                       f"loop solved by findroot in (s, theta) from the drawn pose, continued in {STEP_DEG} deg steps "
                       f"to +-{SPAN_DEG} deg; velocity analogs from J x' = -df/dphi with mpmath.diff at 50 digits"),
        "cases": cases,
    }


def main() -> int:
    OUT.write_text(json.dumps(build(), indent=1) + "\n")
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
