"""Explicit Runge–Kutta steps on plain Python lists: DOP853 (adaptive) and the classical RK4
(fixed step), with their dense outputs (solver.dynamics._stepping drives them).

The state is a handful of numbers (q, q̇ and two work integrals: 4 with one input), so numpy's
per-call overhead is most of scipy's cost per step (≈ 0.26 ms for a DOP853 step of a trivial
right-hand side, against ≈ 20 µs here): the stage sums are ``sum(map(mul, a_row, column))`` over
each component's stage values.

DOP853 is Hairer, Nørsett & Wanner's 8th-order method with the 5th/3rd-order error estimate and
the 7th-order dense output (three more stages), as scipy implements it; its coefficients are
scipy's own (``scipy.integrate._ivp.dop853_coefficients``), read once. The error norm and the
step-size controller are the usual ones (safety 0.9, factors in [0.2, 10], exponent −1/8):
the same steps as scipy's ``DOP853`` up to round-off.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from operator import mul
from typing import Any

from scipy.integrate._ivp import dop853_coefficients as _dop
from scipy.integrate._ivp.rk import RK45 as _RK45

__all__ = ["unrolled", "dop853_step_loop", "dopri5_step_loop",
           "Dense", "PolyDense", "Rhs", "dop853_dense", "dop853_step", "dopri5_dense", "dopri5_error", "dopri5_step",
           "error_norm",
           "hermite", "initial_step", "rk4_step", "ERROR_EXPONENT", "MAX_FACTOR", "MIN_FACTOR", "SAFETY"]

#: f(t, y) → y' (lists of floats); raises solver.errors.AssemblyError where it cannot be assembled
Rhs = Callable[[float, list[float]], list[float]]

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0
#: −1/(order of the error estimate + 1)
ERROR_EXPONENT = -1.0 / 8.0

_STAGES = _dop.N_STAGES
_C = [float(c) for c in _dop.C]
_A = [[float(a) for a in row[:s]] for s, row in enumerate(_dop.A)]  # row s: its first s entries
_B = [float(b) for b in _dop.B]
_E3 = [float(e) for e in _dop.E3]
_E5 = [float(e) for e in _dop.E5]
_D = [[float(d) for d in row] for row in _dop.D]

# Dormand and Prince's 5(4) pair (scipy's RK45 coefficients): six stages and the first same as
# last; its continuous extension of 4th order (the rows of P, powers x … x⁴)
_C5 = [float(c) for c in _RK45.C]
_A5 = [[float(a) for a in row[:s]] for s, row in enumerate(_RK45.A)]
_B5 = [float(b) for b in _RK45.B]
_E5_PAIR = [float(e) for e in _RK45.E]
_P5 = [[float(p) for p in row] for row in _RK45.P]


def dop853_step(f: Rhs, t: float, y: list[float], fy: list[float], h: float) -> tuple[list[float], list[float],
                                                                                         list[list[float]]]:
    """One DOP853 step of size ``h`` from (t, y) with fy = f(t, y): (y_new, f_new, columns), where
    columns[j] holds component j's 13 stage values (the last: f_new, for the error estimate).
    Runs the tableau unrolled for len(y) components (:func:`unrolled`)."""
    return unrolled("dop853", len(y))(f, t, y, fy, h)


def dop853_step_loop(f: Rhs, t: float, y: list[float], fy: list[float], h: float) -> tuple[list[float],
                                                                                           list[float],
                                                                                           list[list[float]]]:
    """:func:`dop853_step` as loops over the tableau (the reference the unrolled step is tested against)."""
    return _step_loop("dop853", f, t, y, fy, h)


def _step_loop(method: str, f: Rhs, t: float, y: list[float], fy: list[float], h: float) -> tuple[
        list[float], list[float], list[list[float]]]:
    """One explicit step of ``method``'s tableau (:data:`_TABLEAUS`) as loops: the stages'
    columns per component, the new state, its evaluation."""
    stages, a, b, c = _TABLEAUS[method]
    n = len(y)
    cols = [[v] for v in fy]
    rng = range(n)
    for s in range(1, stages):
        row = a[s]
        stage = [y[j] + h * sum(map(mul, row, cols[j])) for j in rng]
        ks = f(t + c[s] * h, stage)
        for j in rng:
            cols[j].append(ks[j])
    y_new = [y[j] + h * sum(map(mul, b, cols[j])) for j in rng]
    f_new = f(t + h, y_new)
    for j in rng:
        cols[j].append(f_new[j])
    return y_new, f_new, cols


def error_norm(cols: list[list[float]], h: float, y: Sequence[float], y_new: Sequence[float], rtol: float,
               atol: float) -> float:
    """The step's scaled error (accept where < 1): DOP853's blend of its 5th- and 3rd-order
    estimates, component j against atol + rtol·max(|y_j|, |y_new,j|)."""
    e5 = e3 = 0.0
    for j, col in enumerate(cols):
        scale = atol + rtol * max(abs(y[j]), abs(y_new[j]))
        a = sum(map(mul, _E5, col)) / scale
        b = sum(map(mul, _E3, col)) / scale
        e5 += a * a
        e3 += b * b
    if e5 == 0.0 and e3 == 0.0:
        return 0.0
    return abs(h) * e5 / math.sqrt((e5 + 0.01 * e3) * len(cols))


class Dense:
    """A step's interpolant y(t) on [t_old, t_old + h]: y_old + the nested form in x and 1 − x of
    its coefficient rows (DOP853's 7th-order one; a cubic Hermite for RK4)."""

    __slots__ = ("t_old", "t", "h", "y_old", "rows")

    def __init__(self, t_old: float, h: float, y_old: list[float], rows: list[list[float]]) -> None:
        self.t_old, self.h, self.t, self.y_old, self.rows = t_old, h, t_old + h, y_old, rows

    def __call__(self, t: float) -> list[float]:
        x = (t - self.t_old) / self.h
        y = [0.0] * len(self.y_old)
        for i, row in enumerate(reversed(self.rows)):
            m = x if i % 2 == 0 else 1.0 - x
            y = [(a + b) * m for a, b in zip(y, row)]
        return [a + b for a, b in zip(y, self.y_old)]

    def component(self, t: float, j: int) -> float:
        """Component ``j`` of y(t) alone."""
        x = (t - self.t_old) / self.h
        y = 0.0
        for i, row in enumerate(reversed(self.rows)):
            y = (y + row[j]) * (x if i % 2 == 0 else 1.0 - x)
        return y + self.y_old[j]


def dop853_dense(f: Rhs, t: float, y: list[float], y_new: list[float], fy: list[float], f_new: list[float],
                 cols: list[list[float]], h: float) -> Dense:
    """DOP853's dense output of the step (three more evaluations of ``f``)."""
    n = len(y)
    rng = range(n)
    cols = [list(c) for c in cols]
    for s in range(_STAGES + 1, len(_C)):
        row = _A[s]
        stage = [y[j] + h * sum(map(mul, row, cols[j])) for j in rng]
        ks = f(t + _C[s] * h, stage)
        for j in rng:
            cols[j].append(ks[j])
    delta = [b - a for a, b in zip(y, y_new)]
    rows = [delta, [h * a - d for a, d in zip(fy, delta)],
            [2.0 * d - h * (a + b) for d, a, b in zip(delta, f_new, fy)]]
    rows += [[h * sum(map(mul, d, cols[j])) for j in rng] for d in _D]
    return Dense(t, h, y, rows)


def hermite(t: float, h: float, y: list[float], y_new: list[float], fy: list[float], f_new: list[float]) -> Dense:
    """The cubic Hermite interpolant of a step (its ends and slopes), in :class:`Dense`'s form."""
    delta = [b - a for a, b in zip(y, y_new)]
    return Dense(t, h, y, [delta, [h * a - d for a, d in zip(fy, delta)],
                           [2.0 * d - h * (a + b) for d, a, b in zip(delta, f_new, fy)]])


def dopri5_step(f: Rhs, t: float, y: list[float], fy: list[float], h: float) -> tuple[list[float], list[float],
                                                                                         list[list[float]]]:
    """One step of Dormand and Prince's 5(4) pair from (t, y) with fy = f(t, y): (y_new, f_new,
    columns), columns[j] component j's 7 stage values (the last f_new); 6 evaluations of ``f``.
    The integrator takes it for a step cut short by a kink (solver.dynamics._stepping), where
    DOP853's 12 evaluations buy an accuracy far beyond the tolerance. Unrolled (:func:`unrolled`)."""
    return unrolled("dopri5", len(y))(f, t, y, fy, h)


def dopri5_step_loop(f: Rhs, t: float, y: list[float], fy: list[float], h: float) -> tuple[list[float],
                                                                                           list[float],
                                                                                           list[list[float]]]:
    """:func:`dopri5_step` as loops over the tableau (the reference of the unrolled step)."""
    return _step_loop("dopri5", f, t, y, fy, h)


def dopri5_error(cols: list[list[float]], h: float, y: Sequence[float], y_new: Sequence[float], rtol: float,
                 atol: float) -> float:
    """The 5(4) pair's scaled error (accept where < 1; the RMS norm, as scipy's RK45)."""
    total = 0.0
    for j, col in enumerate(cols):
        e = h * sum(map(mul, _E5_PAIR, col)) / (atol + rtol * max(abs(y[j]), abs(y_new[j])))
        total += e * e
    return math.sqrt(total / len(cols))


class PolyDense(Dense):
    """A step's interpolant y_old + h·Σ_p Q_p·x^p (x = (t − t_old)/h, p = 1 … 4): the 5(4) pair's
    continuous extension, in :class:`Dense`'s interface."""

    __slots__ = ()

    def __call__(self, t: float) -> list[float]:
        x = (t - self.t_old) / self.h
        return [y0 + self.h * x * (q[0] + x * (q[1] + x * (q[2] + x * q[3]))) for y0, q in zip(self.y_old, self.rows)]

    def component(self, t: float, j: int) -> float:
        x = (t - self.t_old) / self.h
        q = self.rows[j]
        return self.y_old[j] + self.h * x * (q[0] + x * (q[1] + x * (q[2] + x * q[3])))


_P5_COLUMNS = [[p[i] for p in _P5] for i in range(4)]


def dopri5_dense(t: float, y: list[float], cols: list[list[float]], h: float) -> PolyDense:
    """The 5(4) pair's dense output of a step (no more evaluations)."""
    return PolyDense(t, h, y, [[sum(map(mul, p, col)) for p in _P5_COLUMNS] for col in cols])


_TABLEAUS = {"dop853": (_STAGES, _A, _B, _C), "dopri5": (6, _A5, _B5, _C5)}
_UNROLLED: dict[tuple[str, int], Callable[..., Any]] = {}


def unrolled(method: str, n: int) -> Callable[..., Any]:
    """The step of ``method`` ("dop853", "dopri5") for states of ``n`` components, generated from
    its tableau with the coefficients as literals and each component's stage sums written out
    (no loop, ``sum`` or ``map`` per stage: a third of the step's own cost with four components);
    the same arithmetic as the loops of :func:`dop853_step_loop` / :func:`dopri5_step_loop`, in
    the same order. Made once per (method, n)."""
    key = (method, n)
    fn = _UNROLLED.get(key)
    if fn is not None:
        return fn
    stages, a, b, c = _TABLEAUS[method]
    rng = range(n)

    def combo(row: Sequence[float], j: int) -> str:
        terms = [f"{coef!r} * k{i}_{j}" for i, coef in enumerate(row) if coef != 0.0]
        return f"y{j} + h * ({' + '.join(terms)})" if terms else f"y{j}"

    lines = ["def step(f, t, y, fy, h):",
             f"    {', '.join(f'y{j}' for j in rng)}, = y",
             f"    {', '.join(f'k0_{j}' for j in rng)}, = fy"]
    for s in range(1, stages):
        stage = ", ".join(combo(a[s], j) for j in rng)
        lines.append(f"    {', '.join(f'k{s}_{j}' for j in rng)}, = f(t + {c[s]!r} * h, [{stage}])")
    lines.append(f"    y_new = [{', '.join(combo(b, j) for j in rng)}]")
    lines.append("    f_new = f(t + h, y_new)")
    cols = ", ".join("[" + ", ".join([f"k{s}_{j}" for s in range(stages)] + [f"f_new[{j}]"]) + "]" for j in rng)
    lines.append(f"    return y_new, f_new, [{cols}]")
    namespace: dict[str, Any] = {}
    exec(compile("\n".join(lines), f"<{method} step, {n} components>", "exec"), namespace)
    fn = _UNROLLED[key] = namespace["step"]
    return fn


def rk4_step(f: Rhs, t: float, y: list[float], fy: list[float], h: float) -> list[float]:
    """One classical Runge–Kutta step (4th order, four evaluations with fy = f(t, y) given)."""
    half = 0.5 * h
    k2 = f(t + half, [a + half * b for a, b in zip(y, fy)])
    k3 = f(t + half, [a + half * b for a, b in zip(y, k2)])
    k4 = f(t + h, [a + h * b for a, b in zip(y, k3)])
    sixth = h / 6.0
    return [a + sixth * (b + 2.0 * (c + d) + e) for a, b, c, d, e in zip(y, fy, k2, k3, k4)]


def initial_step(f: Rhs, t: float, y: list[float], fy: list[float], rtol: float, atol: float,
                 max_step: float) -> float:
    """A first step size for an 8th-order method (Hairer, Nørsett & Wanner's rule)."""
    n = len(y)
    scale = [atol + rtol * abs(v) for v in y]
    d0 = math.sqrt(sum((v / s) ** 2 for v, s in zip(y, scale)) / n)
    d1 = math.sqrt(sum((v / s) ** 2 for v, s in zip(fy, scale)) / n)
    h0 = 1e-6 if d0 < 1e-5 or d1 < 1e-5 else 0.01 * d0 / d1
    h0 = min(h0, max_step)
    f1 = f(t + h0, [a + h0 * b for a, b in zip(y, fy)])
    d2 = math.sqrt(sum(((b - a) / s) ** 2 for a, b, s in zip(fy, f1, scale)) / n) / h0
    if d1 <= 1e-15 and d2 <= 1e-15:
        h1 = max(1e-6, h0 * 1e-3)
    else:
        h1 = (0.01 / max(d1, d2)) ** (1.0 / 8.0)
    return min(100.0 * h0, h1, max_step)
