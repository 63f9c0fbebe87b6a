"""Each body's motion and loads from the plan's jets: centre of mass, angle, wrenches.

Centre and angle (the body frame of docs/forces.md): with origin O and x axis toward X,
    r = X − O,  θ' = Im(r'/r),  θ'' = Im(r''/r − (r'/r)²),
    G = O + c·r/|r|,  G' = O' + jθ'·(G − O),  G'' = O'' + (jθ'' − θ'²)·(G − O)
(seed 000's TurnRI differentiated, as for an attached point); a slider block on a fixed guide
of unit direction e has G = B + c·e, G' = B', G'' = B'' and θ' = θ'' = 0; a slotted link's
block turns with the link (r = eyelet − pivot, origin at the eyelet).
Real motion: a = a_q·ω² + v_q·ε (one input; with several the jets are real motion already).

A body's known loads are kept as one wrench (F, M) about the point R its group takes moments
about (solver.forces.state): the resultant force F (complex, N) and its moment M about R
(N·m): a force F at P adds (F, (P − R) × F), a torque T adds (0, T). d'Alembert's inertial load
with gravity: F = m·(g − a_G), M = (G − R) × F − I·α.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Callable
from typing import Any, NamedTuple

import numpy as np

from .._backend import Backend, abs2, cross, minus
from ..jet import Jet, direction, sub, turning
from .spec import Body, Spring, TableForce
from .state import ForcePass

__all__ = [
    "BodyMotion", "accel", "along", "body_motion", "divide", "inertial_wrench", "moment_of", "spring_force",
    "table_force",
]

_NAN = math.nan


class BodyMotion(NamedTuple):
    """Centre of mass G (a complex jet) and the angle's analogs θ', θ''."""

    center: Jet
    theta1: Any
    theta2: Any


def moment_of(r: Any, f: Any) -> Any:
    """``r × f`` (z of the cross product of two planar vectors) as ``Im(conj(r)·f)``: on arrays one
    complex product instead of four real products on strided views; the same value to rounding."""
    if r.__class__ is float or f.__class__ is float:
        return cross(r, f)
    t = r.conjugate()
    t *= f  # in place on the fresh conjugate
    return t.imag


def along(e: complex, v: Any) -> Any:
    """``e·v`` for a constant unit vector ``e`` (a Python complex) and a planar vector ``v``:
    Re(conj(e)·v), a zero coefficient skipped (a guide along an axis: one real product)."""
    x, y = e.real, e.imag
    if e.__class__ is complex:  # (a population's guides are (C, 1) arrays: no skip)
        if y == 0.0:
            return v.real * x
        if x == 0.0:
            return v.imag * y
    out = v.real * x
    out += v.imag * y  # in place on the fresh product
    return out


def divide(x: Any, y: Any) -> Any:
    """``x / y``; NaN (not a ZeroDivisionError) for a Python zero ``y`` — a singular position on
    the per-tick path, flagged as on the vectorised path."""
    if y.__class__ is float and y == 0.0:
        return complex(_NAN, _NAN) if isinstance(x, complex) else _NAN
    return x / y


def _imag(x: Any) -> Any:
    return x.imag if hasattr(x, "imag") else 0.0


def body_motion(body: Body, values: Any, xp: Backend) -> BodyMotion:
    """G and θ's analogs of ``body`` from the jets ``values`` of a plan run."""
    link = body.link
    c = body.center
    if link.block and link.guide is not None:  # a slider block on a fixed guide: it translates
        b = values[link.points[0]]
        return BodyMotion(b if c == 0 else Jet(b.value + c * link.guide, b.d1, b.d2), 0.0, 0.0)
    if link.block:  # a block on a moving guide: origin at its pin, x along the guide's points (a slotted
        assert link.along is not None  # link's pivot → eyelet; a slider triad's carrier P → Q, or D → E)
        origin, r = values[link.points[0]], sub(values[link.along[1]], values[link.along[0]])
    else:
        origin, r = values[body.frame[0]], sub(values[body.frame[1]], values[body.frame[0]])
    d = direction(r, xp)
    t1, t2 = _imag(d.w), _imag(d.w1)
    if c == 0:
        return BodyMotion(origin, t1, t2)
    v = c * d.unit
    v1, v2 = turning(v, t1, t2)
    return BodyMotion(Jet(origin.value + v, origin.d1 + v1, origin.d2 + v2), t1, t2)


def inertial_wrench(
    body: Body,
    s: ForcePass,
    a_of: Callable[[str], Any],
    a_of_jet: Callable[[Jet], Any],
    gravity: complex,
    length: float | None = None,
) -> tuple[Any, Any]:
    """d'Alembert's load of ``body`` with gravity in real motion, as (F, M): the force
    F = m·(g − a_G) at G and the moment M = (G − R) × F − I·α about the link's reference point
    R = ``s.ref[link]`` (each None when zero). ``a_of(point)`` gives a point's real acceleration,
    ``a_of_jet`` a jet's; ``length`` = |r| when the frame's two points are a rigid pair.

    The frame vector r = X − O keeps its length, so with κ = c/|r| (c the centre in the frame):
        G = O + κ·r,   a_G = a_O + κ·a_r,   α = (r × a_r)/|r|²   (a_r = a_X − a_O)
    — the real-motion form of G'' and θ'' above, in few array passes (route 2's evaluation;
    route 1 uses :func:`body_motion`): F = −m·κ·a_r − m·a_O + m·g, and where R is O or X,
    G − R = λ·r (λ = κ or κ − 1), so that both parts of M are cross products with r:
        M = r × (conj(λ)·F − I·a_r/|r|²) = Im(conj(r)·(conj(λ)·F − I·a_r/|r|²))."""
    link = body.link
    c, mass, inertia = body.center, body.mass, body.inertia
    ref = s.ref[link.name]
    if link.block and link.guide is not None:  # a translating block: G = B + c·e, α = 0
        b = link.points[0]
        f = _weight(a_of(b), mass, gravity)
        if f is None or (c == 0 and b == ref):
            return f, None
        offset = c * link.guide  # G − B, a constant
        if b == ref:
            return f, (f * offset.conjugate()).imag
        return f, moment_of(s.arm(b, ref) + offset, f)
    if link.along is not None:  # the slotted link's block: |pivot → eyelet| varies, the jets' way
        m = body_motion(body, s.values, s.xp)
        f = _weight(a_of_jet(m.center), mass, gravity)
        moment = None if f is None else moment_of(minus(m.center.value, s.point(ref)), f)
        if inertia != 0.0:
            torque = a_of_jet(Jet(0.0, m.theta1, m.theta2)) * -inertia
            moment = torque if moment is None else moment + torque
        return f, moment
    o, x = body.frame
    r_conj = s.arm_conj(x, o)
    a_o = a_of(o)
    a_r = minus(a_of(x), a_o)
    if length is not None:  # |r| = L: constants, no array pass
        inv: Any = 1.0 / (length * length)
        kappa: Any = c / length
    else:
        inv = divide(1.0, abs2(s.arm(x, o)))
        kappa = c * s.xp.sqrt(inv)
    spin = None if inertia == 0.0 else a_r * (inv * -inertia)  # −I·a_r/|r|²: r × it = −I·α
    if c == 0:  # G = O: a_G = a_O (a constant m·g for a fixed O)
        f = _weight(a_o, mass, gravity)
    elif mass != 0.0:
        f = a_r * (kappa * -mass)
        if not (a_o.__class__ is float and a_o == 0.0):
            f -= a_o * mass  # in place on the fresh product (never on a jet or a cached acceleration)
        if gravity != 0:
            f += gravity * mass
    else:
        f = None
    lever = spin
    if f is not None and (c != 0 or o != ref):
        if o != ref and x != ref:  # R off the frame's axis points: G − R = (O − R) + κ·r
            moment = moment_of(s.arm(o, ref) + s.arm(x, o) * kappa, f)
            if spin is not None:
                moment += (r_conj * spin).imag  # in place on the fresh product's part
            return f, moment
        lever = f * (kappa if o == ref else kappa - 1.0).conjugate()
        if spin is not None:
            lever += spin  # in place on the fresh product
    if lever is None:
        return f, None
    lever *= r_conj  # in place on a fresh product (F·conj(λ) or −I·a_r/|r|²)
    return f, lever.imag


def _weight(a_g: Any, mass: float, gravity: complex) -> Any:
    """m·(g − a_G), or None for a massless body."""
    if mass == 0.0:
        return None
    if a_g.__class__ is float and a_g == 0.0:  # a fixed point
        return gravity * mass
    f = a_g * -mass
    if gravity != 0:
        f += gravity * mass  # in place on the fresh product
    return f


def accel(d1: Any, d2: Any, ww: Any, e: Any) -> Any:
    """Real acceleration ``d2·ω² + d1·ε`` from the analogs (``d2`` itself when ω² = 1, ε = 0)."""
    if ww.__class__ is float and ww == 1.0 and e.__class__ is float and e == 0.0:
        return d2
    if d2.__class__ is float and d2 == 0.0 and d1.__class__ is float and d1 == 0.0:
        return 0.0  # a fixed point: no array work
    a = d2 * ww
    if not (e.__class__ is float and e == 0.0):
        a += d1 * e  # in place on the fresh product
    return a


def spring_force(spring: Spring, values: Any, xp: Backend) -> Any:
    """The force (complex, N) on the spring's first end: k·(ℓ − ℓ₀)·(Q − P)/ℓ, ℓ = |Q − P|."""
    p, q = values[spring.ends[0][1]].value, values[spring.ends[1][1]].value
    d = q - p
    length = xp.sqrt(abs2(d))
    return d * divide(spring.stiffness * (length - spring.free_length), length)


def table_force(load: TableForce, values: Any, xp: Backend) -> Any:
    """The tabulated force (complex, N): f(q)·direction, f linear between the table's entries."""
    q = values[load.joint].value
    if load.period is not None:  # an angle: into [at₀, at₀ + period), the turn the table starts
        q = (q - load.at[0]) % load.period + load.at[0]
    if xp.vectorised:
        f = np.interp(q, load.at, load.force)
    else:
        f = xp.call(_interp, q, load.at, load.force)  # one call, as the compiled instant records it
    return f * load.direction


#: The pieces of tables held by the dynamics' integrators (solver.dynamics._breaks) for the steps
#: between two of a table's kinks: (id(``at``), id(``force``)) → (x_mid, f_mid, slope, period), the line
#: of one piece, extended beyond its ends, so that the equation of motion is smooth within a step
#: and the integrator places the kink on a step's end. Empty outside such a run (one truth test).
#: Keyed by both tuples' ids: the compiled instant binds one object per distinct constant, so an
#: equal ``at`` of another table is never taken for this one's (at worst it is not held).
HELD: dict[tuple[int, int], tuple[float, float, float, float]] = {}


def _interp(x: float, at: tuple[float, ...], fs: tuple[float, ...]) -> float:
    x = float(x)
    if HELD:
        line = HELD.get((id(at), id(fs)))
        if line is not None:
            mid, f_mid, slope, period = line
            if period:  # the wrapped coordinate back onto the piece's own turn
                x += round((mid - x) / period) * period
            return f_mid + slope * (x - mid)
    if x <= at[0]:
        return fs[0]
    if x >= at[-1]:
        return fs[-1]
    i = bisect.bisect_right(at, x) - 1
    t = (x - at[i]) / (at[i + 1] - at[i])
    return fs[i] + t * (fs[i + 1] - fs[i])
