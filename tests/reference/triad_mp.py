"""Independent 50-digit references for the triad (class-3 Assur group), mpmath only.

Never imports the solver. Random crank-driven triads are drawn at random poses (seeded): crank
O = 0 of length r at the drawn input φ_d, fixed pivots B and C, ternary-link points D, E, F; the
binary links' lengths are the drawn distances. The loop |D − A| = a, |E − B| = b, |F − C| = c
(E = D + u·e^{jθ}, F = D + v·e^{jθ}) is solved by ``mpmath.findroot`` in (Dx, Dy, θ), continued
from the drawn pose in steps of 0.25° to ±30° (linear extrapolation of the two previous solutions
as the start of each step); the velocity analogs d/dφ come from mpmath's ``lu_solve`` of the
differentiated loop equations at 50 digits. Every 5° of input is stored (positions D, E, F and
θ, velocity analogs), with the case's geometry, in tests/data/reference_triad.json.

Run ``python tests/reference/triad_mp.py`` to rewrite the file.
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
SEED = 28
OUT = Path(__file__).resolve().parents[1] / "data" / "reference_triad.json"


def _cis(t: mpf) -> mpmath.mpc:
    return mpmath.mpc(mpmath.cos(t), mpmath.sin(t))


def _case(rng: random.Random) -> dict | None:
    r = mpf(rng.uniform(0.05, 0.15))
    b = mpmath.mpc(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6))
    c = mpmath.mpc(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6))
    pts = [mpmath.mpc(rng.uniform(-0.6, 0.6), rng.uniform(-0.6, 0.6)) for _ in range(3)]
    phi_d = mpf(rng.uniform(-3.1, 3.1))
    a_d = r * _cis(phi_d)
    d, e, f = pts
    lengths = (abs(d - a_d), abs(e - b), abs(f - c))
    if min(lengths) < 0.1 or min(abs(e - d), abs(f - e), abs(f - d)) < 0.1:
        return None
    theta_d = mpmath.arg(e - d)
    u = abs(e - d)
    v = (f - d) * _cis(-theta_d)
    if abs(v.imag) < 0.05:
        return None
    return {"r": r, "B": b, "C": c, "phi_d": phi_d, "lengths": lengths, "u": u, "v": v, "D": d, "theta": theta_d}


def _equations(cs: dict, phi: mpf):
    a_ = cs["r"] * _cis(phi)
    la, lb, lc = cs["lengths"]

    def f(x: mpf, y: mpf, t: mpf):
        d = mpmath.mpc(x, y)
        w = _cis(t)
        return [abs(d - a_) ** 2 - la**2, abs(d + cs["u"] * w - cs["B"]) ** 2 - lb**2,
                abs(d + cs["v"] * w - cs["C"]) ** 2 - lc**2]
    return f, a_


def _velocity(cs: dict, phi: mpf, x: list) -> tuple[mpmath.mpc, mpf, mpf]:
    """(D', θ', |det|) from the differentiated loop at 50 digits."""
    d, t = mpmath.mpc(x[0], x[1]), x[2]
    w = _cis(t)
    a_ = cs["r"] * _cis(phi)
    a1 = cs["r"] * mpmath.mpc(0, 1) * _cis(phi)
    p, q, s = d - a_, d + cs["u"] * w - cs["B"], d + cs["v"] * w - cs["C"]
    ju, jv = mpmath.mpc(0, 1) * cs["u"] * w, mpmath.mpc(0, 1) * cs["v"] * w

    def dot(m: mpmath.mpc, n: mpmath.mpc) -> mpf:
        return m.real * n.real + m.imag * n.imag
    mat = mpmath.matrix([[p.real, p.imag, 0], [q.real, q.imag, dot(q, ju)], [s.real, s.imag, dot(s, jv)]])
    rhs = mpmath.matrix([dot(a1, p), 0, 0])
    sol = mpmath.lu_solve(mat, rhs)
    return mpmath.mpc(sol[0], sol[1]), sol[2], abs(mpmath.det(mat))


def continue_case(cs: dict) -> list[dict] | None:
    out = []
    for sign in (1, -1):
        x = [cs["D"].real, cs["D"].imag, cs["theta"]]
        prev = list(x)
        for k in range(0, int(SPAN_DEG / STEP_DEG) + 1):
            phi = cs["phi_d"] + sign * mpmath.radians(k * STEP_DEG)
            f, _ = _equations(cs, phi)
            start = [2 * x[i] - prev[i] for i in range(3)] if k > 1 else x
            try:
                sol = mpmath.findroot(f, start, tol=mpf(10) ** (-2 * DPS + 10))
            except (ValueError, ZeroDivisionError):
                return None
            prev, x = x, [sol[0], sol[1], sol[2]]
            d1, t1, det = _velocity(cs, phi, x)
            if det < 1e-3 or abs(x[2] - prev[2]) > 0.05:  # near-singular or a fast swing: not a clean case
                return None
            if k % STORE_EVERY == 0 and not (sign == -1 and k == 0):
                d = mpmath.mpc(x[0], x[1])
                w = _cis(x[2])
                out.append({"phi": phi, "D": d, "E": d + cs["u"] * w, "F": d + cs["v"] * w, "theta": x[2],
                            "dD": d1, "dE": d1 + mpmath.mpc(0, 1) * cs["u"] * w * t1,
                            "dF": d1 + mpmath.mpc(0, 1) * cs["v"] * w * t1, "dtheta": t1})
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
        # the drawn input as a double: the geometry was drawn from doubles, so it is exact
        cases.append({
            "r": _s(cs["r"]), "B": _c(cs["B"]), "C": _c(cs["C"]), "phi_d": _s(cs["phi_d"]),
            "lengths": [_s(x) for x in cs["lengths"]], "drawn": {"D": _c(cs["D"]),
                                                               "E": _c(cs["D"] + cs["u"] * _cis(cs["theta"])),
                                                               "F": _c(cs["D"] + cs["v"] * _cis(cs["theta"]))},
            "theta_d": _s(cs["theta"]),
            "samples": [{k: (_c(v) if isinstance(v, mpmath.mpc) else _s(v)) for k, v in smp.items()}
                        for smp in samples],
        })
    return {
        "provenance": (f"tests/reference/triad_mp.py (mpmath {mpmath.__version__}, mp.dps={DPS}), "
                       f"{datetime.date.today().isoformat()}: seed {SEED}; loop solved by findroot from the drawn "
                       f"pose, continued in {STEP_DEG} deg steps to +-{SPAN_DEG} deg; velocity analogs from the "
                       "differentiated loop (lu_solve) at 50 digits"),
        "cases": cases,
    }


def main() -> int:
    OUT.write_text(json.dumps(build(), indent=1) + "\n")
    print(f"wrote {OUT}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
