"""The integrators' step loop: DOP853 with step-size control, or RK4 with a fixed step, both
breakpoint to breakpoint (solver.dynamics._breaks), on plain Python lists (solver.dynamics._rk).

:meth:`Integrator.step` makes one accepted step and returns its interpolant (:class:`~._rk.Dense`,
valid from the step's start to ``Integrator.t``). Where the scene has tables of an input (or a
motor's torque–speed table), each step holds the pieces the motion is in, and a step that would
pass the nearest end of the held window is aimed at it (q + q̇τ + ½q̈τ² + ⅙q⃛τ³ at its start, the
jerk from the last step). DOP853: a step that ends within √rtol of its move from the kink lands
on it (the error O(δ²·Δslope)); one that passes it further is cut there on its dense output (7th
order). Such a step, cut short by the kink, is tried first with Dormand and Prince's 5(4) pair
(six evaluations against DOP853's twelve; kept where its own error estimate meets the tolerance
and it lands, else DOP853 takes the step): on the engine at 200 rad/s the controller's step is
about seven 5° pieces long, so every step is a piece and half the evaluations went into an
accuracy far beyond the tolerance. RK4: it lands on its aim, with one more try from its cubic
Hermite interpolant where it missed by more than ``tolerances.DYNAMICS_KINK_MISS`` of its move.
The next step holds the next piece. Where a stage cannot be assembled the step is rejected and
shrunk (DOP853: fivefold, RK4: halved, also where its stages pass a toggle its end does not
reach); below the spacing of floats at t the integrator fails with :class:`StepFailure` (the
caller says where, with the group and the reason).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

from ..errors import AssemblyError
from ..tolerances import DYNAMICS_KINK_AIM, DYNAMICS_KINK_MISS, DYNAMICS_TOGGLE
from ._breaks import Breaks
from ._rk import (
    ERROR_EXPONENT,
    MAX_FACTOR,
    MIN_FACTOR,
    SAFETY,
    Dense,
    Rhs,
    dop853_dense,
    dop853_step,
    dopri5_dense,
    dopri5_error,
    dopri5_step,
    error_norm,
    hermite,
    initial_step,
    rk4_step,
)

__all__ = ["Integrator", "StepFailure", "METHODS"]

#: the methods of this loop: adaptive DOP853, fixed-step RK4
METHODS = ("DOP853", "RK4")
#: DOP853: a step cut by a kink to at most this share of the controller's step is tried first
#: with Dormand and Prince's 5(4) pair (6 evaluations, not 12), kept where its own error estimate
#: meets the tolerance and it lands on the kink (or short of it)
SHORT_STEP = 0.5
#: RK4 watches its stages' conditioning (for a toggle between a step's ends) from a step that
#: starts below this (1: well conditioned)
WATCH_BELOW = 0.5


class StepFailure(Exception):
    """The step size fell below the spacing of floats at ``t``: a stage could not be assembled
    however short the step (``group``, ``reason`` of the last AssemblyError) or the error could
    not be met."""

    def __init__(self, t: float, y: list[float], group: str, reason: str) -> None:
        super().__init__(reason)
        self.t, self.y, self.group, self.reason = t, y, group, reason


class Integrator:
    """``f`` from (t0, y0) where y = (q, q̇, …) with k inputs; ``method`` "DOP853" (``rtol``,
    ``atol``, ``max_step``) or "RK4" (``step``: the fixed step size, s)."""

    def __init__(self, f: Rhs, t0: float, y0: Sequence[float], *, k: int, method: str = "DOP853",
                 rtol: float = 1e-9, atol: float = 1e-9, step: float | None = None, max_step: float = math.inf,
                 breaks: Breaks | None = None, conditioning: Callable[[], float] | None = None) -> None:
        if method not in METHODS:
            raise ValueError(f"method must be one of {', '.join(METHODS)}, got {method!r}")
        self.f, self.k, self.method = f, k, method
        #: RK4: the conditioning of f's last evaluation (a step whose stages pass a toggle while its
        #: end does not is halved until its end is there: a fixed step must not jump across one)
        self._conditioning = conditioning
        self.rtol, self.atol, self.max_step = rtol, atol, max_step
        self.breaks = breaks if breaks else None
        self.t = float(t0)
        self.y = [float(v) for v in y0]
        self.nfev = 0
        self._held: list[tuple[dict[Any, Any], Any, Any]] = []
        #: (t, q̈) at the last step's start: the jerk for aiming at a kink
        self._previous: tuple[float, list[float]] | None = None
        self._window: list[tuple[float, float]] | None = None  # held at the first step, with fy's direction
        self.fy = self._f(self.t, self.y)
        if method == "RK4":
            if step is None or not (step > 0 and math.isfinite(step)):
                raise ValueError(f"RK4 needs a positive finite step, got {step!r}")
            self.h = float(step)
        else:
            self._hold()
            try:
                self.h = initial_step(self._f, self.t, self.y, self.fy, rtol, atol, max_step)
            finally:
                self._let_go()
        self.fixed = float(step) if method == "RK4" and step is not None else None

    # ------------------------------------------------------------------ the right-hand side
    def _f(self, t: float, y: list[float]) -> list[float]:
        self.nfev += 1
        return self.f(t, y)

    def _hold(self, at: list[float] | None = None, direction: list[float] | None = None) -> None:
        if self.breaks is None:
            return
        if self._window is None:
            k = self.k
            q = at if at is not None else self.y[:2 * k]
            if direction is None:
                rates = self.fy[:2 * k]
                direction = [w if w != 0.0 else a for w, a in zip(rates, self.fy[k:2 * k] + [0.0] * k)]
            self._window = self.breaks.hold(q, direction)
            self._held = self.breaks.held()
        else:
            for store, key, line in self._held:
                store[key] = line

    def _let_go(self) -> None:
        if self.breaks is not None:
            self.breaks.release()

    # ------------------------------------------------------------------ one step
    def step(self, t_bound: float = math.inf) -> Dense:
        """One accepted step, ending at ``t_bound`` at most (RK4: exactly its fixed step, or the
        rest up to ``t_bound``); the step's interpolant."""
        self._hold()
        try:
            return self._step(t_bound)
        finally:
            self._let_go()

    def _aim(self, h: float) -> tuple[float, bool]:
        """The step size, shortened to end at the nearest end of the held window (DOP853: a
        little past it, to be cut on its dense output), and whether it was."""
        window = self._window
        if window is None:
            return h, False
        k, y, fy = self.k, self.y, self.fy
        best = h
        previous = self._previous
        for i, (lo, hi) in enumerate(window):
            if lo == -math.inf and hi == math.inf:
                continue
            q, w, e = y[i], fy[i], (fy[k + i] if i < k else 0.0)  # a rate's window: linear in time
            # the jerk from the last step's two accelerations: q + q̇τ + ½q̈τ² + ⅙q⃛τ³, off by O(τ⁴)
            jerk = (e - previous[1][i]) / (self.t - previous[0]) if previous and i < k else 0.0
            # an end behind the motion is reached only where it turns back within the step (its rate
            # w + eτ + ½jτ² cannot reach 0 before h where |w| > |e|·h + ½|j|·h²)
            turns = abs(w) <= (abs(e) + 0.5 * abs(jerk) * h) * h
            for bound, ahead, behind in ((lo, q > lo, w > 0.0), (hi, q < hi, w < 0.0)):
                # (a state a rounding outside its window, just past a kink: that end is behind it)
                if ahead and (turns or not behind) and math.isfinite(bound):
                    tau = _reach(bound - q, w, e)
                    if tau is not None and jerk:
                        for _ in range(2):  # Newton on the cubic from the quadratic's root
                            slope = w + e * tau + 0.5 * jerk * tau * tau
                            if slope == 0.0:
                                break
                            tau -= (w * tau + 0.5 * e * tau * tau + jerk * tau ** 3 / 6.0 - (bound - q)) / slope
                        tau = tau if tau > 0.0 else None
                    if tau is not None and tau < best:
                        best = tau
        if best >= h:
            return h, False
        return (best if self.method == "RK4" else best * (1.0 + DYNAMICS_KINK_AIM)), True

    def _step(self, t_bound: float) -> Dense:
        t = self.t
        rest = t_bound - t
        if not rest > 0:
            raise ValueError(f"t_bound {t_bound!r} is not after t = {t!r}")
        if rest <= self._min_step(t):  # t_bound a rounding past t (a tick's time from ns): there already
            self.t = t_bound
            return Dense(t, rest, self.y, [[0.0] * len(self.y)])
        h = min(self.fixed if self.fixed is not None else self.h, self.max_step)
        h, aimed = self._aim(h)
        end = None
        if h >= rest or (self.fixed is not None and rest - h <= 1e-9 * h):
            h, end = rest, t_bound  # the step ends on t_bound, exactly
        if self.method == "RK4":
            return self._rk4(t, h, end)
        if aimed and end is None and h <= SHORT_STEP * self.h:
            dense = self._dopri5(t, h, end)
            if dense is not None:
                return dense
        return self._dop853(t, h, end)

    def _min_step(self, t: float) -> float:
        return 10.0 * abs(math.nextafter(t, math.inf) - t)

    def _dop853(self, t: float, h: float, end: float | None) -> Dense:
        y, fy = self.y, self.fy
        rejected = False
        fault: tuple[str, str] = ("?", "the step size fell below the spacing of floats")
        while True:
            if h < self._min_step(t):
                raise StepFailure(t, y, *fault)
            try:
                self.nfev += 12  # (counted here: one call fewer per evaluation than through _f)
                y_new, f_new, cols = dop853_step(self.f, t, y, fy, h)
                err = error_norm(cols, h, y, y_new, self.rtol, self.atol)
            except AssemblyError as exc:
                fault = (exc.group, exc.reason)
                err = math.nan
            if err < 1.0:
                factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, SAFETY * err ** ERROR_EXPONENT)
                if rejected:
                    factor = min(1.0, factor)
                break
            h *= MIN_FACTOR if math.isnan(err) else max(MIN_FACTOR, SAFETY * err ** ERROR_EXPONENT)
            rejected, end = True, None
        h_next = h * factor
        dense: Dense | None = None
        land = math.sqrt(self.rtol)  # a step this share of its move off a kink lands on it: O(δ²·Δslope)
        crossing = self._crossing(y_new, slack=land)
        if crossing is not None and (abs(y_new[crossing[0]] - crossing[1])
                                     <= land * abs(y_new[crossing[0]] - y[crossing[0]])):
            dense = _LazyDense(self, t, y, y_new, fy, f_new, cols, h)
            self._advance(t + h if end is None else end, y_new, f_new=f_new, crossed=crossing)
        elif crossing is not None:
            dense = dop853_dense(self._f, t, y, y_new, fy, f_new, cols, h)
            i, bound = crossing
            tau = _root(lambda s: dense.component(t + s, i) - bound, h)
            t_cut = t + tau
            y_cut = dense(t_cut)
            y_cut[i] = bound  # (it is, to the interpolant's round-off)
            self._advance(t_cut, y_cut, crossed=(i, bound))
            dense.t = t_cut
        else:
            dense = _LazyDense(self, t, y, y_new, fy, f_new, cols, h)  # type: ignore[assignment]
            self._advance(t + h if end is None else end, y_new, f_new=f_new)
        self.h = h_next
        assert dense is not None
        return dense

    def _dopri5(self, t: float, h: float, end: float | None) -> Dense | None:
        """The short step with the 5(4) pair, or None where DOP853 must take it (its error
        estimate misses the tolerance, a stage cannot be assembled, or it passes the kink by more
        than the landing share: the cut is DOP853's, on its 7th-order dense output). The
        controller's step stays what DOP853 last proposed."""
        y, fy = self.y, self.fy
        try:
            self.nfev += 6
            y_new, f_new, cols = dopri5_step(self.f, t, y, fy, h)
        except AssemblyError:
            return None
        if not dopri5_error(cols, h, y, y_new, self.rtol, self.atol) < 1.0:
            return None
        land = math.sqrt(self.rtol)
        crossing = self._crossing(y_new, slack=land)
        if crossing is not None and (abs(y_new[crossing[0]] - crossing[1])
                                     > land * abs(y_new[crossing[0]] - y[crossing[0]])):
            return None
        self._advance(t + h if end is None else end, y_new, f_new=f_new, crossed=crossing)
        return _LazyPoly(t, y, cols, h)

    def _rk4(self, t: float, h: float, end: float | None) -> Dense:
        y, fy = self.y, self.fy
        fault: tuple[str, str] = ("?", "the step size fell below the spacing of floats")
        tries = 0
        landed = False
        while True:
            if h < self._min_step(t):
                raise StepFailure(t, y, *fault)
            worst = [math.inf]
            f = self.f
            if self._conditioning is not None and self._conditioning() < WATCH_BELOW:
                read = self._conditioning

                def f(t: float, y: list[float], worst: list[float] = worst, read: Any = read) -> list[float]:
                    out = self.f(t, y)
                    worst[0] = min(worst[0], read())
                    return out
            try:
                self.nfev += 4  # (counted here: no call of _f per evaluation)
                y_new = rk4_step(f, t, y, fy, h)
                f_new = self.f(t + h, y_new)
            except AssemblyError as exc:
                fault = (exc.group, exc.reason)
                h, end = 0.5 * h, None
                continue
            if not all(map(math.isfinite, f_new)) or not all(map(math.isfinite, y_new)):
                # past a toggle (M singular within the step): shorter, until its end is a state
                fault = ("?", "the motion is not finite beyond this point (a singular position)")
                h, end = 0.5 * h, None
                continue
            if self._conditioning is not None and worst[0] < DYNAMICS_TOGGLE <= self._conditioning():
                h, end = 0.5 * h, None  # across a toggle: shorter, until the step ends at it
                continue
            # the kink passed, or reached within DYNAMICS_KINK_MISS of the move (landed on it)
            crossing = self._crossing(y_new, slack=DYNAMICS_KINK_MISS)
            if crossing is None:
                break
            i, bound = crossing
            landed = abs(y_new[i] - bound) <= DYNAMICS_KINK_MISS * abs(y_new[i] - y[i])
            if landed or tries:
                break  # landed on the kink (the interpolant's crossing is needed only where it missed)
            cubic = hermite(t, h, y, y_new, fy, f_new)
            tau = _root(lambda s, cubic=cubic, i=i, bound=bound: cubic.component(t + s, i) - bound, h)
            if tau <= 0.0:
                break
            h, tries, end = tau, 1, None  # once more, from the interpolant's crossing
        t_new = t + h if end is None else end
        if crossing is not None:
            # landed: f_new, evaluated on the piece left, is f on the next one (the tables are
            # continuous at their kinks) within DYNAMICS_KINK_MISS of the move times the change of
            # slope, as DOP853's landing step reuses it; otherwise f is evaluated anew there
            self._advance(t_new, y_new, f_new=f_new if landed else None, crossed=crossing)
        else:
            self._advance(t_new, y_new, f_new=f_new)
        return _LazyHermite(t, h, y, y_new, fy, self.fy if crossing is not None else f_new)

    def _crossing(self, y_new: list[float], *, slack: float = 0.0) -> tuple[int, float] | None:
        """(component, the window's end) that the step passed first (or reached within ``slack``
        of the step's move), or None."""
        window = self._window
        if window is None:
            return None
        k, y = self.k, self.y
        out = None
        best = -math.inf
        for i, (lo, hi) in enumerate(window):
            q, dq = y_new[i], y_new[i] - y[i]
            near = slack * abs(dq)
            for bound, past, toward in ((hi, q - hi, dq > 0.0), (lo, lo - q, dq < 0.0)):
                if toward and past > -near and math.isfinite(bound):
                    # the earliest crossing: the one the step passed by the most, relative to its move
                    share = past / abs(dq) if dq else math.inf
                    if share > best:
                        best, out = share, (i, bound)
        del k
        return out

    def _advance(self, t: float, y: list[float], *, f_new: list[float] | None = None,
                 crossed: tuple[int, float] | None = None) -> None:
        """The new step's start; after a crossing, the next piece is held and f evaluated anew."""
        k = self.k
        self._previous = (self.t, self.fy[k:2 * k]) if t > self.t else None
        self.t, self.y = t, y
        if crossed is None:
            assert f_new is not None
            self.fy = f_new
            return
        i, bound = crossed
        k = self.k
        reuse = f_new is not None and not self.breaks.jumps  # type: ignore[union-attr]
        q = list(y[:2 * k])
        direction = [w if w != 0.0 else 1.0 for w in y[k:2 * k]] + [0.0] * k
        lo, hi = self._window[i] if self._window is not None else (-math.inf, math.inf)
        up = bound == hi
        direction[i] = 1.0 if up else -1.0
        q[i] = bound + (1.0 if up else -1.0) * 64.0 * math.ulp(bound)
        self._let_go()
        self._window = None
        self._hold(q, direction)
        # the tables are continuous at their kinks: f there is the same on either piece
        self.fy = f_new if reuse else self._f(t, y)  # type: ignore[assignment]


class _LazyDense(Dense):
    """DOP853's dense output, computed on first use (three more evaluations, with the step's
    pieces held)."""

    __slots__ = ("_args", "_owner", "_held", "_dense")
    _dense: Dense | None

    def __init__(self, owner: Integrator, t: float, y: list[float], y_new: list[float], fy: list[float],
                 f_new: list[float], cols: list[list[float]], h: float) -> None:
        super().__init__(t, h, y, [])
        self._owner, self._held, self._dense = owner, list(owner._held), None
        self._args = (y_new, fy, f_new, cols)

    def __call__(self, t: float) -> list[float]:
        if self._dense is None:
            y_new, fy, f_new, cols = self._args
            owner = self._owner
            for store, key, line in self._held:
                store[key] = line
            try:
                self._dense = dop853_dense(owner._f, self.t_old, self.y_old, y_new, fy, f_new, cols, self.h)
            finally:
                for store, key, _ in self._held:
                    store.pop(key, None)
            self._args = None  # type: ignore[assignment]
        return self._dense(t)


class _LazyHermite(Dense):
    """RK4's cubic Hermite interpolant of a step, made on first use (a tick that lands on the
    step's end never reads it)."""

    __slots__ = ("_ends", "_dense")
    _dense: Dense | None

    def __init__(self, t: float, h: float, y: list[float], y_new: list[float], fy: list[float],
                 f_new: list[float]) -> None:
        super().__init__(t, h, y, [])
        self._ends, self._dense = (y_new, fy, f_new), None

    def _made(self) -> Dense:
        if self._dense is None:
            y_new, fy, f_new = self._ends
            self._dense = hermite(self.t_old, self.h, self.y_old, y_new, fy, f_new)
        return self._dense

    def __call__(self, t: float) -> list[float]:
        return self._made()(t)

    def component(self, t: float, j: int) -> float:
        return self._made().component(t, j)


class _LazyPoly(Dense):
    """The 5(4) pair's dense output, its rows computed on first use (no evaluations)."""

    __slots__ = ("_cols", "_dense")
    _dense: Dense | None

    def __init__(self, t: float, y: list[float], cols: list[list[float]], h: float) -> None:
        super().__init__(t, h, y, [])
        self._cols, self._dense = cols, None

    def _made(self) -> Dense:
        if self._dense is None:
            self._dense = dopri5_dense(self.t_old, self.y_old, self._cols, self.h)
        return self._dense

    def __call__(self, t: float) -> list[float]:
        return self._made()(t)

    def component(self, t: float, j: int) -> float:
        return self._made().component(t, j)


def _reach(d: float, w: float, e: float) -> float | None:
    """The first τ > 0 with ½e·τ² + w·τ − d = 0, or None (the roots without cancellation)."""
    disc = w * w + 2.0 * e * d
    if disc < 0.0:
        return None
    qq = -0.5 * (w + math.copysign(math.sqrt(disc), w))
    roots = []
    if qq != 0.0:
        roots.append(-d / qq)
        if e != 0.0:
            roots.append(2.0 * qq / e)
    positive = [r for r in roots if r > 0.0 and math.isfinite(r)]
    return min(positive) if positive else None


def _root(g: Any, h: float) -> float:
    """The zero of ``g`` on [0, h], g(0)·g(h) ≤ 0: the secant method kept in its bracket (the
    function, a coordinate along a short step, is nearly linear: a few iterations)."""
    a, b = 0.0, h
    ga, gb = g(a), g(b)
    if gb == 0.0 or ga * gb > 0.0:
        return b if abs(gb) <= abs(ga) else a
    x0, g0, x1, g1 = a, ga, b, gb
    s = b
    for _ in range(60):
        s = x1 - g1 * (x1 - x0) / (g1 - g0) if g1 != g0 else 0.5 * (a + b)
        if not a < s < b:
            s = 0.5 * (a + b)
        gs = g(s)
        if gs == 0.0 or abs(s - x1) <= 1e-14 * h:
            return s
        if (gs > 0.0) == (ga > 0.0):
            a, ga = s, gs
        else:
            b, gb = s, gs
        x0, g0, x1, g1 = x1, g1, s, gs
    return s
