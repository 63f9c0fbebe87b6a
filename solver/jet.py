"""Second-order jets: a quantity with its first and second derivative in the crank angle φ.

A planar point is a jet of complex numbers ``(z, dz/dφ, d²z/dφ²)`` — position, velocity analog
and acceleration analog (seed 000) — and a joint coordinate a jet of reals. Derivatives are
propagated exactly by the chain rule written out in each group; no finite differences.

The helpers below are the pieces that several groups share: the direction of a moving vector
and its angular analogs, and the motion of a vector of fixed length turning with a link.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple

from ._backend import Backend

__all__ = ["Jet", "constant", "sub", "direction", "angle_of", "length_of", "turning"]

Num = Any


class Jet(NamedTuple):
    """``(value, d/dφ, d²/dφ²)``; each entry a scalar or an array broadcastable to φ's shape."""

    value: Num
    d1: Num
    d2: Num


def constant(value: Num) -> Jet:
    """A fixed quantity: both derivatives are exactly zero."""
    return Jet(value, 0.0, 0.0)


def sub(a: Jet, b: Jet) -> Jet:
    """``a − b`` term by term (a fixed ``b``'s zero derivatives cost no array pass)."""
    d1 = a.d1 if b.d1.__class__ is float and b.d1 == 0.0 else a.d1 - b.d1  # x − 0.0 is x to the bit
    d2 = a.d2 if b.d2.__class__ is float and b.d2 == 0.0 else a.d2 - b.d2
    return Jet(a.value - b.value, d1, d2)


class Direction(NamedTuple):
    """Unit vector of a moving planar vector r, with the angular analogs of its angle θ."""

    unit: Num  # e^{jθ}
    length: Num  # |r|
    w: Num  # r'/r = ρ'/ρ + j·θ'
    w1: Num  # (r'/r)' = r''/r − (r'/r)²


_NAN = complex(math.nan, math.nan)


def _nonzero(x: Num) -> bool:
    """False only for a Python float 0: per tick, r = 0 at a sample the caller has flagged (mask
    mode) gives NaN, as numpy does on the vectorised path, instead of a ZeroDivisionError."""
    return x.__class__ is not float or x != 0.0


def direction(r: Jet, xp: Backend) -> Direction:
    """Direction of ``r`` (complex jet), from ``ln r = ln ρ + jθ``.

    ``r'/r = ρ'/ρ + jθ'`` and ``(r'/r)' = r''/r − (r'/r)² = ρ''/ρ − (ρ'/ρ)² + jθ''``.
    The caller guarantees ``r ≠ 0``.
    """
    z = r.value
    rho2 = z.real * z.real + z.imag * z.imag
    rho = xp.sqrt(rho2)
    inv = z.conjugate() / rho2 if _nonzero(rho2) else _NAN  # 1/r
    w = r.d1 * inv
    w1 = r.d2 * inv - w * w
    return Direction(z / rho if _nonzero(rho) else _NAN, rho, w, w1)


def angle_of(r: Jet, xp: Backend) -> Jet:
    """Angle θ = arg r in (−π, π] with θ' = Im(r'/r), θ'' = Im((r'/r)')."""
    z = r.value
    rho2 = z.real * z.real + z.imag * z.imag
    inv = z.conjugate() / rho2 if _nonzero(rho2) else _NAN  # 1/r
    w = r.d1 * inv
    w1 = r.d2 * inv - w * w
    return Jet(xp.arg(z), _imag(w), _imag(w1))


def length_of(r: Jet, xp: Backend) -> Jet:
    """Length ρ = |r| with ρ' = ρ·Re(w), ρ'' = ρ·(Re(w') + Re(w)²)."""
    d = direction(r, xp)
    rw = _real(d.w)
    return Jet(d.length, d.length * rw, d.length * (_real(d.w1) + rw * rw))


def turning(v: Num, theta1: Num, theta2: Num) -> tuple[Num, Num]:
    """Analogs of a vector ``v`` of fixed length turning with a link of angular analogs θ', θ''.

    ``v' = jθ'·v`` and ``v'' = (jθ'' − θ'²)·v`` (seed 000's TurnRI differentiated).
    """
    return 1j * theta1 * v, (1j * theta2 - theta1 * theta1) * v


def _real(x: Num) -> Num:
    return x.real if hasattr(x, "real") else x


def _imag(x: Num) -> Num:
    return x.imag if hasattr(x, "imag") else 0.0 * x
