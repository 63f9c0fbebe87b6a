"""At most one log line per kind of warning per period (the node's warnings, issue 30).

rclpy's ``throttle_duration_sec`` throttles by call site: every warning of one ``logger.warning``
line shares a window, so a flood of one kind (dropped JointStates) hid every other kind
(unassemblable input, a refused effort command). :class:`Throttle` keeps one window per *kind*:
the warning's text with its numbers left out, so ``joint 'crank' position is nan`` at every
message is one kind, and ``no joint 'crank' in the message`` another.
"""

from __future__ import annotations

import re

__all__ = ["Throttle", "warning_kind"]

_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|\b(?:nan|inf)\b")


def warning_kind(text: str) -> str:
    """The kind of a warning: its text with every number (and nan, inf) replaced by ``#``."""
    return _NUMBER.sub("#", text)


class Throttle:
    """``allow(text, now_s)``: whether to log ``text`` now — the first of its kind, or the first
    after ``period_s`` seconds (monotonic) since the last one of its kind that was logged."""

    def __init__(self, period_s: float) -> None:
        self.period_s = float(period_s)
        self._last: dict[str, float] = {}

    def allow(self, text: str, now_s: float) -> bool:
        kind = warning_kind(text)
        last = self._last.get(kind)
        if last is not None and 0.0 <= now_s - last < self.period_s:
            return False
        if len(self._last) > 1000:  # many kinds (names in texts): forget the old windows
            self._last.clear()
        self._last[kind] = now_s
        return True
