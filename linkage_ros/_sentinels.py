"""Sentinel numbers for finding where a message's numbers sit in its CDR bytes.

The byte-template serialiser (:mod:`linkage_ros.serialize`: the node's ticks, the relay,
``linkage-run``'s whole runs and the recorder) builds each topic's message once from a probe
frame whose every number is a distinct sentinel, serialises it, and looks the sentinels up in the
bytes: their offsets are where each tick's numbers are written.
"""

from __future__ import annotations

import struct

__all__ = ["NSEC", "SEC", "find_all", "sentinel"]

SEC = 0x3A5B7C1D  # sentinel stamp: seconds (int32) ...
NSEC = 0x2C4D6E1F  # ... and nanoseconds (< 10⁹)
_FLOAT_BASE = 0x7A5A_0000_0000_A5A5  # finite doubles ~1e281 with a recognisable bit pattern


def sentinel(i: int) -> float:
    """The ``i``-th sentinel double: finite, distinct for every i < 2¹⁶, never a real value."""
    value: float = struct.unpack("<d", struct.pack("<Q", _FLOAT_BASE | (i + 1) << 16))[0]
    return value


def find_all(data: bytes, pattern: bytes) -> list[int]:
    """Every offset of ``pattern`` in ``data`` (overlapping matches included)."""
    out, start = [], 0
    while (i := data.find(pattern, start)) >= 0:
        out.append(i)
        start = i + 1
    return out
