"""The relay's ω and ε rules: the input's rates from successive JointState messages.

:class:`Rates` keeps the previous accepted message and gives, for the next one, ω and ε in the
driver joint's coordinate and where each came from (:mod:`linkage_ros.relay` states the rules and
``docs/relay.md`` what each costs):

* ω = the message's velocity q̇; without velocities the backward difference
  ω = wrap(q_k − q_{k−1})/(t_k − t_{k−1}) (wrap to (−π, π]) when the previous message is newer than
  ``max_gap``; else 0.
* ε = 0 (rule ``"zero"``), or with rule ``"difference"`` ε = (q̇_k − q̇_{k−1})/(t_k − t_{k−1}) when
  both messages carry velocities, the stamps increase and the gap is ≤ ``max_gap``; else 0.
* A message older than the previous one (reordered) is answered but does not replace it.

With several inputs the same rules apply input by input on k-tuples.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

__all__ = [
    "DEFAULT_MAX_GAP",
    "EPSILON_DIFFERENCE",
    "EPSILON_FROM_VELOCITIES",
    "EPSILON_FROM_ZERO",
    "EPSILON_RULES",
    "EPSILON_ZERO",
    "NS_PER_S",
    "OMEGA_FROM_MESSAGE",
    "OMEGA_FROM_NONE",
    "OMEGA_FROM_POSITIONS",
    "Rates",
]

#: The ε rules (``Relay(epsilon=...)``).
EPSILON_ZERO = "zero"
EPSILON_DIFFERENCE = "difference"
EPSILON_RULES = (EPSILON_ZERO, EPSILON_DIFFERENCE)

#: Where an answer's ω came from.
OMEGA_FROM_MESSAGE = "message"
OMEGA_FROM_POSITIONS = "positions"
OMEGA_FROM_NONE = "none"
#: Where an answer's ε came from.
EPSILON_FROM_ZERO = "zero"
EPSILON_FROM_VELOCITIES = "velocities"

#: Two messages further apart than this (s) are not differenced (for ω without velocities, or ε).
DEFAULT_MAX_GAP = 0.25

NS_PER_S = 1_000_000_000
TWO_PI = 2.0 * math.pi


@dataclass(slots=True)
class _Previous:
    stamp_ns: int
    q: float
    dq: float | None  # the message's velocity (None: the message had none)


@dataclass(slots=True)
class _PreviousInputs:
    """The previous accepted message of a several-input relay: one entry per input."""

    stamp_ns: int
    q: tuple[float, ...]
    dq: tuple[float, ...] | None


class Rates:
    """ω and ε of successive messages under ε rule ``rule``; messages further apart than
    ``max_gap_ns`` are not differenced (see the module docstring)."""

    def __init__(self, *, rule: str, max_gap_ns: int, strokes: tuple[bool, ...] = ()) -> None:
        self.rule = rule
        self.max_gap_ns = max_gap_ns
        #: per input, whether it is an actuator's stroke (m): its positions are differenced unwrapped
        self.strokes = strokes
        self._previous: _Previous | None = None
        self._multi: _PreviousInputs | None = None

    def reset(self) -> None:
        """Forget the previous message."""
        self._previous = None
        self._multi = None

    def one(self, stamp_ns: int, q: float, dq: float | None) -> tuple[float, str, float, str]:
        """ω and ε in the driver joint's coordinate, and where each came from; remembers the
        message for the next one."""
        prev = self._previous
        dt_ns = stamp_ns - prev.stamp_ns if prev is not None else 0
        near = prev is not None and 0 < dt_ns <= self.max_gap_ns
        dt = dt_ns / NS_PER_S
        if dq is not None:
            omega, omega_from = dq, OMEGA_FROM_MESSAGE
        elif near:
            assert prev is not None
            step = q - prev.q if self.strokes[:1] == (True,) else _wrap(q - prev.q)
            omega, omega_from = step / dt, OMEGA_FROM_POSITIONS
        else:
            omega, omega_from = 0.0, OMEGA_FROM_NONE
        eps, eps_from = 0.0, EPSILON_FROM_ZERO
        if self.rule == EPSILON_DIFFERENCE and near and dq is not None:
            assert prev is not None
            if prev.dq is not None:
                eps, eps_from = (dq - prev.dq) / dt, EPSILON_FROM_VELOCITIES
        if prev is None:
            self._previous = _Previous(stamp_ns, q, dq)
        elif dt_ns > 0:  # an older (reordered) message does not replace a newer one
            prev.stamp_ns, prev.q, prev.dq = stamp_ns, q, dq
        return omega, omega_from, eps, eps_from

    def several(
        self, stamp_ns: int, q: tuple[float, ...], dq: tuple[float, ...] | None
    ) -> tuple[tuple[float, ...], str, tuple[float, ...], str]:
        """:meth:`one` input by input: ω and ε k-tuples, and where they came from."""
        prev = self._multi
        dt_ns = stamp_ns - prev.stamp_ns if prev is not None else 0
        near = prev is not None and 0 < dt_ns <= self.max_gap_ns
        dt = dt_ns / NS_PER_S
        zeros = (0.0,) * len(q)
        omega, omega_from = zeros, OMEGA_FROM_NONE
        if dq is not None:
            omega, omega_from = dq, OMEGA_FROM_MESSAGE
        elif near:
            assert prev is not None
            strokes = self.strokes or (False,) * len(q)
            omega = tuple((a - b if m else _wrap(a - b)) / dt for a, b, m in zip(q, prev.q, strokes))
            omega_from = OMEGA_FROM_POSITIONS
        eps, eps_from = zeros, EPSILON_FROM_ZERO
        if self.rule == EPSILON_DIFFERENCE and near and dq is not None:
            assert prev is not None
            if prev.dq is not None:
                eps = tuple((a - b) / dt for a, b in zip(dq, prev.dq))
                eps_from = EPSILON_FROM_VELOCITIES
        if prev is None or dt_ns > 0:  # an older (reordered) message does not replace a newer one
            self._multi = _PreviousInputs(stamp_ns, q, dq)
        return omega, omega_from, eps, eps_from


def _wrap(x: float) -> float:
    """``x`` wrapped to (−π, π]."""
    y = math.remainder(x, TWO_PI)
    return math.pi if y == -math.pi else y
