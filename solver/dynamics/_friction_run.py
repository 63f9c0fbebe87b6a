"""A run of forward dynamics with Coulomb friction: segments between the friction's switches
(docs/dynamics.md#friction).

The friction's direction switches where a relative velocity passes through zero, so the right-hand
side has a jump there. A Runge–Kutta step across a jump is no longer of its order, so the run is
cut into **segments** on the own step loop (solver.dynamics._run), each ended by a terminal event:

* the input's rate q̇ = 0 (a turning point): the **stick test** — the holding interval [Q₋, Q₊]
  at that q (solver.dynamics._friction.FrictionDynamics.holding); inside it the input sticks (the
  state holds, ε = 0) until the drive leaves it, outside it slips on, toward +q beyond Q₊ and
  toward −q below Q₋ (one line in the run's ``messages`` each);
* an element's relative-velocity analog v′(q) = 0 (a pin whose relative rotation reverses while
  the input moves): the next segment starts there with that element's friction set by the sign
  of its relative acceleration v″·q̇².

Within a segment the friction's directions and the motion's sign are held fixed (its *mode*,
``FrictionEquation.mode``), so the equation is smooth across the switch that ends it: the step
that crosses it is an ordinary step, and the event is located on its dense output. Each
segment's events carry their direction, so the switch just made is not found again at the next
segment's start. The state is (q, q̇, W_drive, W_other, W_friction), W_friction = −∫ P_loss dt
the friction's work (≤ 0), so that T + V − W_drive − W_other − W_friction is constant.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from scipy.optimize import brentq

from ..errors import AssemblyError, DynamicsError
from ._equation import Equation
from ._friction import FrictionDynamics
from ._run import Outcome, Solution, run
from .drive import Drive
from .reduced import ReducedModel

__all__ = ["FrictionEquation", "FrictionOutcome", "run_with_friction", "first_outside", "MAX_SWITCHES"]

#: At most this many switches (turning points, reversals, stick–slips) in one run: a run past it
#: stops with one line (a chatter that would not end).
MAX_SWITCHES = 100_000
#: While the input sticks under a drive that depends on the time, the drive is sampled this many
#: times over the rest of the run (or every ``dt``/``max_step``, if finer) to find where it leaves
#: the holding interval, then located by Brent's method.
STICK_SAMPLES = 2000


class FrictionEquation(Equation):
    """The right-hand side y' of y = (q, q̇, W_drive, W_other, W_friction) with friction, one input,
    in a segment's local time (``t0`` its start: the drive reads t0 + t)."""

    def __init__(self, model: ReducedModel, drive: Drive) -> None:
        super().__init__(model, drive)
        assert isinstance(model.friction, FrictionDynamics)
        self.friction: FrictionDynamics = model.friction
        self.t0 = 0.0
        self.slip = 0.0  # where q̇ = 0: the direction the input slips in
        self.override: dict[int, float] | None = None  # at the segment's start: element → d
        #: the segment's friction directions and motion's sign, held until its first switch
        self.mode: tuple[list[float], float] | None = None
        #: the drive's effort on floats where it has one (solver.dynamics.drive: the same effort)
        self._one: Callable[[float, float, float], float] | None = getattr(drive, "one", None)

    def rates(self, t: float, y: list[float]) -> list[float]:
        """y' at (t, y) on plain lists, as :meth:`Equation.rates` (faults kept and counted); ``t`` is
        the segment's local time (the drive reads t0 + t)."""
        if not all(map(math.isfinite, y[:2])):
            return [math.nan] * len(y)
        q, w = y[0], y[1]
        one = self._one
        try:
            effort = one(self.t0 + t, q, w) if one is not None else float(self.drive(self.t0 + t, [q], [w])[0])
            eps, loss, other, self.last_conditioning = self.friction.solve_rates(q, w, effort, mode=self.mode)
        except AssemblyError as exc:
            self.fault = (exc.group, exc.reason, [q])
            self.faults += 1
            raise
        return [w, eps, effort * w, other * w, -loss]

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        return np.array(self.rates(t, [float(v) for v in y]))

    def accelerations(self, t: float, q: Sequence[float], qd: Sequence[float]) -> tuple[list[float], list[float],
                                                                                          float]:
        """(ε, Q_drive, conditioning) at global time ``t``; at rest inside the holding interval ε = 0."""
        x, w = float(q[0]), float(qd[0])
        effort = float(self.drive(t, [x], [w])[0])
        slip = self.slip
        if w == 0.0:
            lo, hi = self.friction.holding(x)
            if lo <= effort <= hi:
                return [0.0], [effort], 1.0
            slip = 1.0 if effort > hi else -1.0
        st = self.friction.solve(x, w, effort, slip=slip)
        return [st.epsilon], [effort], st.conditioning


@dataclass
class _Piece:
    """One part of the run's dense output: a segment's (in its local time from ``t0``) or a held
    state (``y`` while the input sticks)."""

    t0: float
    t1: float
    sol: Any = None
    y: list[float] = field(default_factory=list)

    @property
    def t_old(self) -> float:  # (a step's names: the run's dense output is a Solution of pieces)
        return self.t0

    @property
    def t(self) -> float:
        return self.t1

    def __call__(self, t: float) -> list[float]:
        return list(self.y) if self.sol is None else list(self.sol(t - self.t0))


def hold(pieces: list[_Piece], emit: Callable[[float, Any], None], t_eval: np.ndarray | None, t0: float, t1: float,
         y: Sequence[float]) -> None:
    """A held state from ``t0`` to ``t1`` (every input stuck): its piece of the dense output and
    its ``t_eval`` samples in (t0, t1], then ``t1`` itself."""
    pieces.append(_Piece(t0, t1, y=list(y)))
    if t_eval is not None:
        for te in t_eval[(t_eval > t0) & (t_eval <= t1)]:
            emit(float(te), y)
    emit(t1, y)


@dataclass
class FrictionOutcome(Outcome):
    """:class:`Outcome` with the stick–slip lines and switches."""

    messages: list[str] = field(default_factory=list)
    switches: list[tuple[str, float, float]] = field(default_factory=list)
    #: the input of each switch (several inputs: solver.dynamics._friction_multi_run)
    inputs: list[str] = field(default_factory=list)


def _where(eq: FrictionEquation, t: float, q: float) -> str:
    name = eq.friction.input
    unit = eq.model.scene.joint_units.get(name, "rad")
    at = f"{name} = {q:.9g} rad ({math.degrees(q):.6g}°)" if unit == "rad" else f"{name} = {q:.9g} {unit}"
    return f"t = {t:.9g} s, {at}"


def first_outside(outside: Callable[[float], float], t_from: float, t_end: float, *, max_step: float,
                  t_eval: np.ndarray | None) -> float:
    """While the inputs stick under a drive that depends on the time: the first time in
    (t_from, t_end] at which ``outside(t)`` > 0 (the drive leaves a holding interval), t_end if
    none — sampled (STICK_SAMPLES, or every ``max_step``/``dt`` if finer), then Brent's method,
    then the first float outside (the slip's own test)."""
    n = STICK_SAMPLES
    grid = np.linspace(t_from, t_end, n + 1)
    finer = min(max_step, *(np.diff(t_eval) if t_eval is not None and t_eval.size > 1 else [math.inf]))
    if math.isfinite(finer) and finer > 0 and (t_end - t_from) / finer > n:
        grid = np.append(np.arange(t_from, t_end, finer), t_end)
    prev = grid[0]
    for t in grid[1:]:
        if outside(float(t)) > 0.0:
            r = float(brentq(outside, float(prev), float(t), xtol=1e-15, rtol=4 * np.finfo(float).eps))
            for _ in range(64):
                if outside(r) > 0.0:
                    break
                r = math.nextafter(r, math.inf)
            return min(max(r, float(prev)), float(t))
        prev = t
    return t_end


def run_with_friction(
    eq: FrictionEquation, t_end: float, y0: Sequence[float], *, method: str, rtol: float, atol: float,
    step: float | None, max_step: float, events: Sequence[tuple[Callable[[float, Any], float], int]],
    t_eval: np.ndarray | None, time_dependent: bool,
) -> FrictionOutcome:
    """:func:`solver.dynamics._run.run` segment by segment (module docstring). ``events`` are the
    run's own (global time; the first the toggle), ``hit`` indexes them."""
    fd = eq.friction
    m = len(fd.elements)
    ts: list[float] = []
    ys: list[list[float]] = []
    pieces: list[_Piece] = []
    messages: list[str] = []
    switches: list[tuple[str, float, float]] = []
    nfev = 0
    t0, y = 0.0, list(y0)
    directions: dict[int, int] = {}  # element → the direction of its next reversal's event
    omega_direction = 0
    status, hit, fault = 0, None, None

    def emit(t: float, yy: list[float]) -> None:
        if not ts or t > ts[-1]:
            ts.append(t)
            ys.append(list(yy))

    def held(t_from: float, yy: list[float]) -> float:
        """The input sticks at ``yy`` from ``t_from``: the time it slips again (t_end: never)."""
        q = yy[0]
        lo, hi = fd.holding(q)
        if not time_dependent:
            return t_end

        def outside(t: float) -> float:
            e = float(eq.drive(t, [q], [0.0])[0])
            return max(lo - e, e - hi)

        return first_outside(outside, t_from, t_end, max_step=max_step, t_eval=t_eval)

    def stick_test(t: float, yy: list[float]) -> float:
        """At rest at ``t``: 0.0 if the input sticks, else the direction it slips in (one line each)."""
        q = yy[0]
        effort = float(eq.drive(t, [q], [0.0])[0])
        lo, hi = fd.holding(q)
        interval = f"[{lo:.6g}, {hi:.6g}]"
        if lo <= effort <= hi:
            messages.append(f"{_where(eq, t, q)}: sticks: the holding effort {effort:.6g} is inside the breakaway "
                            f"interval {interval}")
            switches.append(("stick", t, q))
            return 0.0
        s = 1.0 if effort > hi else -1.0
        if t > 0.0 or switches:
            messages.append(f"{_where(eq, t, q)}: slips toward {'+' if s > 0 else '−'}: the effort {effort:.6g} "
                            f"leaves the breakaway interval {interval}")
            switches.append(("slip", t, q))
        return s

    emit(0.0, y) if t_eval is None else None
    if t_eval is not None and t_eval.size and t_eval[0] == 0.0:
        emit(0.0, y)
    slip = 0.0
    if y[1] == 0.0:
        slip = stick_test(0.0, y)
    n_user = len(events)
    for _ in range(MAX_SWITCHES):
        if y[1] == 0.0 and slip == 0.0:  # stuck: the state holds
            t1 = held(t0, y)
            hold(pieces, emit, t_eval, t0, t1, y)
            if t1 >= t_end:
                break
            t0 = t1
            slip = stick_test(t0, y)
            if slip == 0.0:  # (the drive touched the edge and came back: rounding) held on
                continue
        eq.t0, eq.slip = t0, slip
        eq.mode = fd.mode(y[0], y[1], slip=slip, override=eq.override)
        omega_direction = -int(_sign(y[1]) or slip)

        def shifted(g: Callable[[float, Any], float], t0: float = t0) -> Callable[[float, Any], float]:
            return lambda t, yy: g(t + t0, yy)

        seg_events = [(ev if i == 0 else shifted(ev), d) for i, (ev, d) in enumerate(events)]

        def turning(t: float, yy: Any) -> float:
            return float(yy[1])

        seg_events.append((turning, omega_direction))
        for j in range(m):
            def reverses(t: float, yy: Any, j: int = j) -> float:
                return fd.analogs(float(yy[0]))[j][0]

            seg_events.append((reverses, directions.get(j, 0)))
        local_eval = None if t_eval is None else t_eval[t_eval > t0] - t0
        out = run(eq, t_end - t0, y, method=method, rtol=rtol, atol=atol, step=step, max_step=max_step,
                  events=seg_events, t_eval=local_eval)
        nfev += out.nfev
        eq.override, eq.mode = None, None
        start = 1 if t_eval is None else 0
        for i in range(start, out.t.size):
            emit(t0 + float(out.t[i]), [float(v) for v in out.y[:, i]])
        t_stop = t0 + (float(out.t[-1]) if out.t.size else 0.0)
        pieces.append(_Piece(t0, t_stop, sol=out.sol))
        if out.status != 1 or out.hit is None or out.hit < n_user:
            status, hit, fault = out.status, out.hit, out.fault
            break
        y = [float(v) for v in out.sol(float(out.t[-1]))] if out.sol.steps else list(y)
        t0 = t_stop
        directions = {j: d for j, d in directions.items()}
        if out.hit == n_user:  # the input's rate reaches 0: a turning point
            y[1] = 0.0
            if ts and ts[-1] == t0:  # (the event's sample: at rest, exactly)
                ys[-1][1] = 0.0
            slip = stick_test(t0, y)
            directions = {}
            continue
        j = out.hit - n_user - 1  # element j's relative velocity reverses
        v2 = fd.analogs(y[0])[j][1]
        eq.override = {j: -_sign(v2)}  # the friction after the reversal: against v″·q̇²
        directions[j] = -int(_sign(v2 * y[1]))  # v′ moves with sign(v″·q̇): its next zero the other way
        slip = 0.0
    else:
        raise DynamicsError(f"{_where(eq, t0, y[0])}: {MAX_SWITCHES} switches of the friction's direction in one run "
                            "(a chatter that would not end)", scene=eq.friction.name)
    y_arr = np.array(ys, float).T if ys else np.empty((len(y0), 0))
    return FrictionOutcome(np.array(ts, float), y_arr, status, hit, fault, nfev, Solution(pieces),  # type: ignore[arg-type]
                           messages=messages, switches=switches)


def _sign(v: float) -> float:
    return 1.0 if v > 0.0 else -1.0 if v < 0.0 else 0.0
