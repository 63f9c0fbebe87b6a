"""Two evaluators for one set of formulas: numpy arrays (sweeps) and Python scalars (one φ a tick).

Every group is written with arithmetic operators and the few functions below, so the same code
runs on ``complex``/``float`` scalars (about 50 ns an operation) and on numpy arrays (vectorised).
Planar points are complex numbers ``x + j·y`` (seed 000's notation).
"""

from __future__ import annotations

import math
import operator
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np

__all__ = ["Backend", "NUMPY", "SCALAR", "dot", "cross", "abs2", "minus"]

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
    #: √max(x, 0); an array argument (a fresh temporary of the caller's) is overwritten
    sqrt0: Callable[[Num], Num]
    #: ``arg z = atan2(Im z, Re z)`` in (−π, π] of a planar point or vector
    arg: Callable[[Num], Num]
    #: ``−z``
    negative: Callable[[Num], Num]
    vectorised: bool

    def cis(self, angle: Num) -> Num:
        """``e^{j·angle}``."""
        if not self.vectorised:
            return complex(self.cos(angle), self.sin(angle))
        out = np.empty(np.shape(angle), np.complex128)
        np.cos(angle, out=out.real)
        np.sin(angle, out=out.imag)
        return out

    def call(self, fn: Callable[..., Num], *args: Num) -> Num:
        """``fn(*args)`` for a scalar function the formulas use as a whole (a wrap to (−π, π]);
        the tracing evaluator (solver._trace) records it as one call."""
        return fn(*args)


def _sqrt0_array(x: Num) -> Num:
    if isinstance(x, np.ndarray) and x.ndim:
        return np.sqrt(np.maximum(x, 0.0, out=x), out=x)
    return np.sqrt(np.maximum(x, 0.0))


def _arg_array(z: Num) -> Num:
    # numpy's arctan2 is about twice as fast on contiguous inputs as on the strided .real/.imag
    # views of a complex array, with the same results to the bit: copy the parts out first
    if isinstance(z, np.ndarray) and z.ndim and np.iscomplexobj(z):
        return np.arctan2(np.array(z.imag), np.array(z.real))
    return np.arctan2(z.imag, z.real)


def _arg_scalar(z: Num) -> Num:
    return math.atan2(z.imag, z.real)


def _negative_array(a: Num) -> Num:
    # a complex array negated as its float pairs: the same sign bits flipped, several times faster
    if isinstance(a, np.ndarray) and a.ndim and a.dtype == np.complex128 and a.flags.c_contiguous:
        return np.negative(a.view(np.float64)).view(np.complex128)
    return -a


NUMPY = Backend(
    "numpy", np.sqrt, np.cos, np.sin, np.arctan2, np.tan, _sqrt0_array, _arg_array, _negative_array, True
)
SCALAR = Backend(
    "scalar",
    math.sqrt,
    math.cos,
    math.sin,
    math.atan2,
    math.tan,
    lambda x: math.sqrt(max(x, 0.0)),
    _arg_scalar,
    operator.neg,
    False,
)


def minus(a: Num, b: Num) -> Num:
    """``a − b``; ``a`` itself when ``b`` is the float 0.0 (a fixed point's derivative), since
    ``x − 0.0`` is ``x`` to the bit (−0.0 and NaN included): no array pass for a copy.
    (``__class__``, not ``type()``: a traced value answers it, and records the test as a guard.)"""
    if b.__class__ is float and b == 0.0:
        return a
    return a - b


def _is_zero(x: Num) -> bool:
    """A real scalar zero: a fixed quantity's derivative (structural zeros are the float 0.0), or,
    per tick, a real value that is exactly 0. A complex value is never skipped: a planar vector
    that happens to be 0j gives the same product up to the sign of a zero, and testing every
    complex operand would cost each compiled instant a comparison per product (solver._trace)."""
    return x.__class__ is float and x == 0.0 or x.__class__ is int and x == 0


def dot(a: Num, b: Num) -> Num:
    """Scalar product of planar vectors given as complex numbers: ``Re(conj(a)·b)``."""
    if _is_zero(a) or _is_zero(b):
        return 0.0
    out = a.real * b.real
    out += a.imag * b.imag  # in place on the fresh product: one temporary less for arrays
    return out


def cross(a: Num, b: Num) -> Num:
    """z-component of the cross product of planar vectors: ``Im(conj(a)·b)``."""
    if _is_zero(a) or _is_zero(b):
        return 0.0
    out = a.real * b.imag
    out -= a.imag * b.real
    return out


def abs2(a: Num) -> Num:
    """Squared length of a planar vector."""
    if _is_zero(a):
        return 0.0
    out = a.real * a.real
    out += a.imag * a.imag
    return out
