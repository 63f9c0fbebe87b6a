"""Two evaluators for one set of formulas: numpy arrays (sweeps) and Python scalars (one φ a tick).

Every group is written with arithmetic operators and the few functions below, so the same code
runs on ``complex``/``float`` scalars (about 50 ns an operation) and on numpy arrays (vectorised).
Planar points are complex numbers ``x + j·y`` (seed 000's notation).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Backend", "NUMPY", "SCALAR", "dot", "cross", "abs2"]

Num = Any  # float | complex | np.ndarray: what flows through the formulas


@dataclass(frozen=True)
class Backend:
    """The transcendental functions of one evaluator; arithmetic is the operators'."""

    name: str
    sqrt: Callable[[Num], Num]
    cos: Callable[[Num], Num]
    sin: Callable[[Num], Num]
    atan2: Callable[[Num, Num], Num]
    tan: Callable[[Num], Num]
    clamp0: Callable[[Num], Num]  # max(x, 0)
    vectorised: bool

    def cis(self, angle: Num) -> Num:
        """``e^{j·angle}``."""
        if not self.vectorised:
            return complex(self.cos(angle), self.sin(angle))
        out = np.empty(np.shape(angle), np.complex128)
        np.cos(angle, out=out.real)
        np.sin(angle, out=out.imag)
        return out


NUMPY = Backend("numpy", np.sqrt, np.cos, np.sin, np.arctan2, np.tan, lambda x: np.maximum(x, 0.0), True)
SCALAR = Backend("scalar", math.sqrt, math.cos, math.sin, math.atan2, math.tan, lambda x: max(x, 0.0), False)


def _is_zero(x: Num) -> bool:
    return isinstance(x, (int, float, complex)) and x == 0


def dot(a: Num, b: Num) -> Num:
    """Scalar product of planar vectors given as complex numbers: ``Re(conj(a)·b)``."""
    if _is_zero(a) or _is_zero(b):
        return 0.0
    return a.real * b.real + a.imag * b.imag


def cross(a: Num, b: Num) -> Num:
    """z-component of the cross product of planar vectors: ``Im(conj(a)·b)``."""
    if _is_zero(a) or _is_zero(b):
        return 0.0
    return a.real * b.imag - a.imag * b.real


def abs2(a: Num) -> Num:
    """Squared length of a planar vector."""
    if _is_zero(a):
        return 0.0
    return a.real * a.real + a.imag * a.imag
