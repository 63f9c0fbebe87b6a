"""The dynamic node's ticks on its timer's grid (issue 32): the periods rcl's timer skips after a
late callback are caught up, stamped and solved at their grid times, within a bound — with a
fake clock and a fake rcl timer, no ROS (:mod:`linkage_ros._tick_grid`, :class:`Runtime`)."""

from __future__ import annotations

import pytest
from conftest import stamp_of

from linkage_ros._tick_grid import CATCH_UP_ENV, CATCH_UP_TICKS, TickGrid, catch_up_limit
from linkage_ros.runtime import Runtime

NS = 1_000_000_000
P = 1_000_000  # 1 kHz
PHASE = 123_456  # the timer's grid: PHASE + n·P
T0 = 5 * NS + PHASE


class RclTimer:
    """rcl's timer semantics: a call moves the next due time on by a period, and past now when the
    callback came more than a period late (the periods in between are skipped)."""

    def __init__(self, first_due: int, period: int = P) -> None:
        self.next_due, self.period = first_due, period

    def call(self, now: int) -> int:
        """The callback at ``now``: the next due time, as rclpy's time_until_next_call + now gives it."""
        self.next_due += self.period
        if self.next_due <= now:
            self.next_due += ((now - self.next_due) // self.period + 1) * self.period
        return self.next_due


def test_an_on_time_callback_ticks_once_at_its_grid_time() -> None:
    grid = TickGrid(P)
    timer = RclTimer(T0)
    stamps = []
    for n in range(5):
        now = T0 + n * P + 80_000  # 80 µs late: the usual
        stamps += grid.due(now, timer.call(now))
    assert stamps == [T0 + n * P for n in range(5)]
    assert grid.late == 0 and grid.skipped == 0


def test_a_late_callback_catches_up_the_skipped_periods_on_the_grid() -> None:
    grid = TickGrid(P)
    timer = RclTimer(T0)
    stamps = list(grid.due(T0 + 50_000, timer.call(T0 + 50_000)))
    late = T0 + P + 3_700_000  # the callback due at T0 + P starts 3.7 periods late
    stamps += grid.due(late, timer.call(late))
    assert timer.next_due == T0 + 5 * P  # rcl skipped the periods due at T0 + 2P .. T0 + 4P
    assert stamps == [T0 + n * P for n in range(5)]  # ... caught up: T0 + P .. T0 + 4P now
    assert grid.late == 3 and grid.skipped == 0
    now = T0 + 5 * P + 10_000
    assert list(grid.due(now, timer.call(now))) == [T0 + 5 * P]
    # a second callback within the same period (or one that fires early) has nothing due
    assert list(grid.due(now + 20_000, now + P)) == []


def test_beyond_the_bound_the_oldest_periods_are_skipped_and_counted() -> None:
    grid = TickGrid(P, limit=CATCH_UP_TICKS)
    timer = RclTimer(T0)
    grid.due(T0, timer.call(T0))
    now = T0 + 35 * P + 500_000  # a stall of 35 periods
    stamps = list(grid.due(now, timer.call(now)))
    assert stamps == [T0 + n * P for n in range(35 - CATCH_UP_TICKS + 1, 36)]
    assert grid.skipped == 35 - CATCH_UP_TICKS and grid.late == CATCH_UP_TICKS - 1
    assert all(b - a == P for a, b in zip(stamps, stamps[1:]))


def test_the_grid_follows_a_reset_timer_and_restarts_after_the_clock_jumps_back() -> None:
    grid = TickGrid(P)
    assert list(grid.due(T0)) == []  # not locked to a timer yet: nothing due
    assert list(grid.due(T0 + 10, T0 + P)) == [T0]
    shifted = T0 + 2 * P + 400_000  # the timer reset: its grid moved by 0.4 periods
    # the new grid's times after the last tick, the first at least half a period after it:
    # increasing, none ahead of now
    assert list(grid.due(shifted + 10, shifted + P)) == [shifted - P, shifted]
    assert grid.next_due(shifted, 700_000, shifted + 20_000) == shifted + 700_000
    assert grid.next_due(shifted, 700_000, shifted + 300_000) is None  # preempted between the readings
    assert grid.next_due(shifted, None, shifted) is None  # a cancelled timer
    back = T0 - 3 * NS
    assert list(grid.due(back + 5, back + P)) == [back]  # a jump back of 3 s: starts again there
    with pytest.raises(ValueError, match="needs a period > 0 ns and a limit >= 1, got 0, 20"):
        TickGrid(0)


def test_the_catch_up_limit_comes_from_the_environment(monkeypatch: pytest.MonkeyPatch) -> None:
    assert catch_up_limit() == CATCH_UP_TICKS
    monkeypatch.setenv(CATCH_UP_ENV, "0")  # no grid: each tick at its callback's time, as before
    assert catch_up_limit() == 0
    assert Runtime({"scene": "four_bar_loaded", "mode": "dynamic", "phi0": 0.3}).grid is None
    monkeypatch.setenv(CATCH_UP_ENV, "many")
    with pytest.raises(ValueError, match="LINKAGE_ROS_CATCH_UP must be an integer >= 0, got 'many'"):
        catch_up_limit()


def test_a_delayed_callback_leaves_no_gap_and_the_timeout_holds_within_a_tick() -> None:
    """The node's loop (linkage_ros.node: _on_timer, _on_effort_command) on a fake clock: one
    callback delayed by 7.3 periods, an effort command arriving during the delay."""
    timeout = 0.05
    rt = Runtime({"scene": "four_bar_loaded", "mode": "dynamic", "rate_hz": 1000.0, "phi0": 0.3, "omega": 0.0,
                  "effort_timeout": timeout})
    assert rt.grid is not None and rt.grid.period_ns == P
    timer = RclTimer(T0)
    ticks: list[tuple[int, float]] = []  # (joint_states stamp, the drive's effort)

    def render(stamp: int) -> None:
        messages = dict(rt.tick(stamp))
        ticks.append((stamp_of(messages["joint_states"]), float(rt.engine.motion.effort)))

    def on_timer(now: int) -> None:
        for stamp in rt.grid.due(now, timer.call(now)):  # type: ignore[union-attr]
            render(stamp)

    command_at = T0 + 40 * P + 2_500_000
    while timer.next_due < T0 + 1200 * P:  # past the law's first 1 s window (tick_share)
        due = timer.next_due
        now = due + (7_300_000 if due == T0 + 40 * P else 60_000)  # the callback due at 40 P comes 7.3 ms late
        if due <= command_at < now:  # the command arrives meanwhile: the periods due before it first
            for stamp in rt.grid.due(command_at):  # type: ignore[union-attr]
                render(stamp)
            assert rt.command_efforts([1.0], command_at) is None
        on_timer(now)
    stamps = [s for s, _ in ticks]
    assert stamps == [T0 + n * P for n in range(len(stamps))]  # on the grid, strictly increasing, no gap
    assert rt.grid.late == 6 and rt.grid.skipped == 0  # type: ignore[union-attr]
    applied = [s for s, effort in ticks if effort == pytest.approx(1.0, rel=1e-12)]
    assert applied[0] > command_at and applied[0] - command_at <= P  # on from the first tick after it
    assert applied[-1] <= command_at + timeout * NS < applied[-1] + P  # off at its timeout, within a tick
    assert all(abs(effort) < 1e-12 for s, effort in ticks if s > applied[-1])
    law = rt.engine.motion
    assert law.tick_share == pytest.approx(1.0, abs=1e-3)  # the law saw every period
    values = dict(rt.builder.diagnostic_values())  # type: ignore[misc]
    assert values["ticks_late"] == "6" and values["ticks_skipped"] == "0"
