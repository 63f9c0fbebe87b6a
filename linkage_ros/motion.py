"""The time law of the input joint: segments of constant angular acceleration.

Within a segment that starts at ``t_s`` with angle ``phi_s`` and angular velocity ``omega_s``::

    phi(t)   = phi_s + omega_s (t - t_s) + 1/2 epsilon (t - t_s)^2
    omega(t) = omega_s + epsilon (t - t_s)

Every evaluation starts from the segment's start, never from the previous tick, so nothing
accumulates: after 10^7 ticks φ is as exact as one evaluation of the closed form. The
difference ``t - t_s`` and the product ``omega_s (t - t_s)`` are computed with their rounding
errors (error-free transformations) and the small terms are summed before the large ones.

Changing ω or ε (or reversing, or holding) starts a new segment at that time with φ continuous;
ω stays continuous when only ε changes. A new segment at time ``t`` discards segments that start
after ``t``, so the history is always a sequence of segments in time order.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = ["SEGMENT_HOLD", "SEGMENT_REVERSE", "SEGMENT_USER", "Motion", "Motions", "Segment"]

#: Tags naming why a segment started.
SEGMENT_USER = "user"
SEGMENT_HOLD = "hold"
SEGMENT_REVERSE = "reverse"

#: Dekker's splitter for float64 (2**27 + 1): splits a double into two 26-bit halves.
_SPLITTER = 134217729.0


@dataclass(frozen=True)
class Segment:
    """One piece of the time law: constant ``epsilon`` from ``t0`` on."""

    t0: float
    phi0: float
    omega0: float
    epsilon: float
    tag: str = SEGMENT_USER


def _two_sum(a, b):  # type: ignore[no-untyped-def]
    """``(s, e)`` with ``s = fl(a + b)`` and ``a + b = s + e`` exactly (Knuth). Arrays or floats."""
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
    return s, e


def _two_prod(a, b):  # type: ignore[no-untyped-def]
    """``(p, e)`` with ``p = fl(a * b)`` and ``a * b = p + e`` exactly (Dekker; no overflow here)."""
    p = a * b
    ca = _SPLITTER * a
    a_hi = ca - (ca - a)
    a_lo = a - a_hi
    cb = _SPLITTER * b
    b_hi = cb - (cb - b)
    b_lo = b - b_hi
    e = ((a_hi * b_hi - p) + a_hi * b_lo + a_lo * b_hi) + a_lo * b_lo
    return p, e


def _check_finite(**values: float) -> None:
    for name, value in values.items():
        if not math.isfinite(value):
            raise ValueError(f"{name} must be a finite number, got {value!r}")


class Motion:
    """Piecewise-constant angular acceleration of the input joint, exact from each segment start.

    ``Motion(phi0=0.0, omega=1.0, epsilon=0.0, t0=0.0)`` starts one segment at ``t0``. Times
    before the first segment extrapolate it backwards. ``unit``: the input's, ``"rad"`` (an
    angle: rad, rad/s, rad/s²) or ``"m"`` (an actuator's stroke: m, m/s, m/s²), for its repr.
    """

    unit = "rad"

    def __init__(
        self, *, phi0: float = 0.0, omega: float = 1.0, epsilon: float = 0.0, t0: float = 0.0, unit: str = "rad"
    ) -> None:
        _check_finite(phi0=phi0, omega=omega, epsilon=epsilon, t0=t0)
        if unit not in ("rad", "m"):
            raise ValueError(f"unit must be 'rad' or 'm', got {unit!r}")
        self.unit = unit
        self._segments: list[Segment] = [
            Segment(float(t0), float(phi0), float(omega), float(epsilon))
        ]
        self._starts: list[float] = [float(t0)]

    # ------------------------------------------------------------------ inspection
    @property
    def segments(self) -> tuple[Segment, ...]:
        """Every segment, in time order."""
        return tuple(self._segments)

    def segment_index(self, t: float) -> int:
        """Index of the segment in effect at ``t`` (the first one for earlier times)."""
        if t >= self._starts[-1]:
            return len(self._starts) - 1
        return max(bisect.bisect_right(self._starts, t) - 1, 0)

    def segment_at(self, t: float) -> Segment:
        """The segment in effect at ``t``."""
        return self._segments[self.segment_index(t)]

    # ------------------------------------------------------------------ evaluation
    def state(self, t: float) -> tuple[float, float, float]:
        """``(phi, omega, epsilon)`` at time ``t`` (s), as Python floats."""
        seg = self._segments[self.segment_index(t)]
        return _evaluate_scalar(seg, float(t))

    def moving_state(self, t: float) -> tuple[float, float, float] | None:
        """:meth:`state`, or None when the segment in effect at ``t`` is a hold (one look-up of
        the segment: the node's per-tick call)."""
        seg = self._segments[self.segment_index(t)]
        return None if seg.tag == SEGMENT_HOLD else _evaluate_scalar(seg, float(t))

    def states(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Vectorised :meth:`state`: arrays ``phi, omega, epsilon`` of the shape of ``t``."""
        times = np.asarray(t, dtype=np.float64)
        flat = times.reshape(-1)
        index = np.searchsorted(np.asarray(self._starts), flat, side="right") - 1
        np.clip(index, 0, len(self._starts) - 1, out=index)
        t0 = np.array([s.t0 for s in self._segments])[index]
        phi0 = np.array([s.phi0 for s in self._segments])[index]
        omega0 = np.array([s.omega0 for s in self._segments])[index]
        eps = np.array([s.epsilon for s in self._segments])[index]
        phi, omega = _evaluate(t0, phi0, omega0, eps, flat)
        shape = times.shape
        return phi.reshape(shape), omega.reshape(shape), eps.reshape(shape)

    def crossing(self, phi: float, t_lo: float, t_hi: float) -> float | None:
        """Earliest time in ``[t_lo, t_hi]`` where φ(t) = ``phi``, within one segment; else None.

        Used to find when the input reached the boundary of an assemblable interval. Only the
        segment in effect at ``t_hi`` is searched (clipped to its start).
        """
        seg = self.segment_at(t_hi)
        lo = max(t_lo, seg.t0) - seg.t0
        hi = t_hi - seg.t0
        c = seg.phi0 - phi
        b = seg.omega0
        a = 0.5 * seg.epsilon
        roots: list[float] = []
        if a == 0.0:
            if b != 0.0:
                roots.append(-c / b)
        else:
            disc = b * b - 4.0 * a * c
            if disc >= 0.0:
                sq = math.sqrt(disc)
                # Numerically stable pair of roots.
                q = -0.5 * (b + math.copysign(sq, b))
                if q != 0.0:
                    roots.extend((q / a, c / q))
                else:
                    roots.append(-b / (2.0 * a))
        inside = sorted(r for r in roots if lo <= r <= hi)
        return seg.t0 + inside[0] if inside else None

    # ------------------------------------------------------------------ new segments
    def set_omega(self, t: float, omega: float, *, epsilon: float | None = None) -> Segment:
        """From ``t`` on, angular velocity ``omega`` (and ``epsilon`` if given); φ continuous."""
        _check_finite(t=t, omega=omega)
        phi, _, eps = self.state(t)
        if epsilon is not None:
            _check_finite(epsilon=epsilon)
            eps = float(epsilon)
        return self._start(Segment(float(t), phi, float(omega), eps))

    def set_epsilon(self, t: float, epsilon: float) -> Segment:
        """From ``t`` on, angular acceleration ``epsilon``; φ and ω continuous."""
        _check_finite(t=t, epsilon=epsilon)
        phi, omega, _ = self.state(t)
        return self._start(Segment(float(t), phi, omega, float(epsilon)))

    def reverse(self, t: float) -> Segment:
        """Reverse the drive at ``t``: ω and ε change sign, φ and |ω| continuous.

        The law after ``t`` is the mirror image (in φ) of the law that would have followed.
        """
        _check_finite(t=t)
        phi, omega, eps = self.state(t)
        return self._start(Segment(float(t), phi, -omega, -eps, SEGMENT_REVERSE))

    def hold(self, t: float) -> Segment:
        """Stop at ``t``: φ stays at φ(t), ω = ε = 0 until the next segment."""
        _check_finite(t=t)
        phi, _, _ = self.state(t)
        return self._start(Segment(float(t), phi, 0.0, 0.0, SEGMENT_HOLD))

    def _start(self, segment: Segment) -> Segment:
        """Append ``segment``, dropping segments that start at or after its start."""
        cut = bisect.bisect_left(self._starts, segment.t0)
        del self._segments[cut:]
        del self._starts[cut:]
        self._segments.append(segment)
        self._starts.append(segment.t0)
        return segment

    def snapshot(self) -> tuple[Segment, ...]:
        """The history, to :meth:`restore` after a tentative change."""
        return tuple(self._segments)

    def restore(self, segments: Sequence[Segment]) -> None:
        """Replace the history by ``segments`` (from :meth:`snapshot`)."""
        if not segments:
            raise ValueError("a motion needs at least one segment")
        self._segments = list(segments)
        self._starts = [s.t0 for s in self._segments]

    def __repr__(self) -> str:
        last = self._segments[-1]
        q, w, e, u = ("s", "ṡ", "s̈", "m") if self.unit == "m" else ("φ", "ω", "ε", "rad")
        return (
            f"Motion({len(self._segments)} segment(s); last from t={last.t0:g} s: "
            f"{q}={last.phi0:g} {u}, {w}={last.omega0:g} {u}/s, {e}={last.epsilon:g} {u}/s², {last.tag})"
        )


def _evaluate_scalar(seg: Segment, t: float) -> tuple[float, float, float]:
    """The same operations as :func:`_evaluate`, on Python floats (identical results)."""
    phi, omega = _evaluate(seg.t0, seg.phi0, seg.omega0, seg.epsilon, t)  # type: ignore[arg-type]
    return float(phi), float(omega), seg.epsilon


def _evaluate(
    t0: NDArray[np.float64],
    phi0: NDArray[np.float64],
    omega0: NDArray[np.float64],
    eps: NDArray[np.float64],
    t: NDArray[np.float64],
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    dt, dt_err = _two_sum(t, -t0)
    p, p_err = _two_prod(omega0, dt)
    s, s_err = _two_sum(phi0, p)
    quad = 0.5 * eps * dt * dt
    small = (s_err + p_err) + (omega0 * dt_err + eps * dt * dt_err)
    phi = s + (quad + small)
    omega = omega0 + (eps * dt + eps * dt_err)
    return phi, omega


class Motions:
    """The time laws of a scene with several inputs: one :class:`Motion` per input joint, in the
    order of ``scene.inputs`` (docs/inputs.md).

    The same interface as :class:`Motion`, with tuples (one entry per input) where it has floats:
    :meth:`state` gives ``(phi, omega, epsilon)`` as k-tuples of Python floats, :meth:`states`
    (N, k) arrays. :meth:`hold` and :meth:`reverse` act on every input at once (the engine's
    unassemblable policy); a segment is a hold when every input holds.
    """

    def __init__(self, laws: Sequence[Motion]) -> None:
        if len(laws) < 2:
            raise ValueError(f"Motions is for two or more inputs, got {len(laws)} law(s); use Motion")
        self.laws: tuple[Motion, ...] = tuple(laws)

    @classmethod
    def of(
        cls,
        count: int,
        *,
        phi0: Sequence[float] | float = 0.0,
        omega: Sequence[float] | float = 1.0,
        epsilon: Sequence[float] | float = 0.0,
        t0: float = 0.0,
        units: Sequence[str] | None = None,
    ) -> Motions:
        """``count`` laws from per-input values (a sequence of ``count``) or one value for all;
        ``units``: each input's ("rad" or "m"; default every one "rad")."""

        def each(label: str, value: Sequence[float] | float) -> list[float]:
            if isinstance(value, (int, float)):
                return [float(value)] * count
            values = [float(v) for v in value]
            if len(values) != count:
                raise ValueError(f"{label} needs {count} values (one per input), got {len(values)}")
            return values

        p, w, e = each("phi0", phi0), each("omega", omega), each("epsilon", epsilon)
        us = tuple(units) if units is not None else ("rad",) * count
        return cls([Motion(phi0=p[i], omega=w[i], epsilon=e[i], t0=t0, unit=us[i]) for i in range(count)])

    def __len__(self) -> int:
        return len(self.laws)

    @property
    def segments(self) -> tuple[Segment, ...]:
        """The first input's segments (for the start time; each law keeps its own history)."""
        return self.laws[0].segments

    def segment_at(self, t: float) -> Segment:
        """A hold when every input holds at ``t``; else the first non-holding input's segment."""
        segs = [law.segment_at(t) for law in self.laws]
        return next((s for s in segs if s.tag != SEGMENT_HOLD), segs[0])

    def start(self) -> tuple[float, tuple[float, ...], tuple[float, ...], tuple[float, ...]]:
        """``(t0, phi0, omega0, epsilon)`` of the first segments, per input."""
        firsts = [law.segments[0] for law in self.laws]
        return (
            firsts[0].t0,
            tuple(s.phi0 for s in firsts),
            tuple(s.omega0 for s in firsts),
            tuple(s.epsilon for s in firsts),
        )

    def state(self, t: float) -> tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...]]:
        """``(phi, omega, epsilon)`` at ``t``, each a k-tuple of Python floats."""
        states = [law.state(t) for law in self.laws]
        return tuple(s[0] for s in states), tuple(s[1] for s in states), tuple(s[2] for s in states)

    def moving_state(self, t: float) -> tuple[tuple[float, ...], tuple[float, ...], tuple[float, ...]] | None:
        """:meth:`state`, or None when every input holds at ``t`` (:meth:`segment_at`)."""
        return None if self.segment_at(t).tag == SEGMENT_HOLD else self.state(t)

    def states(self, t: ArrayLike) -> tuple[NDArray[np.float64], NDArray[np.float64], NDArray[np.float64]]:
        """Vectorised :meth:`state`: ``phi, omega, epsilon`` of shape ``t.shape + (k,)``."""
        parts = [law.states(t) for law in self.laws]
        return tuple(np.stack([p[i] for p in parts], axis=-1) for i in range(3))  # type: ignore[return-value]

    def crossing(self, phi: float, t_lo: float, t_hi: float) -> float | None:
        """No φ interval bounds a k-dimensional unassemblable region: always None."""
        return None

    def reverse(self, t: float) -> Segment:
        """Reverse every input at ``t``."""
        return [law.reverse(t) for law in self.laws][0]

    def hold(self, t: float) -> Segment:
        """Stop every input at ``t``."""
        return [law.hold(t) for law in self.laws][0]

    def set_omega(self, t: float, omega: Sequence[float], *, epsilon: Sequence[float] | None = None) -> Segment:
        """From ``t`` on, per-input angular velocities (and accelerations if given)."""
        eps: Sequence[float | None] = [None] * len(self.laws) if epsilon is None else epsilon
        return [law.set_omega(t, w, epsilon=e) for law, w, e in zip(self.laws, omega, eps, strict=True)][0]

    def set_epsilon(self, t: float, epsilon: Sequence[float]) -> Segment:
        """From ``t`` on, per-input angular accelerations."""
        return [law.set_epsilon(t, e) for law, e in zip(self.laws, epsilon, strict=True)][0]

    def snapshot(self) -> tuple[tuple[Segment, ...], ...]:
        return tuple(law.snapshot() for law in self.laws)

    def restore(self, segments: Sequence[Sequence[Segment]]) -> None:
        for law, segs in zip(self.laws, segments, strict=True):
            law.restore(segs)

    def __repr__(self) -> str:
        return f"Motions({', '.join(repr(law) for law in self.laws)})"
