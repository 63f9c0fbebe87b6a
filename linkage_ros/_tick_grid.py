"""The dynamic node's ticks on its timer's period grid: the periods rcl's timer skipped, caught up
(issue 32).

rcl's timer skips periods: when a callback starts more than a period after its due time,
``rcl_timer_call`` moves the next due time past now, and the periods in between are never
called. At 1 kHz on a shared machine that was the 1–4 % of ticks the dynamic node lost (the
callback's own cost is well under a period on average; a preempted or slow callback now and then
is not): measured in process on ``engine`` (docs/ros.md, "1 kHz, caught up"), 96 % of the
callbacks started within 0.2 ms of their due time, the rest up to 13 ms late, and each lateness
of k periods lost k − 1 ticks.

:class:`TickGrid` keeps the node on the timer's grid (its phase, locked from the timer's next due
time) and hands each callback the grid times due since the last tick it rendered: every one of
them (oldest first), so a late callback renders the skipped periods' ticks too, each stamped and
solved at its own grid time; at most :data:`CATCH_UP_TICKS` a call — beyond that the older ones
are skipped and counted (:attr:`TickGrid.skipped`), the ticks the law then misses show in its
``tick_share`` (diagnostics WARN ``behind``). Stamps are strictly increasing, on the grid, and
never ahead of the clock (a grid time ≤ now): they follow the wall clock within the callback's
lateness. A clock that jumps back by more than a period starts the grid again.
"""

from __future__ import annotations

import os
from collections.abc import Mapping
from typing import Any

__all__ = ["CATCH_UP_ENV", "CATCH_UP_TICKS", "TickGrid", "catch_up_limit", "grid_for"]

#: At most this many ticks a call (the newest; older due ones are skipped): the law's own bound
#: on a tick's advance (:data:`linkage_ros.dynamic.MAX_GAP_TICKS`), so that a stalled process
#: does not answer with one callback of ever more ticks.
CATCH_UP_TICKS = 20
#: Environment variable that overrides :data:`CATCH_UP_TICKS` (an integer >= 0; 0: no grid, each
#: tick stamped at its callback's clock time as before issue 32's catch-up — for A/B benchmarks).
CATCH_UP_ENV = "LINKAGE_ROS_CATCH_UP"
#: A timer whose phase moved by more than this share of a period (a reset, a new timer) re-locks
#: the grid; less is the jitter of reading the clock twice.
RELOCK_SHARE = 8


def catch_up_limit() -> int:
    """:data:`CATCH_UP_TICKS`, or the integer >= 0 in :data:`CATCH_UP_ENV` (ValueError otherwise)."""
    text = os.environ.get(CATCH_UP_ENV, "").strip()
    if not text:
        return CATCH_UP_TICKS
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise ValueError(f"{CATCH_UP_ENV} must be an integer >= 0, got {text!r}")
    return value


class TickGrid:
    """The grid times due at each call (see the module docstring).

    ``period_ns``: the timer's period (as rclpy computes it: ``int(period_s * 1e9)``);
    ``limit``: at most this many ticks a call.
    """

    def __init__(self, period_ns: int, *, limit: int = CATCH_UP_TICKS) -> None:
        if int(period_ns) <= 0 or int(limit) < 1:
            raise ValueError(f"a tick grid needs a period > 0 ns and a limit >= 1, got {period_ns}, {limit}")
        self.period_ns = int(period_ns)
        self.limit = int(limit)
        #: the grid's phase (ns modulo the period), None until locked to the timer
        self.phase_ns: int | None = None
        #: the grid time of the last tick handed out, None before the first
        self.last_ns: int | None = None
        #: ticks handed out a period or more after their grid time (periods the timer skipped)
        self.late = 0
        #: grid times beyond :attr:`limit` at one call: never ticked
        self.skipped = 0

    def due(self, now_ns: int, next_due_ns: int | None = None) -> range:
        """The grid times in (last tick, ``now_ns``], oldest first, at most :attr:`limit` (the
        newest). ``next_due_ns``: the timer's next due time, which locks the grid's phase to the
        timer's (at the first call, and again when it moved by more than an eighth of a period;
        the first time on a new phase is at least half a period after the last tick); before
        that, nothing is due. Give it only where it is read tight (:meth:`next_due`)."""
        period = self.period_ns
        if next_due_ns is not None:
            phase = int(next_due_ns) % period
            if self.phase_ns is None or min((phase - self.phase_ns) % period,
                                            (self.phase_ns - phase) % period) > period // RELOCK_SHARE:
                self.phase_ns = phase
        if self.phase_ns is None:
            return range(0)
        now_ns = int(now_ns)
        newest = now_ns - (now_ns - self.phase_ns) % period  # the latest grid time <= now
        last = self.last_ns
        if last is not None and newest < last - period:  # the clock jumped back: start again
            last = None
        if last is None:
            first = newest
        else:
            first = last + period - (last - self.phase_ns) % period  # the first grid time after it
            if first - last < period // 2:  # re-locked: no two ticks within half a period
                first += period
            if first > newest:
                return range(0)
        count = (newest - first) // period + 1
        if count > self.limit:
            self.skipped += count - self.limit
            first = newest - (self.limit - 1) * period
            count = self.limit
        self.late += count - 1
        self.last_ns = newest
        return range(first, newest + 1, period)

    def next_due(self, now_ns: int, until_ns: int | None, read_ns: int) -> int | None:
        """The timer's next due time from ``until_ns`` (rclpy's ``time_until_next_call``, read
        between the clock readings ``now_ns`` and ``read_ns``), or None (no timer, or the reading
        too loose to lock a phase on: a process preempted between the two calls would otherwise
        move the grid by the preemption's length)."""
        if until_ns is None or read_ns - now_ns > self.period_ns // (2 * RELOCK_SHARE):
            return None
        return now_ns + until_ns


def grid_for(settings: Mapping[str, Any]) -> TickGrid | None:
    """The node's grid for its settings: in dynamic mode, a timer's at ``rate_hz`` (its period as
    rclpy's create_timer rounds it); None in the other modes and with ``LINKAGE_ROS_CATCH_UP=0``."""
    limit = catch_up_limit()
    if settings.get("mode") != "dynamic" or not limit:
        return None
    return TickGrid(int(1.0 / float(settings["rate_hz"]) * 1_000_000_000), limit=limit)
