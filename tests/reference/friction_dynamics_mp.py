"""Independent 50-digit reference for forward dynamics with Coulomb pin friction (issue 29, item 3).

A four-bar pendulum (tests/dynamics/scenes/friction_four_bar_pendulum.yaml, read with plain PyYAML:
crank OA, coupler AB, rocker CB under gravity, a friction circle μ·r at each of its four pins, no
drive) released from rest. This module never imports the solver. At ``mp.dps = 50``:

* **positions** in closed form from the crank angle φ (B the intersection of the circles about A
  and C on the scene's branch M = +1: B to the right of the line A→C), the
  coupler's and rocker's rates from the loop's velocity equation (a 2 × 2 system);
* **Newton–Euler in absolute coordinates**: the unknowns are the three bodies' centre accelerations
  and angular accelerations and the four pins' forces (17); the equations are the bodies' nine
  equations of motion and the pins' eight acceleration constraints (a_P equal on both bodies,
  zero on the ground). Friction: at a pin joining bodies i and j (reaction R), a couple
  −μ·r·|R|·sign(ωᵢ − ωⱼ) on i and the opposite on j. The system is linear in the four magnitudes
  x = μ·r·|R|, so it is solved (one elimination) for the frictionless right-hand side and each pin's
  unit couple; the magnitudes then solve x = μ·r·|R₀ + Σ x·d·R_unit| by fixed point to 1e-45;
* **the run**: the friction's directions d are a *mode*, fixed within a segment; y = (φ, ω) is
  integrated by the 8-stage Gauss–Legendre collocation method (order 16, implicit, the stages
  by simplified Newton) with steps of at most ``STEP``, each checked by step doubling (one step
  against two of half its length, halved until they agree to LOCAL = 1e-13: where a pin's force
  passes near zero its |R| is nearly a kink, which a fixed step does not resolve); a segment ends
  where ω = 0 (a turning point) or where a pin's relative rotation rate ωᵢ − ωⱼ = 0 (a reversal:
  that pin's d flips), located on the step's collocation polynomial, then by the secant method on
  the length of the step that crosses it;
* **stick–slip** at a turning point (and at the release): for a start toward +φ and toward −φ
  the free equations are solved with the friction against that start; where neither start is
  consistent (its ε has the other sign) the pendulum sticks: the reference's answer is that time
  and angle, with the mechanical energy E = T + V there (the friction's work is E − E₀).

Each accepted step's two halves agree with the whole step to 1e-13 (its own error is then about
1e-13/2¹⁶); ``--check`` reruns everything at twice STEP in parallel and writes the difference.
Run ``python tests/reference/friction_dynamics_mp.py`` to (re)write
tests/data/friction_ref_four_bar_pendulum.json (about an hour on the shared 2-core VM).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path
from typing import Any

import yaml
from mpmath import mp, mpf

DPS = 50
STEP = "0.02"  # s
STAGES = 8  # Gauss–Legendre: order 16 (h·√|∂ε/∂φ| ≈ 0.2 per step: a truncation of ~1e-12 per unit time)
TOL = "1e-20"  # the stages' simplified Newton
LOCAL = mpf("1e-13")  # step doubling: a step's |y(h) − y(h/2, h/2)| (rad, rad/s) accepted
#: the truncation at STEP, measured without ``--check`` (which reruns everything at 2·STEP)
CHECKED = ("from rest at phi0 over 0.08 s (4 steps): |phi(h=0.02) - phi(h=0.01)| = 1.4e-16 rad, |omega| 6.8e-15 rad/s "
           "(2026-11-27)")
ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "tests/dynamics/scenes/friction_four_bar_pendulum.yaml"
DATA = ROOT / "tests/data/friction_ref_four_bar_pendulum.json"
PHI0 = "0.3"  # rad, released from rest
T_MAX = 10.0  # s: the run must stick before


def _n(x: Any) -> mpf:
    return mpf(str(x))


def _sign(x: Any) -> int:
    return 1 if x > 0 else (-1 if x < 0 else 0)


class Pendulum:
    """The four-bar's data and its Newton–Euler equations with friction."""

    def __init__(self, data: dict[str, Any]) -> None:
        g = {x["name"]: x for x in data["groups"]}
        deg = data["units"]["angle"] == "deg"
        assert data["units"]["length"] == "m" and deg
        self.O = tuple(_n(v) for v in data["fixed"]["O"])
        self.C = tuple(_n(v) for v in data["fixed"]["C"])
        self.l1 = _n(g["crank"]["length"])
        self.l2, self.l3 = (_n(v) for v in g["dyad"]["lengths"])
        self.branch = int(g["dyad"]["M"])
        self.grav = tuple(_n(v) for v in data["gravity"])
        b = data["bodies"]
        self.bodies = []  # (mass, inertia, centre in the body frame, frame length)
        for name, length in (("crank", self.l1), ("coupler", self.l2), ("rocker", self.l3)):
            self.bodies.append((_n(b[name]["mass"]), _n(b[name]["inertia"]),
                                tuple(_n(v) for v in b[name]["center"]), length))
        fr = data["friction"]["all_pins"]
        self.circle = _n(fr["mu"]) * _n(fr["radius"])
        # pins: (name, body i, body j or None for the ground, end of i: 0 first point / 1 second, end of j)
        self.pins = (("O", 0, None, 0, None), ("A", 0, 1, 1, 0), ("B", 1, 2, 1, 1), ("C", 2, None, 0, None))

    # -- kinematics ----------------------------------------------------------------------------
    def angles(self, phi: Any) -> tuple[Any, Any, Any]:
        """θ of the crank (φ), the coupler A→B and the rocker C→B."""
        ax, ay = self.O[0] + self.l1 * mp.cos(phi), self.O[1] + self.l1 * mp.sin(phi)
        dx, dy = self.C[0] - ax, self.C[1] - ay
        d = mp.sqrt(dx * dx + dy * dy)
        along = (self.l2 ** 2 - self.l3 ** 2 + d * d) / (2 * d)
        h = mp.sqrt(self.l2 ** 2 - along ** 2)
        # the branch: B to the right of A→C for M = +1 (checked against the solver's float B once: --branch)
        bx = ax + along * dx / d + self.branch * h * dy / d
        by = ay + along * dy / d - self.branch * h * dx / d
        return phi, mp.atan2(by - ay, bx - ax), mp.atan2(by - self.C[1], bx - self.C[0])

    def rates(self, th: tuple[Any, Any, Any], w1: Any) -> tuple[Any, Any, Any]:
        """(ω₁, ω₂, ω₃) from l₁ω₁·ie^{iθ₁} + l₂ω₂·ie^{iθ₂} = l₃ω₃·ie^{iθ₃}."""
        t1, t2, t3 = th
        # l2 w2 (-sin t2) - l3 w3 (-sin t3) = l1 w1 sin t1 ; l2 w2 cos t2 - l3 w3 cos t3 = -l1 w1 cos t1
        a11, a12 = -self.l2 * mp.sin(t2), self.l3 * mp.sin(t3)
        a21, a22 = self.l2 * mp.cos(t2), -self.l3 * mp.cos(t3)
        r1, r2 = self.l1 * w1 * mp.sin(t1), -self.l1 * w1 * mp.cos(t1)
        det = a11 * a22 - a12 * a21
        return w1, (r1 * a22 - a12 * r2) / det, (a11 * r2 - a21 * r1) / det

    def _frames(self, th: tuple[Any, Any, Any]) -> list[dict[str, Any]]:
        """Per body: its centre G (world), and the vectors G→first point, G→second point (world)."""
        origins = [self.O, None, self.C]
        ax, ay = self.O[0] + self.l1 * mp.cos(th[0]), self.O[1] + self.l1 * mp.sin(th[0])
        origins[1] = (ax, ay)
        out = []
        for (_, _, c, length), o, t in zip(self.bodies, origins, th):
            cs, sn = mp.cos(t), mp.sin(t)
            gx, gy = o[0] + cs * c[0] - sn * c[1], o[1] + sn * c[0] + cs * c[1]
            first = (o[0] - gx, o[1] - gy)
            second = (o[0] + cs * length - gx, o[1] + sn * length - gy)
            out.append({"G": (gx, gy), "ends": (first, second)})
        return out

    def energy(self, phi: Any, w1: Any) -> Any:
        """T + V: Σ ½m|v_G|² + ½Iω² − Σ m g·G."""
        th = self.angles(phi)
        w = self.rates(th, w1)
        fr = self._frames(th)
        e = mpf(0)
        for (mass, inertia, _, _), f, wi, v in zip(self.bodies, fr, w, self._centre_velocities(th, w, fr)):
            e += mass * (v[0] ** 2 + v[1] ** 2) / 2 + inertia * wi * wi / 2
            e -= mass * (self.grav[0] * f["G"][0] + self.grav[1] * f["G"][1])
        return e

    def _centre_velocities(self, th: Any, w: Any, fr: Any) -> list[tuple[Any, Any]]:
        def about(point_to_g: tuple[Any, Any], wi: Any, base: tuple[Any, Any]) -> tuple[Any, Any]:
            return base[0] - wi * point_to_g[1], base[1] + wi * point_to_g[0]
        g_crank = (-fr[0]["ends"][0][0], -fr[0]["ends"][0][1])  # O → G
        v1 = about(g_crank, w[0], (mpf(0), mpf(0)))
        va = about((self.l1 * mp.cos(th[0]), self.l1 * mp.sin(th[0])), w[0], (mpf(0), mpf(0)))
        v2 = about((-fr[1]["ends"][0][0], -fr[1]["ends"][0][1]), w[1], va)
        v3 = about((-fr[2]["ends"][0][0], -fr[2]["ends"][0][1]), w[2], (mpf(0), mpf(0)))
        return [v1, v2, v3]

    # -- Newton–Euler -----------------------------------------------------------------------------
    def relative(self, w: tuple[Any, Any, Any]) -> list[Any]:
        """Each pin's relative rotation rate ωᵢ − ωⱼ."""
        return [w[i] - (0 if j is None else w[j]) for _, i, j, _, _ in self.pins]

    def solve(self, phi: Any, w1: Any, mode: list[int]) -> tuple[Any, list[Any]]:
        """(ε, the pins' friction magnitudes) at (φ, ω) with the friction's directions ``mode``
        (d per pin: the couple x·d on body i, −x·d on j)."""
        th = self.angles(phi)
        w = self.rates(th, w1)
        fr = self._frames(th)
        n = 17
        a = [[mpf(0)] * n for _ in range(n)]
        rhs0 = [mpf(0)] * n
        for b, (mass, inertia, _, _) in enumerate(self.bodies):
            a[3 * b][3 * b] = mass
            a[3 * b + 1][3 * b + 1] = mass
            a[3 * b + 2][3 * b + 2] = inertia
            rhs0[3 * b] = mass * self.grav[0]
            rhs0[3 * b + 1] = mass * self.grav[1]
        for p, (_, i, j, ei, ej) in enumerate(self.pins):
            col = 9 + 2 * p  # F_p: the force on body i from j (j gets −F_p)
            for body, end, sgn in ((i, ei, 1), (j, ej, -1)):
                if body is None:
                    continue
                s = fr[body]["ends"][end]
                # m a − Σ F = m g ; I α − Σ s × F = couples
                a[3 * body][col] = -sgn
                a[3 * body + 1][col + 1] = -sgn
                a[3 * body + 2][col] = sgn * s[1]
                a[3 * body + 2][col + 1] = -sgn * s[0]
            row = 9 + 2 * p  # a_G,i + α_i k×s_i − ω_i² s_i = (the same of j, or 0)
            rx, ry = mpf(0), mpf(0)
            for body, end, sgn in ((i, ei, 1), (j, ej, -1)):
                if body is None:
                    continue
                s = fr[body]["ends"][end]
                a[row][3 * body] = sgn
                a[row + 1][3 * body + 1] = sgn
                a[row][3 * body + 2] = -sgn * s[1]
                a[row + 1][3 * body + 2] = sgn * s[0]
                rx += sgn * w[body] ** 2 * s[0]
                ry += sgn * w[body] ** 2 * s[1]
            rhs0[row], rhs0[row + 1] = rx, ry
        cols = [rhs0]
        for _, i, j, _, _ in self.pins:
            r = [mpf(0)] * n
            r[3 * i + 2] = mpf(1)
            if j is not None:
                r[3 * j + 2] = mpf(-1)
            cols.append(r)
        z0, *units = _solve_many(a, cols)
        # R_p = R⁰_p + Σ_q x_q·d_q·R_p(unit q): the coefficients once, then the fixed point
        r0 = [(z0[9 + 2 * p], z0[10 + 2 * p]) for p in range(4)]
        coef = [[(mode[q] * units[q][9 + 2 * p], mode[q] * units[q][10 + 2 * p]) for q in range(4)] for p in range(4)]
        x = [self.circle * mp.sqrt(r[0] ** 2 + r[1] ** 2) for r in r0]
        tol = mpf(10) ** (-45)
        for _ in range(400):
            new = []
            for p in range(4):
                fx, fy = r0[p]
                for q in range(4):
                    fx += x[q] * coef[p][q][0]
                    fy += x[q] * coef[p][q][1]
                new.append(self.circle * mp.sqrt(fx * fx + fy * fy))
            change = max(abs(u - v) for u, v in zip(new, x))
            x = new
            if change < tol * max(max(x), mpf(1)):
                break
        else:
            raise RuntimeError("the friction magnitudes did not converge")
        eps = z0[2] + sum(x[q] * mode[q] * units[q][2] for q in range(4))
        return eps, x

    def mode_of(self, phi: Any, w1: Any, start: int = 0) -> list[int]:
        """The friction's directions: against each pin's relative rotation (at rest: against a start
        toward ``start``·φ)."""
        th = self.angles(phi)
        rel = self.relative(self.rates(th, w1 if w1 != 0 else mpf(start)))
        return [-_sign(r) for r in rel]


def _solve_many(a: list[list[Any]], cols: list[list[Any]]) -> list[list[Any]]:
    """A·z = c for each column c: Gaussian elimination with partial pivoting (zeros skipped)."""
    n = len(a)
    m = [list(row) + [c[i] for c in cols] for i, row in enumerate(a)]
    width = n + len(cols)
    for k in range(n):
        piv = max(range(k, n), key=lambda r: abs(m[r][k]))
        m[k], m[piv] = m[piv], m[k]
        pk = m[k]
        nz = [c for c in range(k + 1, width) if pk[c] != 0]
        for r in range(k + 1, n):
            f = m[r][k]
            if f == 0:
                continue
            f = f / pk[k]
            row = m[r]
            for c in nz:
                row[c] -= f * pk[c]
    out = []
    for j in range(len(cols)):
        z = [mpf(0)] * n
        for k in range(n - 1, -1, -1):
            z[k] = (m[k][n + j] - sum(m[k][c] * z[c] for c in range(k + 1, n) if m[k][c] != 0)) / m[k][k]
        out.append(z)
    return out


# -- the run ----------------------------------------------------------------------------------------
def _gauss() -> tuple[list[Any], list[list[Any]], list[Any]]:
    """The Gauss–Legendre collocation method of STAGES stages (order 2·STAGES): nodes c (the roots
    of the shifted Legendre polynomial, by the secant method from the classical guesses), A_ij = ∫₀^{c_i} l_j
    and b_j = ∫₀¹ l_j (l_j the Lagrange basis on c), from the moment conditions at mp precision."""
    s = STAGES
    roots = []
    for i in range(1, s // 2 + 1):  # the positive roots (P_s is even: the others are their mirrors)
        x0 = mp.cos(mp.pi * (i - mpf(1) / 4) / (s + mpf(1) / 2))
        roots.append(mp.findroot(lambda x: mp.legendre(s, x), x0, tol=mpf(10) ** (-(DPS - 5))))
    assert s % 2 == 0 and len(set(roots)) == s // 2
    c = sorted([(1 + x) / 2 for x in roots] + [(1 - x) / 2 for x in roots])
    v = [[cj ** k for cj in c] for k in range(s)]
    b = _solve_many(v, [[mpf(1) / (k + 1) for k in range(s)]])[0]
    cols = _solve_many(v, [[ci ** (k + 1) / (k + 1) for k in range(s)] for ci in c])
    return c, cols, b


class Run:
    def __init__(self, pend: Pendulum, step: Any) -> None:
        self.p = pend
        self.h = step
        self.c, self.a, self.b = _gauss()
        self.evals = 0
        self.steps: list[float] = []  # the accepted step lengths (s)

    def f(self, y: list[Any], mode: list[int]) -> list[Any]:
        self.evals += 1
        return [y[1], self.p.solve(y[0], y[1], mode)[0]]

    def step(self, y: list[Any], h: Any, mode: list[int], guess: Any = None) -> tuple[list[Any], Any]:
        """One collocation step: the stage increments Z_i = h·Σⱼ a_ij·f(y + Z_j) by simplified
        Newton (the matrix I − h·A⊗J, J = ∂f/∂y at y by central differences), to TOL (far below the
        method's truncation error)."""
        s = STAGES
        f0 = self.f(y, mode)
        delta = mpf(10) ** (-20)
        jac = [[(self.f([y[0] + delta * (c == 0), y[1] + delta * (c == 1)], mode)[r]
                 - self.f([y[0] - delta * (c == 0), y[1] - delta * (c == 1)], mode)[r]) / (2 * delta)
                for c in range(2)] for r in range(2)]
        n = 2 * s
        mat = [[(1 if i == j else 0) - h * self.a[i // 2][j // 2] * jac[i % 2][j % 2] for j in range(n)]
               for i in range(n)]
        z = list(guess) if guess is not None else [h * self.c[i] * f0[d] for i in range(s) for d in range(2)]
        for _ in range(100):
            fs = [self.f([y[0] + z[2 * i], y[1] + z[2 * i + 1]], mode) for i in range(s)]
            res = [z[2 * i + d] - h * sum(self.a[i][j] * fs[j][d] for j in range(s))
                   for i in range(s) for d in range(2)]
            dz = _solve_many(mat, [res])[0]
            z = [z[i] - dz[i] for i in range(n)]
            if max(abs(v) for v in dz) < mpf(TOL) * (abs(y[0]) + abs(y[1]) + 1) * h:
                break
        else:
            raise RuntimeError("the collocation stages did not converge")
        fs = [self.f([y[0] + z[2 * i], y[1] + z[2 * i + 1]], mode) for i in range(s)]
        return [y[d] + h * sum(self.b[j] * fs[j][d] for j in range(s)) for d in range(2)], (list(y), z)

    def dense(self, poly: Any, theta: Any) -> list[Any]:
        """The collocation polynomial of a step at θ = (t − tₙ)/h (through y at 0 and the stages)."""
        y, z = poly
        nodes = [mpf(0), *self.c]
        values = [list(y)] + [[y[0] + z[2 * i], y[1] + z[2 * i + 1]] for i in range(STAGES)]
        out = [mpf(0), mpf(0)]
        for j, nj in enumerate(nodes):
            w = mpf(1)
            for m_, nm in enumerate(nodes):
                if m_ != j:
                    w *= (theta - nm) / (nj - nm)
            out[0] += w * values[j][0]
            out[1] += w * values[j][1]
        return out

    def predict(self, poly: Any, start: Any, scale: Any) -> list[Any]:
        """Stage increments for a step from θ = ``start`` of length ``scale``·h, off the last step's
        collocation polynomial (Newton's start: its error is the polynomial's, ~h^(s+1))."""
        y0 = self.dense(poly, start)
        out = []
        for ci in self.c:
            u = self.dense(poly, start + scale * ci)
            out += [u[0] - y0[0], u[1] - y0[1]]
        return out

    def events(self, y: list[Any]) -> list[Any]:
        th = self.p.angles(y[0])
        return [y[1], *self.p.relative(self.p.rates(th, mpf(1)))]  # ω and each pin's ρ = (ωᵢ − ωⱼ)/ω

    def start(self, y: list[Any]) -> int:
        """At rest: +1 / −1 the direction it slips in, 0 if it sticks (module docstring)."""
        for s in (1, -1):
            mode = self.p.mode_of(y[0], mpf(0), s)
            eps = self.p.solve(y[0], mpf(0), mode)[0]
            if _sign(eps) == s:
                return s
        return 0

    def go(self, phi0: Any, log: Any = print) -> dict[str, Any]:
        y = [phi0, mpf(0)]
        t = mpf(0)
        e0 = self.p.energy(y[0], y[1])
        switches = []
        s = self.start(y)
        assert s != 0, "released from rest it must move"
        mode = self.p.mode_of(y[0], mpf(0), s)
        h = self.h
        while t < T_MAX:
            g_old = self.events(y)
            # step doubling: one step of h against two of h/2, h halved until they agree to LOCAL
            # (a pin force passing near zero makes |R| nearly a kink: the fixed step cannot see it)
            while True:
                y_full, poly = self.step(y, h, mode)
                y_mid, poly_mid = self.step(y, h / 2, mode, self.predict(poly, mpf(0), mpf(1) / 2))
                y_new, _ = self.step(y_mid, h / 2, mode, self.predict(poly, mpf(1) / 2, mpf(1) / 2))
                err = max(abs(y_full[0] - y_new[0]), abs(y_full[1] - y_new[1]))
                if err <= LOCAL:
                    break
                h = h / 2
            g_new = self.events(y_new)
            crossed = [i for i in range(len(g_old))  # (not the switch just made: its event is ~0 at the start)
                       if _sign(g_old[i]) != _sign(g_new[i]) and abs(g_old[i]) > mpf(10) ** -30]
            if not crossed:
                y, t = y_new, t + h
                self.steps.append(float(h))
                if err <= LOCAL / 1000:
                    h = min(2 * h, self.h)
                continue
            # the first crossing within the step: its θ on the collocation polynomial, then the step
            # length where the event of the step itself is 0 (secant from there)
            first = None
            for i in crossed:
                theta = mp.findroot(lambda th, i=i, poly=poly: self.events(self.dense(poly, th))[i],
                                    (g_old[i] / (g_old[i] - g_new[i]), g_old[i] / (g_old[i] - g_new[i]) * mpf("1.01")),
                                    solver="secant", tol=mpf(10) ** (-30))

                def g(hh: Any, i: int = i, y: list[Any] = y, mode: list[int] = mode, poly: Any = poly,
                      h: Any = h) -> Any:
                    return self.events(self.step(y, hh, mode, self.predict(poly, mpf(0), hh / h))[0])[i]
                hs = mp.findroot(g, (theta * h, theta * h * (1 + mpf(10) ** -6)), solver="secant",
                                 tol=mpf(10) ** (-40), maxsteps=50)
                if first is None or hs < first[0]:
                    first = (hs, i)
            assert first is not None
            hs, i = first
            y, _ = self.step(y, hs, mode, self.predict(poly, mpf(0), hs / h))
            t += hs
            if i == 0:  # a turning point
                y[1] = mpf(0)
                s = self.start(y)
                log(f"turning point t = {mp.nstr(t, 15)}, phi = {mp.nstr(y[0], 15)}: "
                    f"{'sticks' if s == 0 else 'slips ' + str(s)}")
                switches.append({"kind": "stick" if s == 0 else "slip", "t": mp.nstr(t, 30), "phi": mp.nstr(y[0], 30)})
                if s == 0:
                    e = self.p.energy(y[0], y[1])
                    return {"t_stick": mp.nstr(t, 30), "phi_stick": mp.nstr(y[0], 30), "energy0": mp.nstr(e0, 30),
                            "energy_stick": mp.nstr(e, 30), "switches": switches, "evaluations": self.evals,
                            "smallest_step": min(self.steps), "steps": len(self.steps)}
                mode = self.p.mode_of(y[0], mpf(0), s)
            else:  # pin i − 1 reverses its relative rotation
                mode = list(mode)
                mode[i - 1] = -mode[i - 1]
                log(f"reversal of pin {self.p.pins[i - 1][0]} at t = {mp.nstr(t, 15)}")
                switches.append({"kind": f"reversal {self.p.pins[i - 1][0]}", "t": mp.nstr(t, 30),
                                 "phi": mp.nstr(y[0], 30)})
        raise RuntimeError(f"no stick before {T_MAX} s")


def _go(step: str, log: bool) -> dict[str, Any]:
    mp.dps = DPS
    pend = Pendulum(yaml.safe_load(SCENE.read_text(encoding="utf-8")))
    return Run(pend, _n(step)).go(_n(PHI0), log=print if log else (lambda *_: None))


def main() -> None:
    mp.dps = DPS
    data = yaml.safe_load(SCENE.read_text(encoding="utf-8"))
    pend = Pendulum(data)
    if "--branch" in sys.argv:  # the solver's float B at φ0 (a look at the branch only, never the numbers)
        sys.path.insert(0, str(ROOT))
        import solver
        k = solver.load_scene(str(SCENE)).solve(float(PHI0))
        th = pend.angles(_n(PHI0))
        print("solver B", k.point("B").position, "reference B",
              [float(pend.C[0] + pend.l3 * mp.cos(th[2])), float(pend.C[1] + pend.l3 * mp.sin(th[2]))])
        return
    started = time.time()
    from concurrent.futures import ProcessPoolExecutor

    if "--check" in sys.argv:  # the run at twice STEP too, in parallel (the truncation estimate)
        with ProcessPoolExecutor(2) as pool:
            fine_f, coarse_f = pool.submit(_go, STEP, True), pool.submit(_go, str(2 * _n(STEP)), False)
            fine, coarse = fine_f.result(), coarse_f.result()
        diff = {key: mp.nstr(abs(_n(fine[key]) - _n(coarse[key])), 3) for key in ("t_stick", "phi_stick")}
    else:
        fine = _go(STEP, True)
        diff = {"note": CHECKED}
    out = {
        "provenance": ("tests/reference/friction_dynamics_mp.py (mpmath, mp.dps=50, 30 digits written): the scene "
                       "tests/dynamics/scenes/friction_four_bar_pendulum.yaml read with PyYAML; closed-form "
                       "positions, Newton-Euler in absolute coordinates (17 unknowns: centre and angular "
                       "accelerations, four pin forces) with friction couples mu*r*|R| against each pin's "
                       "relative rotation solved by fixed point to 1e-45; the run by 8-stage Gauss-Legendre "
                       f"collocation (order 16), steps of at most {STEP} s each checked by step doubling to 1e-13, "
                       "switches located on the step length; "
                       "stick where neither start (toward +phi, -phi) is consistent. Never the solver."),
        "scene_file": "tests/dynamics/scenes/friction_four_bar_pendulum.yaml",
        "input": {"phi0": PHI0, "omega0": "0", "drive": "free"},
        "units": "t s, phi rad, energy J (T + V, V = -sum m g.r_G)",
        "expected": {k: v for k, v in fine.items() if k != "evaluations"},
        "truncation_estimate": {"against_twice_the_step": diff},
        "evaluations": fine["evaluations"],
        "seconds": round(time.time() - started, 1),
    }
    DATA.write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    print(f"wrote {DATA.relative_to(ROOT)}: {json.dumps(out['expected'])[:400]} diff {diff}")


if __name__ == "__main__":
    main()
