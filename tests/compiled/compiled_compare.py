"""Helpers: the compiled instant against today's scalar path, bit for bit."""

from __future__ import annotations

import math
from typing import Any

import solver


def bits(x: Any) -> Any:
    """A value's identity to the bit: floats by their sign and repr (NaN equal to NaN)."""
    if isinstance(x, complex):
        return (bits(x.real), bits(x.imag))
    if isinstance(x, float):
        return ("nan",) if x != x else (math.copysign(1.0, x), repr(x))
    return x


def outcome(fn: Any, *args: float) -> Any:
    """What ``fn(*args)`` gives: its values to the bit, or its error's class and message."""
    try:
        return tuple(bits(v) for v in fn(*args))
    except solver.SolverError as exc:
        return (type(exc).__name__, str(exc))


def agree(scene: solver.Scene, *args: float) -> bool:
    """The compiled function (with its fallback) and the scalar path give the same at ``args``."""
    unit = scene.compiled()
    return outcome(unit.function, *args) == outcome(unit.fallback, *args)


def compiled_hit(scene: solver.Scene, *args: float) -> bool:
    """True when the compiled code itself (no guard tripped) served ``args``."""
    return scene.compiled().core(*args) is not None
