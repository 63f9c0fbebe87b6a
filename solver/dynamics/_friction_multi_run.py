"""A run of forward dynamics with Coulomb friction and several inputs: segments between the
friction's switches (docs/dynamics.md#friction-with-several-inputs).

As with one input (solver.dynamics._friction_run) the run is cut into **segments** of the own
step loop, each holding its *mode* — the stuck inputs, the friction's directions and the seals'
signs (solver.dynamics._friction_multi) — so that the equation is smooth across the switch that
ends it, located on the step's dense output. A segment ends at:

* a free input's rate q̇ᵢ = 0 (its turning point): the **stick test** of that input — its holding
  interval [Q₋ᵢ, Q₊ᵢ] with the others as they are (moving under their drives, or stuck); inside
  it the input sticks (q̇ᵢ = εᵢ = 0 from then on: its efforts are the holding ones), outside it
  slips on, toward +qᵢ beyond Q₊ᵢ, toward −qᵢ below Q₋ᵢ; the stuck inputs are tested again, as
  the one that joined or left them changes their holding efforts;
* a stuck input's drive leaving its interval (the event min(Q_drive,i − Q₋ᵢ, Q₊ᵢ − Q_drive,i) = 0,
  the interval computed along the segment with the others' motion): it slips;
* an element's relative velocity vⱼ(q, q̇) = 0 while the inputs move: the next segment starts
  with its friction against its relative acceleration at the switch (computed in the mode just
  ended).

While every input sticks nothing is integrated: the state holds until a drive that depends on
the time leaves an interval (solver.dynamics._friction_run.first_outside). Each stick and slip is
one line in the run's ``messages``. The state is (q, q̇, W_drive, W_other, W_friction).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np

from ..errors import AssemblyError, DynamicsError
from ._equation import Equation
from ._friction_multi import Mode, MultiFrictionDynamics
from ._friction_run import MAX_SWITCHES, FrictionOutcome, _Piece, first_outside, hold
from ._run import Solution, run
from .drive import Drive
from .reduced import ReducedModel

__all__ = ["MultiFrictionEquation", "run_with_friction_multi"]


def _sign(v: float) -> float:
    return 1.0 if v > 0.0 else -1.0 if v < 0.0 else 0.0


class MultiFrictionEquation(Equation):
    """The right-hand side y' of y = (q, q̇, W_drive, W_other, W_friction) with friction and k
    inputs, in a segment's local time (``t0`` its start: the drive reads t0 + t)."""

    def __init__(self, model: ReducedModel, drive: Drive) -> None:
        super().__init__(model, drive)
        assert isinstance(model.friction, MultiFrictionDynamics)
        self.friction: MultiFrictionDynamics = model.friction
        self.t0 = 0.0
        #: the segment's stuck inputs, and its friction directions and seals' signs
        self.stuck: frozenset[int] = frozenset()
        self.mode: Mode | None = None

    def rates(self, t: float, y: list[float]) -> list[float]:
        """y' at (t, y) on plain lists, as :meth:`Equation.rates` (faults kept and counted)."""
        k = self.k
        if not all(map(math.isfinite, y[:2 * k])):
            return [math.nan] * len(y)
        q, qd = y[:k], y[k:2 * k]
        try:
            drive = [float(v) for v in self.drive(self.t0 + t, q, qd)]
            st = self.friction.solve(q, qd, drive, stuck=self.stuck, mode=self.mode)
        except AssemblyError as exc:
            self.fault = (exc.group, exc.reason, list(q))
            self.faults += 1
            raise
        self.last_conditioning = st.conditioning
        return [*qd, *st.epsilon, sum(a * b for a, b in zip(drive, qd)), sum(a * b for a, b in zip(st.other, qd)),
                -st.loss]

    def __call__(self, t: float, y: np.ndarray) -> np.ndarray:
        return np.array(self.rates(t, [float(v) for v in y]))

    def accelerations(self, t: float, q: Sequence[float], qd: Sequence[float]) -> tuple[list[float], list[float],
                                                                                          float]:
        """(ε, Q_drive, conditioning) at global time ``t``: the inputs at rest stick or slip by
        the stick test (solver.dynamics._friction_multi.MultiFrictionDynamics.settle), the
        elements at rest checked (``consistent``: a segment's start). (A run's samples take the
        ε its integrator had, where it had one: the locked elements are the segment's.)"""
        q, qd = [float(v) for v in q], [float(v) for v in qd]
        drive = [float(v) for v in self.drive(t, q, qd)]
        fd = self.friction
        rest = [i for i in range(self.k) if qd[i] == 0.0]
        stuck: frozenset[int] = frozenset()
        starts: list[float] | None = None
        if rest:
            stuck, starts, _ = fd.settle(q, qd, drive, rest)
        mode = fd.consistent(q, qd, drive, fd.mode(q, qd, drive, stuck=stuck, starts=starts), stuck=stuck)
        st = fd.solve(q, qd, drive, stuck=stuck, mode=mode)
        return st.epsilon, drive, st.conditioning


def _element(fd: MultiFrictionDynamics, j: int) -> str:
    e = fd.elements[j]
    return f"pin {e.point}" if e.kind == "pin" else f"the slide of {e.body}"


def _at(eq: MultiFrictionEquation, t: float, q: Sequence[float], i: int) -> str:
    name = eq.friction.inputs[i]
    unit = eq.model.scene.joint_units.get(name, "rad")
    v = q[i]
    at = f"{name} = {v:.9g} rad ({math.degrees(v):.6g}°)" if unit == "rad" else f"{name} = {v:.9g} {unit}"
    return f"t = {t:.9g} s, {at}"


def run_with_friction_multi(
    eq: MultiFrictionEquation, t_end: float, y0: Sequence[float], *, method: str, rtol: float, atol: float,
    step: float | None, max_step: float, events: Sequence[tuple[Callable[[float, Any], float], int]],
    t_eval: np.ndarray | None, time_dependent: bool,
) -> FrictionOutcome:
    """:func:`solver.dynamics._run.run` segment by segment (module docstring). ``events`` are the
    run's own (global time; the first the toggle)."""
    fd = eq.friction
    k, m = eq.k, fd.m
    names = fd.inputs
    ts: list[float] = []
    ys: list[list[float]] = []
    pieces: list[_Piece] = []
    messages: list[str] = []
    switches: list[tuple[str, float, float]] = []
    inputs: list[str] = []
    nfev = 0
    t0, y = 0.0, list(y0)
    status, hit, fault = 0, None, None

    rs: list[list[float] | None] = []  # y' where the segment's integrator had it (its ε: the locked elements')

    def emit(t: float, yy: list[float], rate: list[float] | None = None) -> None:
        if not ts or t > ts[-1]:
            ts.append(t)
            ys.append(list(yy))
            rs.append(rate)

    def drive_at(t: float, yy: list[float]) -> list[float]:
        return [float(v) for v in eq.drive(t, yy[:k], yy[k:2 * k])]

    def others(i: int, stuck: frozenset[int]) -> str:
        parts = [f"{names[n]} {'stuck' if n in stuck else 'moving'}" for n in range(k) if n != i]
        return f" ({', '.join(parts)})" if parts else ""

    def settle(t: float, yy: list[float], rest: set[int], before: frozenset[int], starts: list[float],
               report: set[int]) -> tuple[frozenset[int], list[float]]:
        """The stick test of the inputs at rest ``rest`` (one line per change, and per input of
        ``report``: the one at its turning point)."""
        q, qd = yy[:k], yy[k:2 * k]
        drive = drive_at(t, yy)
        stuck, starts, tests = fd.settle(q, qd, drive, rest, starts=starts, locked=carry)
        told = t > 0.0 or bool(switches) or bool(stuck)  # (a release from rest where nothing sticks: no line)
        for i in sorted(rest):
            lo, hi = tests[i]
            interval = f"[{lo:.6g}, {hi:.6g}]"
            if i in stuck and (i not in before or i in report):
                messages.append(f"{_at(eq, t, q, i)}: {names[i]} sticks: its holding effort {drive[i]:.6g} is "
                                f"inside its breakaway interval {interval}{others(i, stuck)}")
                switches.append(("stick", t, q[i]))
                inputs.append(names[i])
            elif i not in stuck and (i in before or (i in report and told)):
                messages.append(f"{_at(eq, t, q, i)}: {names[i]} slips toward {'+' if starts[i] > 0 else '−'}: "
                                f"the effort {drive[i]:.6g} leaves its breakaway interval {interval}"
                                f"{others(i, stuck)}")
                switches.append(("slip", t, q[i]))
                inputs.append(names[i])
        return stuck, starts

    def held(t_from: float, yy: list[float]) -> float:
        """Every input sticks at ``yy`` from ``t_from``: the time one slips again (t_end: never)."""
        if not time_dependent:
            return t_end
        q, qd = yy[:k], yy[k:2 * k]
        every = frozenset(range(k))
        drive = drive_at(t_from, yy)
        spans = [fd.holding(q, qd, drive, i, stuck=every - {i}) for i in range(k)]

        def outside(t: float) -> float:
            e = drive_at(t, yy)
            return max(max(lo - e[i], e[i] - hi) for i, (lo, hi) in enumerate(spans))

        return first_outside(outside, t_from, t_end, max_step=max_step, t_eval=t_eval)

    if t_eval is None or (t_eval.size and t_eval[0] == 0.0):
        emit(0.0, y)
    stuck: frozenset[int] = frozenset()
    starts = [0.0] * k
    override: dict[int, float] | None = None
    carry: frozenset[int] = frozenset()  # the elements locked at the last segment's end
    rest0 = {i for i in range(k) if y[k + i] == 0.0}
    if rest0:
        stuck, starts = settle(0.0, y, rest0, frozenset(), starts, rest0)
    n_user = len(events)
    for _ in range(MAX_SWITCHES):
        if len(stuck) == k:  # every input sticks: the state holds
            t1 = held(t0, y)
            hold(pieces, emit, t_eval, t0, t1, y)
            if t1 >= t_end:
                break
            t0 = t1
            stuck, starts = settle(t0, y, set(range(k)), stuck, starts, set())
            if len(stuck) == k:  # (the drive touched an edge and came back: rounding) held on
                continue
        q, qd = y[:k], y[k:2 * k]
        drive = drive_at(t0, y)
        mode = fd.mode(q, qd, drive, stuck=stuck, starts=starts, override=override, locked=carry)
        mode = fd.consistent(q, qd, drive, mode, stuck=stuck, where=f"t = {t0:.9g} s, {fd._where(q)}")
        eq.t0, eq.stuck, eq.mode = t0, stuck, mode
        dirs, sigma, locked = mode
        held_now = stuck
        if locked - carry:  # one line per element that locks
            st = fd.solve(q, qd, drive, stuck=stuck, mode=mode)
            for j in sorted(locked - carry):
                lam, most = st.holds[j]
                messages.append(f"t = {t0:.9g} s, {fd._where(q)}: {_element(fd, j)} locks: its friction holds its "
                                f"relative motion while the inputs move (its moment {lam:.6g} within ±{most:.6g})")
        def shifted(g: Callable[[float, Any], float], t0: float = t0) -> Callable[[float, Any], float]:
            return lambda t, yy: g(t + t0, yy)

        seg_events = [(ev if n == 0 else shifted(ev), d) for n, (ev, d) in enumerate(events)]
        what: list[tuple[str, int]] = []
        for i in range(k):
            if i in stuck:
                continue

            def turning(t: float, yy: Any, i: int = i) -> float:
                return float(yy[k + i])

            seg_events.append((turning, -int(sigma[i])))
            what.append(("turn", i))
        for j in range(m):
            if dirs[j] == 0.0:
                continue

            def reverses(t: float, yy: Any, j: int = j) -> float:
                return fd.velocity(list(yy[:k]), list(yy[k:2 * k]), j)

            seg_events.append((reverses, int(dirs[j])))
            what.append(("reverse", j))
        for i in sorted(stuck):
            def margin(t: float, yy: Any, i: int = i, t0: float = t0, held_now: frozenset[int] = held_now,
                       s: tuple[float, ...] = tuple(starts), keep: tuple[float, ...] = tuple(dirs),
                       lk: frozenset[int] = locked) -> float:
                yy = list(yy)
                drive = drive_at(t0 + t, yy)
                lo, hi = fd.holding(yy[:k], yy[k:2 * k], drive, i, stuck=held_now - {i}, starts=s, keep=keep,
                                    locked=lk)
                return min(drive[i] - lo, hi - drive[i])

            seg_events.append((margin, -1))
            what.append(("slip", i))
        for j in sorted(locked):
            def grip(t: float, yy: Any, j: int = j, t0: float = t0, mode: Any = mode,
                     held_now: frozenset[int] = held_now) -> float:
                yy = list(yy)
                st = fd.solve(yy[:k], yy[k:2 * k], drive_at(t0 + t, yy), stuck=held_now, mode=mode)
                lam, most = st.holds[j]
                return most - abs(lam)

            seg_events.append((grip, -1))
            what.append(("unlock", j))
        local_eval = None if t_eval is None else t_eval[t_eval > t0] - t0
        out = run(eq, t_end - t0, y, method=method, rtol=rtol, atol=atol, step=step, max_step=max_step,
                  events=seg_events, t_eval=local_eval)
        nfev += out.nfev
        override = None
        start = 1 if t_eval is None else 0
        for n in range(start, out.t.size):
            known = out.rates[n] if out.rates is not None and n < len(out.rates) else None
            emit(t0 + float(out.t[n]), [float(v) for v in out.y[:, n]], None if known is None else list(known))
        t_stop = t0 + (float(out.t[-1]) if out.t.size else 0.0)
        pieces.append(_Piece(t0, t_stop, sol=out.sol))
        if out.status != 1 or out.hit is None or out.hit < n_user:
            status, hit, fault = out.status, out.hit, out.fault
            break
        y = [float(v) for v in out.sol(float(out.t[-1]))] if out.sol.steps else list(y)
        kind, n = what[out.hit - n_user]
        prev_t0, t0 = t0, t_stop
        carry = locked
        for i in stuck:  # (held exactly)
            y[k + i] = 0.0
        if kind == "turn":  # input n's rate reaches 0: its stick test, and the stuck ones' again
            y[k + n] = 0.0
            if ts and ts[-1] == t0:
                ys[-1][k + n] = 0.0
            starts = [0.0] * k
            stuck, starts = settle(t0, y, set(stuck) | {n}, stuck, starts, {n})
        elif kind == "slip":  # stuck input n's drive leaves its interval
            drive = drive_at(t0, y)
            lo, hi = fd.holding(y[:k], y[k:2 * k], drive, n, stuck=stuck - {n}, starts=starts, keep=dirs,
                                locked=locked)
            side = 1.0 if drive[n] - hi > lo - drive[n] else -1.0
            messages.append(f"{_at(eq, t0, y[:k], n)}: {names[n]} slips toward {'+' if side > 0 else '−'}: the "
                            f"effort {drive[n]:.6g} leaves its breakaway interval [{lo:.6g}, {hi:.6g}]"
                            f"{others(n, stuck - {n})}")
            switches.append(("slip", t0, y[n]))
            inputs.append(names[n])
            starts = [0.0] * k
            starts[n] = side
            rest = set(stuck) - {n}
            stuck = frozenset()
            if rest:
                stuck, starts = settle(t0, y, rest, frozenset(rest), starts, set())
        elif kind == "unlock":  # locked element n's moment reaches its friction's: it slips, the moment kept
            eq.t0 = prev_t0
            st = fd.solve(y[:k], y[k:2 * k], drive_at(t0, y), stuck=stuck, mode=mode)
            override = {n: _sign(st.holds[n][0])}
            messages.append(f"t = {t0:.9g} s, {fd._where(y[:k])}: {_element(fd, n)} slips: its moment reaches its "
                            f"friction's {st.holds[n][1]:.6g}")
            carry = locked - {n}
            starts = [0.0] * k
        else:  # element n's relative velocity reverses: its friction against its relative acceleration
            eq.t0 = prev_t0
            acc = fd.relative_accelerations(y[:k], y[k:2 * k], eq.rates(t_stop - prev_t0, y)[k:2 * k])[n]
            override = {n: -_sign(acc)}
            starts = [0.0] * k
    else:
        raise DynamicsError(f"t = {t0:.9g} s: {MAX_SWITCHES} switches of the friction's direction in one run "
                            "(a chatter that would not end)", scene=fd.name)
    y_arr = np.array(ys, float).T if ys else np.empty((len(y0), 0))
    return FrictionOutcome(np.array(ts, float), y_arr, status, hit, fault, nfev, Solution(pieces),  # type: ignore[arg-type]
                           rates=rs, messages=messages, switches=switches, inputs=inputs)
