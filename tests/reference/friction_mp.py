"""Independent 50-digit Newton–Euler reference for Coulomb friction (issue 29): mpmath + PyYAML only.

The mechanism is the offset slider-crank of tests/forces/scenes/friction_slider_crank.yaml (crank
OA about the fixed O, rod AB, piston B on the guide y = offset along +x, M = +1); its numbers are
read from that file with plain PyYAML. This module never imports the solver. At ``mp.dps = 50``:

* positions in closed form (A = a·(cos φ, sin φ), B = (x_A + √(b² − (e − y_A)²), e)), real
  accelerations and rates by ``mp.diff`` in time along φ(t) = φ + ω·t + ε·t²/2;
* unknowns R_O (ground on crank), R_A (rod on crank), R_B (piston on rod), the guide's normal
  force N and couple C on the piston, the effort Q (torque on the crank): nine Newton–Euler
  equations (three per body, moments about O, A and B);
* friction: moment −μr·|R|·sign(ωᵢ − ωⱼ) on body i of each pin (ground and piston: ω = 0), the
  opposite on j; −μ·|N|·sign(v_B) along the guide on the piston. The magnitudes enter through
  |R| and |N|: the linear system is solved again with the magnitudes of the previous solution
  (a fixed point from the frictionless solution) until they change by < 1e-45 relative;
* every solution is checked: its equilibrium residual < 1e-40 and the power balance
  (Q − Q₀)·ω = Σ μr|R||Δω| + μ|N||v_B| to < 1e-35 relative (Q₀ the frictionless effort).

Run ``python tests/reference/friction_mp.py`` to (re)write tests/data/friction_ref_slider_crank.json
(``--check``: compare with the stored file).
"""

from __future__ import annotations

import json
import random
import sys
from pathlib import Path
from typing import Any

import yaml
from mpmath import mp, mpf

DPS = 50
ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "tests/forces/scenes/friction_slider_crank.yaml"
DATA = ROOT / "tests/data/friction_ref_slider_crank.json"


def _n(x: Any) -> mpf:
    return mpf(str(x))


def _cross(p: tuple[mpf, mpf], f: tuple[mpf, mpf]) -> mpf:
    return p[0] * f[1] - p[1] * f[0]


def _sign(x: mpf) -> int:
    return 1 if x > 0 else (-1 if x < 0 else 0)


class Mechanism:
    def __init__(self, data: dict[str, Any]) -> None:
        g = {x["name"]: x for x in data["groups"]}
        self.a = _n(g["crank"]["length"])
        self.b = _n(g["rod"]["length"])
        self.e = _n(g["rod"]["guide"]["offset"])
        bd = data["bodies"]
        self.m1, self.c1, self.i1 = _n(bd["crank"]["mass"]), [_n(v) for v in bd["crank"]["center"]], _n(
            bd["crank"]["inertia"])
        self.m2, self.c2, self.i2 = _n(bd["rod"]["mass"]), [_n(v) for v in bd["rod"]["center"]], _n(
            bd["rod"]["inertia"])
        self.m3 = _n(bd["piston"]["mass"])
        self.g = [_n(v) for v in data["gravity"]]
        self.load = [_n(v) for v in data["loads"][0]["force"]]
        fr = data["friction"]
        self.cO, self.cA, self.cB = (_n(fr["pins"][p]["mu"]) * _n(fr["pins"][p]["radius"]) for p in "OAB")
        self.mu = _n(fr["slides"]["piston"]["mu"])

    def positions(self, phi: mpf) -> dict[str, Any]:
        a = (self.a * mp.cos(phi), self.a * mp.sin(phi))
        bx = a[0] + mp.sqrt(self.b ** 2 - (self.e - a[1]) ** 2)
        b = (bx, self.e)
        t1 = phi
        t2 = mp.atan2(b[1] - a[1], b[0] - a[0])
        g1 = (self.c1[0] * mp.cos(t1) - self.c1[1] * mp.sin(t1), self.c1[0] * mp.sin(t1) + self.c1[1] * mp.cos(t1))
        g2 = (a[0] + self.c2[0] * mp.cos(t2) - self.c2[1] * mp.sin(t2),
              a[1] + self.c2[0] * mp.sin(t2) + self.c2[1] * mp.cos(t2))
        return {"A": a, "B": b, "G1": g1, "G2": g2, "t2": t2}

    def motion(self, phi: mpf, w: mpf, eps: mpf) -> dict[str, Any]:
        def at(t: mpf) -> dict[str, Any]:
            return self.positions(phi + w * t + eps * t * t / 2)

        def d(key: str, i: int | None, n: int) -> mpf:
            return mp.diff(lambda t: at(t)[key] if i is None else at(t)[key][i], 0, n)

        pos = at(mpf(0))
        return {
            "pos": pos,
            "aG1": (d("G1", 0, 2), d("G1", 1, 2)),
            "aG2": (d("G2", 0, 2), d("G2", 1, 2)),
            "aB": (d("B", 0, 2), d("B", 1, 2)),
            "vB": d("B", 0, 1),
            "w2": d("t2", None, 1),
            "al2": d("t2", None, 2),
        }

    def solve(self, phi: mpf, w: mpf, eps: mpf, *, friction: bool = True) -> dict[str, Any]:
        mo = self.motion(phi, w, eps)
        p = mo["pos"]
        a, b, g1, g2 = p["A"], p["B"], p["G1"], p["G2"]
        # known loads: gravity and d'Alembert
        f1 = (self.m1 * (self.g[0] - mo["aG1"][0]), self.m1 * (self.g[1] - mo["aG1"][1]))
        f2 = (self.m2 * (self.g[0] - mo["aG2"][0]), self.m2 * (self.g[1] - mo["aG2"][1]))
        f3 = (self.m3 * (self.g[0] - mo["aB"][0]) + self.load[0], self.m3 * (self.g[1] - mo["aB"][1]) + self.load[1])
        m1 = _cross(g1, f1) - self.i1 * eps
        m2 = _cross((g2[0] - a[0], g2[1] - a[1]), f2) - self.i2 * mo["al2"]
        w1, w2, vb = w, mo["w2"], mo["vB"]
        s_o, s_a, s_b, s_v = _sign(w1), _sign(w2 - w1), _sign(w2), _sign(vb)
        ab = (b[0] - a[0], b[1] - a[1])

        def linear(mo_: mpf, ma: mpf, mb: mpf, fs: mpf) -> list[mpf]:
            # unknowns x = [ROx, ROy, RAx, RAy, RBx, RBy, N, C, Q]
            # friction moments: on crank −mo_·s_o (pin O) + ma·s_a (pin A: −ma·s_a on the rod);
            # on the rod −mb·s_b (pin B, +mb·s_b on the piston); on the piston −fs·s_v along x.
            rows = [
                ([1, 0, 1, 0, 0, 0, 0, 0, 0], -f1[0]),
                ([0, 1, 0, 1, 0, 0, 0, 0, 0], -f1[1]),
                ([0, 0, -a[1], a[0], 0, 0, 0, 0, 1], -m1 + mo_ * s_o - ma * s_a),
                ([0, 0, -1, 0, 1, 0, 0, 0, 0], -f2[0]),
                ([0, 0, 0, -1, 0, 1, 0, 0, 0], -f2[1]),
                ([0, 0, 0, 0, -ab[1], ab[0], 0, 0, 0], -m2 + ma * s_a + mb * s_b),
                ([0, 0, 0, 0, -1, 0, 0, 0, 0], -f3[0] + fs * s_v),
                ([0, 0, 0, 0, 0, -1, 1, 0, 0], -f3[1]),
                ([0, 0, 0, 0, 0, 0, 0, 1, 0], -mb * s_b),
            ]
            mat = mp.matrix([[mpf(v) for v in r] for r, _ in rows])
            rhs = mp.matrix([v for _, v in rows])
            x = mp.lu_solve(mat, rhs)
            res = mat * x - rhs
            scale = max(abs(v) for v in rhs) + 1
            assert max(abs(v) for v in res) < mpf("1e-40") * scale
            return [x[i] for i in range(9)]

        x = linear(mpf(0), mpf(0), mpf(0), mpf(0))
        q0 = x[8]
        if friction:
            for _ in range(500):
                mags = (self.cO * mp.hypot(x[0], x[1]), self.cA * mp.hypot(x[2], x[3]),
                        self.cB * mp.hypot(x[4], x[5]), self.mu * abs(x[6]))
                xn = linear(*mags)
                change = max(abs(u - v) for u, v in zip(xn, x))
                x = xn
                if change < mpf("1e-45") * (max(abs(v) for v in x) + 1):
                    break
            else:
                raise RuntimeError("no fixed point: self-locking?")
        ro, ra, rb = (x[0], x[1]), (x[2], x[3]), (x[4], x[5])
        loss = (self.cO * mp.hypot(*ro) * abs(w1) + self.cA * mp.hypot(*ra) * abs(w2 - w1)
                + self.cB * mp.hypot(*rb) * abs(w2) + self.mu * abs(x[6]) * abs(vb))
        if friction:
            balance = (x[8] - q0) * w - loss
            assert abs(balance) < mpf("1e-35") * (abs(loss) + 1), balance
        return {"effort": x[8], "effort0": q0, "O": ro, "A": ra, "B": rb, "normal": x[6],
                "friction": -self.mu * abs(x[6]) * s_v, "couple": x[7], "loss": loss}


def samples() -> list[tuple[float, float, float]]:
    rng = random.Random("friction_slider_crank")
    out = [(0.7, 12.0, 35.0)]
    for _ in range(7):
        phi = rng.uniform(0.0, 6.283185307179586)
        w = rng.choice((-1.0, 1.0)) * rng.uniform(2.0, 40.0)
        out.append((phi, w, rng.uniform(-300.0, 300.0)))
    return out


def build() -> dict[str, Any]:
    mp.dps = DPS
    data = yaml.safe_load(SCENE.read_text(encoding="utf-8"))
    mech = Mechanism(data)
    rows = []
    for phi, w, eps in samples():
        s = mech.solve(mpf(phi), mpf(w), mpf(eps))
        rows.append({
            "phi": repr(phi), "omega": repr(w), "epsilon": repr(eps),
            "effort": mp.nstr(s["effort"], 30), "effort0": mp.nstr(s["effort0"], 30),
            "reactions": {"O": {"on": "crank", "value": [mp.nstr(v, 30) for v in s["O"]]},
                          "A": {"on": "crank", "value": [mp.nstr(v, 30) for v in s["A"]]},
                          "B": {"on": "rod", "value": [mp.nstr(v, 30) for v in s["B"]]}},
            "slide": {"force": [mp.nstr(s["friction"], 30), mp.nstr(s["normal"], 30)],
                      "couple": mp.nstr(s["couple"], 30)},
            "loss": mp.nstr(s["loss"], 30),
        })
    return {
        "provenance": (
            "tests/reference/friction_mp.py (mpmath, mp.dps=50, 30 digits written): closed-form positions of "
            "tests/forces/scenes/friction_slider_crank.yaml, accelerations by mp.diff in time, the nine "
            "Newton-Euler equations with Coulomb friction (friction circles mu*r*|R| against the relative "
            "rotation at O, A, B; mu*|N| against the piston's velocity) solved by fixed-point iteration on the "
            "magnitudes to 1e-45; each sample checked by its equilibrium residual and the power balance "
            "(Q - Q0)*omega = dissipated power to 1e-35. Never the solver."),
        "scene_file": "tests/forces/scenes/friction_slider_crank.yaml",
        "units": "phi rad, omega rad/s, epsilon rad/s^2; N, N m, W",
        "conventions": ("reactions[P]: force on body 'on' at P from the other body; slide: the guide's whole "
                        "force on the piston [friction along x, normal along y] and its couple about B"),
        "samples": rows,
    }


def main(argv: list[str]) -> int:
    data = build()
    if "--check" in argv:
        stored = json.loads(DATA.read_text(encoding="utf-8"))
        same = stored["samples"] == data["samples"]
        print("same" if same else "DIFFERENT")
        return 0 if same else 1
    DATA.write_text(json.dumps(data, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {DATA}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
