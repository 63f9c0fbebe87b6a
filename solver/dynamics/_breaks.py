"""Breakpoints of the equation of motion: the kinks of the tables of an input's coordinate.

A table load (``loads: - table: {of: crankshaft, …}``) is linear between its entries and
constant beyond them (or wrapped over its ``period``): its force, and with it q̈, has a kink at
every entry — 145 in the engine's 720° gas cycle. A Runge–Kutta step across a kink loses its
order (the adaptive one crawls through it with rejected steps, the fixed one makes an O(h²)
error). The integrators (solver.dynamics._stepping) therefore step **breakpoint to
breakpoint**: while a step runs, each table *holds* the piece the motion is in — its line,
extended beyond the piece's ends (solver.forces.frames.HELD) — so that the right-hand side is
smooth; the step is aimed at the piece's end and, where it passes it, cut there on its dense
output; then the next piece is held. Landing a distance δ off the kink costs O(δ²·Δslope), not
O(δ).

A motor's torque–speed table has its kinks in the input's rate: there the window is on q̇ (held
in solver.dynamics.drive.HELD). Only tables of an input's own coordinate or rate have kinks at
known values of the state; a table of another joint (a piston's x) is evaluated as it is.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

from ..forces import frames
from ..forces.spec import TableForce
from .drive import HELD as drive_held

__all__ = ["Breaks", "breaks_of"]


@dataclass(frozen=True)
class _Table:
    """One table of input ``index``: its knots (the entries, and the end of its period where the
    table is shorter than it) in the wrapped coordinate, the values there, the period."""

    key: Any
    #: the state component whose value the table reads: q_i (i), or a motor's q̇_i (k + i)
    index: int
    knots: tuple[float, ...]
    values: tuple[float, ...]
    period: float

    def piece(self, q: float, direction: float) -> tuple[float, float, tuple[float, float, float, float]]:
        """(lo, hi, line): the piece the motion at ``q`` enters in ``direction`` (its ends in the
        input's own, unwrapped coordinate; ±inf beyond a table without a period) and its line."""
        knots, values, period = self.knots, self.values, self.period
        base = 0.0
        x = q
        if period:
            base = math.floor((q - knots[0]) / period) * period
            x = q - base
            if direction < 0 and x <= knots[0]:  # at the start of a turn, going back: the last piece
                x, base = x + period, base - period
        i = (bisect.bisect_right(knots, x) if direction >= 0 else bisect.bisect_left(knots, x)) - 1
        n = len(knots)
        lo = knots[i] if i >= 0 else -math.inf
        hi = knots[i + 1] if i + 1 < n else math.inf
        if 0 <= i < len(values) - 1:
            slope = (values[i + 1] - values[i]) / (knots[i + 1] - knots[i])
            mid = 0.5 * (lo + hi)
            f_mid = values[i] + slope * (mid - knots[i])
        else:  # constant: before the first entry, after the last (to the end of the period)
            slope, f_mid = 0.0, values[0] if i < 0 else values[-1]
            mid = hi if i < 0 else lo
        return lo + base, hi + base, (mid, f_mid, slope, period)


class Breaks:
    """The kinks of a scene's tables of its inputs; :meth:`hold` holds the pieces the motion is
    in and gives the window of each input they are valid in; :meth:`release` lets them go."""

    def __init__(self, tables: Sequence[_Table], k: int, stores: Sequence[dict[Any, Any]] = ()) -> None:
        self.tables = tuple(tables)
        self.k = k
        #: per table, the dict its held line goes into (frames.HELD, or drive.HELD for a motor)
        self.stores = tuple(stores) or (frames.HELD,) * len(self.tables)
        #: whether a table jumps at a kink (one shorter than its period, its ends unequal): f must
        #: then be evaluated anew on the next piece
        self.jumps = any(t.period and t.knots[-1] != t.knots[len(t.values) - 1] and t.values[-1] != t.values[0]
                         for t in self.tables)
        #: (lo, hi) per state component q_1 … q_k, q̇_1 … q̇_k while held: where the held pieces are
        #: the tables themselves
        self.window: list[tuple[float, float]] = [(-math.inf, math.inf)] * (2 * k)

    def __bool__(self) -> bool:
        return bool(self.tables)

    def hold(self, y: Sequence[float], direction: Sequence[float]) -> list[tuple[float, float]]:
        """Hold, for the state ``y`` = (q, q̇) moving in ``direction`` (per component: its rate,
        or where that is 0 its acceleration), each table's piece; the window of each component."""
        window = [(-math.inf, math.inf)] * (2 * self.k)
        for table, store in zip(self.tables, self.stores):
            i = table.index
            lo, hi, line = table.piece(y[i], direction[i])
            store[table.key] = line
            w_lo, w_hi = window[i]
            window[i] = (max(lo, w_lo), min(hi, w_hi))
        self.window = window
        return window

    def held(self) -> list[tuple[dict[Any, Any], Any, tuple[float, float, float, float]]]:
        """The lines held now, (store, key, line) (what a step's dense output is evaluated with later)."""
        return [(store, t.key, store[t.key]) for t, store in zip(self.tables, self.stores) if t.key in store]

    def release(self) -> None:
        for table, store in zip(self.tables, self.stores):
            store.pop(table.key, None)
        self.window = [(-math.inf, math.inf)] * (2 * self.k)


def breaks_of(model: Any) -> Breaks:
    """The breakpoints of a :class:`~solver.dynamics.ReducedModel`'s scene: its tables of an
    input's coordinate and its motors' torque–speed tables (kinks in the input's rate)."""
    inputs = list(model.inputs)
    k = len(inputs)
    tables = []
    stores: list[dict[Any, Any]] = []
    for load in model.spec.loads:
        if not isinstance(load, TableForce) or load.joint not in inputs:
            continue
        at, force = tuple(load.at), tuple(load.force)
        knots, values = list(at), list(force)
        period = float(load.period or 0.0)
        if period and at[-1] < at[0] + period:
            knots.append(at[0] + period)
        key = (id(load.at), id(load.force))
        tables.append(_Table(key, inputs.index(load.joint), tuple(knots), tuple(values), period))
        stores.append(frames.HELD)
    for joint, motor in model.motors.items():
        if not motor.linear and joint in inputs and len(motor.speeds) > 1:
            tables.append(_Table(id(motor), k + inputs.index(joint), tuple(motor.speeds), tuple(motor.torques), 0.0))
            stores.append(drive_held)
    return Breaks(tables, k, stores)
