"""50-digit reference for forward dynamics with friction and two inputs: the accelerations of the
test five-bar (tests/dynamics/scenes/friction_five_bar_pendulum.yaml) under given crank torques
at given states, with a friction circle at each of its five pins (issue 29 item 3).

Independent of the solver: Newton–Euler in absolute coordinates. Unknowns (22): each link's
centre acceleration and angular acceleration (4 × 3) and each pin's reaction (5 × 2); equations:
each link's Newton–Euler (12) and each pin's acceleration constraint (10: O1 and O2 fixed, A1, A2
and P common to the two links they join). The cranks' angular accelerations are ε1, ε2. The pin
friction: a couple x·d on the pin's first body and −x·d on its second, x = μ·r·|R|, d = −sign of
their relative angular velocity (every pin moves at the states chosen); x by fixed point from the
frictionless solve, each step a 22 × 22 solve at 50 digits, to |Δx| < 1e-45. Positions and
velocities from the closed form at 50 digits (P: the circles' intersection on the scene's branch,
its root picked by the solver's P to float precision; the distal links' rates from the velocity
constraint at P).

Run from the repository root: ``.venv/bin/python tests/reference/friction_multi_mp.py`` (writes
tests/data/friction_ref_five_bar_states.json; seconds). Also the two edges of crank 1's holding
interval at two states where it is at rest and crank 2 moves (``holding``: crank 1 held at
ε1 = 0, its torque a 23rd unknown, its pivot's friction against each start).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import mpmath as mp
import yaml

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "tests/dynamics/scenes/friction_five_bar_pendulum.yaml"
OUT = ROOT / "tests/data/friction_ref_five_bar_states.json"
mp.mp.dps = 50

#: (q1, q2, q̇1, q̇2, Q1, Q2): states where every pin's relative rotation moves, drive torques N·m
STATES = [
    ("-1.0", "-1.9", "1.5", "-2.0", "0.3", "-0.2"),
    ("-1.3", "-1.7", "-3.0", "0.7", "0.0", "0.0"),
    ("-1.7", "-1.4", "2.2", "2.9", "-0.4", "0.5"),
]
#: states with crank 1 at rest (its torque unknown): the edges of its holding interval
HELD = [
    ("-1.3", "-1.7", "0", "1.1", "0", "0.1"),
    ("-1.6", "-1.5", "0", "-2.4", "0", "-0.3"),
]


def _c(x: list) -> mp.mpc:
    return mp.mpc(mp.mpf(str(x[0])), mp.mpf(str(x[1])))


def _cross(w: mp.mpf, r: mp.mpc) -> mp.mpc:  # ω × r in the plane
    return mp.mpc(-w * r.imag, w * r.real)


def _r_cross_f(r: mp.mpc, f: mp.mpc) -> mp.mpf:
    return r.real * f.imag - r.imag * f.real


def solve_state(data: dict, state: tuple[str, ...], p_guess: complex, *, held: int = 0) -> dict:
    """ε and the loss at ``state``; ``held`` = ±1: crank 1 at rest held (ε1 = 0, its torque the
    23rd unknown) with its pivot's friction against a start toward ``held`` (an edge of its
    holding interval)."""
    q1, q2, w1, w2, t1, t2 = (mp.mpf(v) for v in state)
    o1, o2 = _c(data["fixed"]["O1"]), _c(data["fixed"]["O2"])
    groups = {g["name"]: g for g in data["groups"]}
    r1 = mp.mpf(str(groups["left_crank"]["length"]))
    r2 = mp.mpf(str(groups["right_crank"]["length"]))
    la, lb = (mp.mpf(str(v)) for v in groups["distal"]["lengths"])
    a1 = o1 + r1 * mp.expj(q1)
    a2 = o2 + r2 * mp.expj(q2)
    d = a2 - a1
    dist = abs(d)
    along = (la ** 2 - lb ** 2 + dist ** 2) / (2 * dist)
    h = mp.sqrt(la ** 2 - along ** 2)
    base = a1 + d * along / dist
    cands = [base + s * h * mp.mpc(-d.imag, d.real) / dist for s in (1, -1)]
    p = min(cands, key=lambda z: abs(complex(z) - p_guess))
    # velocities: cranks about their pivots; distal links' rates from the common point P
    va1, va2 = _cross(w1, a1 - o1), _cross(w2, a2 - o2)
    # va1 + ωL × (P − A1) = va2 + ωR × (P − A2): two real equations in ωL, ωR
    ra, rb = p - a1, p - a2
    m = mp.matrix([[-ra.imag, rb.imag], [ra.real, -rb.real]])
    rhs = mp.matrix([(va2 - va1).real, (va2 - va1).imag])
    wl, wr = mp.lu_solve(m, rhs)
    # bodies: (name, frame origin, frame x-point, ω, pivot for the constraint bookkeeping)
    spec = data["bodies"]
    frames = {"left_crank": (o1, a1, w1), "right_crank": (o2, a2, w2), "left_distal_link": (a1, p, wl),
              "right_distal_link": (a2, p, wr)}
    names = list(frames)
    bodies = {}
    for name in names:
        org, xpt, w = frames[name]
        ex = (xpt - org) / abs(xpt - org)
        c = _c(spec[name]["center"])
        g = org + ex * c
        bodies[name] = dict(g=g, w=w, m=mp.mpf(str(spec[name]["mass"])), i=mp.mpf(str(spec[name]["inertia"])))
    grav = _c(data["gravity"])
    pins = [("O1", "left_crank", None, o1), ("O2", "right_crank", None, o2),
            ("A1", "left_distal_link", "left_crank", a1), ("A2", "right_distal_link", "right_crank", a2),
            ("P", "left_distal_link", "right_distal_link", p)]
    fr = data["friction"]["all_pins"]
    circle = mp.mpf(str(fr["mu"])) * mp.mpf(str(fr["radius"]))
    # unknown order: per body (ax, ay, α) 12, per pin (Rx, Ry) 10; R of a pin acts on its first
    # body (+R) and on its second (−R)
    bi = {n: 3 * k for k, n in enumerate(names)}
    pi = {pin[0]: 12 + 2 * k for k, pin in enumerate(pins)}

    def rel_w(pin: tuple) -> mp.mpf:
        _, b, o, _ = pin
        return bodies[b]["w"] - (bodies[o]["w"] if o else 0)

    dirs = [-mp.sign(rel_w(pin)) for pin in pins]
    if held:
        assert w1 == 0 and dirs[0] == 0
        dirs[0] = mp.mpf(-held)  # O1: against crank 1's start
    assert all(dd != 0 for dd in dirs)
    n = 23 if held else 22

    def system(x: list) -> mp.matrix:
        a = mp.zeros(n, n)
        r = mp.zeros(n, 1)
        row = 0
        for name in names:  # Newton–Euler of each body
            bd = bodies[name]
            k = bi[name]
            fx, fy, mom = row, row + 1, row + 2
            a[fx, k] = bd["m"]
            a[fy, k + 1] = bd["m"]
            a[mom, k + 2] = bd["i"]
            r[fx] = bd["m"] * grav.real
            r[fy] = bd["m"] * grav.imag
            for n_pin, (pname, b, o, at) in enumerate(pins):
                sgn = 1 if b == name else -1 if o == name else 0
                if not sgn:
                    continue
                j = pi[pname]
                arm = at - bd["g"]
                a[fx, j] -= sgn
                a[fy, j + 1] -= sgn
                a[mom, j] -= sgn * (-arm.imag)  # r × R = rx·Ry − ry·Rx
                a[mom, j + 1] -= sgn * arm.real
                r[mom] += sgn * x[n_pin] * dirs[n_pin]  # the friction couple
            if name == "left_crank" and held:
                a[mom, 22] = -1  # its torque, unknown
            elif name == "left_crank":
                r[mom] += t1
            if name == "right_crank":
                r[mom] += t2
            row += 3
        for _, b, o, at in pins:  # acceleration of the pin point alike on both bodies
            for side, body in ((1, b), (-1, o)):
                if body is None:
                    continue
                bd = bodies[body]
                k = bi[body]
                arm = at - bd["g"]
                # a_P = a_G + α × arm − ω²·arm
                a[row, k] += side
                a[row + 1, k + 1] += side
                a[row, k + 2] += side * (-arm.imag)
                a[row + 1, k + 2] += side * arm.real
                cen = -bd["w"] ** 2 * arm
                r[row] -= side * cen.real
                r[row + 1] -= side * cen.imag
            row += 2
        assert row == 22
        if held:  # crank 1 held: ε1 = 0
            a[22, bi["left_crank"] + 2] = 1
        return mp.lu_solve(a, r)

    x = [mp.mpf(0)] * 5
    for _ in range(200):
        sol = system(x)
        new = [circle * abs(mp.mpc(sol[pi[pin[0]]], sol[pi[pin[0]] + 1])) for pin in pins]
        change = max(abs(u - v) for u, v in zip(new, x))
        x = new
        if change < mp.mpf("1e-45"):
            break
    else:
        raise RuntimeError("fixed point did not settle")
    sol = system(x)
    eps1, eps2 = sol[bi["left_crank"] + 2], sol[bi["right_crank"] + 2]
    loss = sum(xx * abs(rel_w(pin)) for xx, pin in zip(x, pins))
    if held:
        return {"state": list(state), "held": held, "effort": mp.nstr(sol[22], 40),
                "epsilon": [mp.nstr(eps1, 40), mp.nstr(eps2, 40)]}
    return {"state": list(state), "epsilon": [mp.nstr(eps1, 40), mp.nstr(eps2, 40)],
            "magnitudes": {pin[0]: mp.nstr(xx, 30) for xx, pin in zip(x, pins)}, "loss": mp.nstr(loss, 40)}


def main() -> int:
    sys.path.insert(0, str(ROOT))
    import solver  # only to pick P's root (float precision) on the scene's branch

    data = yaml.safe_load(SCENE.read_text(encoding="utf-8"))
    scene = solver.load_scene(str(SCENE))
    t = time.time()
    out = []
    for st in STATES:
        k = scene.solve((float(st[0]), float(st[1])), omega=0.0, epsilon=0.0)
        px, py = (float(v) for v in k.point("P").position)
        out.append(solve_state(data, st, complex(px, py)))
    holding = []
    for st in HELD:
        k = scene.solve((float(st[0]), float(st[1])), omega=0.0, epsilon=0.0)
        px, py = (float(v) for v in k.point("P").position)
        holding += [solve_state(data, st, complex(px, py), held=side) for side in (-1, 1)]
    OUT.write_text(json.dumps({
        "provenance": "tests/reference/friction_multi_mp.py: Newton–Euler in absolute coordinates at 50 digits "
                      "(22 unknowns), friction magnitudes by fixed point to 1e-45",
        "scene_file": str(SCENE.relative_to(ROOT)),
        "units": {"state": "q1, q2 (rad), q1', q2' (rad/s), Q1, Q2 (N·m)", "epsilon": "rad/s²", "loss": "W"},
        "expected": out, "holding": holding, "seconds": round(time.time() - t, 1)}, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {OUT} in {time.time() - t:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
