"""Independent 50-digit references for the slider triad (the triad with one prismatic pair:
D on a fixed guide), mpmath only.

Never imports the solver. Random crank-driven slider triads are drawn at random poses (seeded):
crank O = 0 of length r at the drawn input φ_d carrying B, a fixed pivot C, a guide through the
fixed point G at the angle γ, the ternary link's points D (on the guide), E, F; the binary
links' lengths are the drawn distances |E − B|, |F − C|. The loop |E − B| = b, |F − C| = c
(D = G + s·e^{jγ}, E = D + u·e^{jθ}, F = D + v·e^{jθ}) is solved by ``mpmath.findroot`` in
(s, θ), continued from the drawn pose in steps of 0.25° to ±30° (linear extrapolation of the two
previous solutions as the start of each step); the velocity analogs d/dφ come from mpmath's
``lu_solve`` of the differentiated loop equations at 50 digits. Every 5° of input is stored
(positions D, E, F, θ and s, velocity analogs), with the case's geometry, in
tests/data/reference_slider_triad.json. A case whose normalised Jacobian determinant falls below
0.02 or whose θ swings by more than 0.05 rad in a step is skipped (not a clean case).

Run ``python tests/reference/slider_triad_mp.py`` to rewrite the file.
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
CASES = 12
SEED = 2876
MIN_COND = 0.02
OUT = Path(__file__).resolve().parents[1] / "data" / "reference_slider_triad.json"


def _cis(t: mpf) -> mpmath.mpc:
    return mpmath.mpc(mpmath.cos(t), mpmath.sin(t))


def _dot(m: mpmath.mpc, n: mpmath.mpc) -> mpf:
    return m.real * n.real + m.imag * n.imag


def _case(rng: random.Random) -> dict | None:
    r = mpf(rng.uniform(0.05, 0.15))
    c = mpmath.mpc(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6))
    g = mpmath.mpc(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6))
    gamma = mpf(rng.uniform(-3.1, 3.1))
    s_d = mpf(rng.uniform(-0.4, 0.4))
    e, f = (mpmath.mpc(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6)) for _ in range(2))
    phi_d = mpf(rng.uniform(-3.1, 3.1))
    b = r * _cis(phi_d)
    d = g + s_d * _cis(gamma)
    lengths = (abs(e - b), abs(f - c))
    if min(lengths) < 0.1 or min(abs(e - d), abs(f - e), abs(f - d)) < 0.1:
        return None
    theta_d = mpmath.arg(e - d)
    u = abs(e - d)
    v = (f - d) * _cis(-theta_d)
    if abs(v.imag) < 0.05:
        return None
    return {"r": r, "C": c, "G": g, "gamma": gamma, "s_d": s_d, "phi_d": phi_d, "lengths": lengths, "u": u, "v": v,
            "D": d, "E": e, "F": f, "theta": theta_d}


def _points(cs: dict, s: mpf, t: mpf) -> tuple[mpmath.mpc, mpmath.mpc, mpmath.mpc]:
    d = cs["G"] + s * _cis(cs["gamma"])
    w = _cis(t)
    return d, d + cs["u"] * w, d + cs["v"] * w


def _equations(cs: dict, phi: mpf):
    b_ = cs["r"] * _cis(phi)
    lb, lc = cs["lengths"]

    def f(s: mpf, t: mpf):
        _, e, ff = _points(cs, s, t)
        return [abs(e - b_) ** 2 - lb**2, abs(ff - cs["C"]) ** 2 - lc**2]
    return f


def _velocity(cs: dict, phi: mpf, x: list) -> tuple[mpf, mpf, mpf]:
    """(s', θ', normalised |det|) from the differentiated loop at 50 digits."""
    s, t = x
    _, e, f = _points(cs, s, t)
    w = _cis(t)
    b_ = cs["r"] * _cis(phi)
    b1 = cs["r"] * mpmath.mpc(0, 1) * _cis(phi)
    ed = _cis(cs["gamma"])
    q, r = e - b_, f - cs["C"]
    ju, jv = mpmath.mpc(0, 1) * cs["u"] * w, mpmath.mpc(0, 1) * cs["v"] * w
    mat = mpmath.matrix([[_dot(ed, q), _dot(q, ju)], [_dot(ed, r), _dot(r, jv)]])
    sol = mpmath.lu_solve(mat, mpmath.matrix([_dot(b1, q), 0]))
    lb, lc = cs["lengths"]
    cond = abs(mpmath.det(mat)) / (lb * lc * (abs(cs["u"]) + abs(cs["v"])))
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
                sol = mpmath.findroot(_equations(cs, phi), start, tol=mpf(10) ** (-2 * DPS + 10))
            except (ValueError, ZeroDivisionError):
                return None
            prev, x = x, [sol[0], sol[1]]
            s1, t1, cond = _velocity(cs, phi, x)
            if cond < MIN_COND or abs(x[1] - prev[1]) > 0.05:
                return None
            if k % STORE_EVERY == 0 and not (sign == -1 and k == 0):
                d, e, f = _points(cs, x[0], x[1])
                w = _cis(x[1])
                d1 = s1 * _cis(cs["gamma"])
                out.append({"phi": phi, "D": d, "E": e, "F": f, "theta": x[1], "s": x[0], "dD": d1,
                            "dE": d1 + mpmath.mpc(0, 1) * cs["u"] * w * t1,
                            "dF": d1 + mpmath.mpc(0, 1) * cs["v"] * w * t1, "dtheta": t1, "ds": s1})
    return sorted(out, key=lambda s: s["phi"])


def _s(x: mpf) -> str:
    return mpmath.nstr(x, DPS, strip_zeros=False)


def _c(z: mpmath.mpc) -> list[str]:
    return [_s(z.real), _s(z.imag)]


def build() -> dict:
    mp.dps = DPS
    rng = random.Random(SEED)
    cases = []
    while len(cases) < CASES:
        cs = _case(rng)
        if cs is None:
            continue
        samples = continue_case(cs)
        if samples is None:
            continue
        # the drawn values are doubles (drawn from doubles): exact as decimal strings
        cases.append({
            "r": _s(cs["r"]), "C": _c(cs["C"]), "G": _c(cs["G"]), "gamma": _s(cs["gamma"]), "phi_d": _s(cs["phi_d"]),
            "lengths": [_s(x) for x in cs["lengths"]],
            "drawn": {"D": _c(cs["D"]), "E": _c(cs["E"]), "F": _c(cs["F"])},
            "theta_d": _s(cs["theta"]), "s_d": _s(cs["s_d"]),
            "samples": [{k: (_c(v) if isinstance(v, mpmath.mpc) else _s(v)) for k, v in smp.items()}
                        for smp in samples],
        })
    return {
        "provenance": (f"tests/reference/slider_triad_mp.py (mpmath {mpmath.__version__}, mp.dps={DPS}), "
                       f"{datetime.date.today().isoformat()}: seed {SEED}; loop solved by findroot in (s, theta) "
                       f"from the drawn pose, continued in {STEP_DEG} deg steps to +-{SPAN_DEG} deg; velocity "
                       "analogs from the differentiated loop (lu_solve) at 50 digits"),
        "cases": cases,
    }


def main() -> int:
    OUT.write_text(json.dumps(build(), indent=1) + "\n")
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
