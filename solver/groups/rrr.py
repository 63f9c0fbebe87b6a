"""The RRR dyad (ВВВ group) of seed 003: joint B at distance l₁ from A and l₂ from C.

Loop equation
    |B − A| = l₁,  |B − C| = l₂,  with A and C known.
    With d = C − A and D = |d|: B = A + d·(a − j·M·h), where
    a = (l₁² − l₂² + D²)/(2D²) and h² = l₁²/D² − a²  (the law of cosines of seed 003),
    computed factored: 4D⁴·h² = ((l₁+l₂)² − D²)(D² − (l₁−l₂)²).
Derivatives (exact): differentiate (B − A)·(B − A) = l₁², (B − C)·(B − C) = l₂².
Linear system, with p = B − A, q = B − C (real dot products on complex numbers):
    B'·p = A'·p,                    B'·q = C'·q,
    B''·p = A''·p − |B' − A'|²,     B''·q = C''·q − |B' − C'|²,
    solved by Cramer's rule: for X·p = s₁, X·q = s₂,  X = j·(s₂·p − s₁·q) / (p × q).
Branch rule (seed 003)
    M = +1 when the joints A → B → C are traversed counter-clockwise (the signed area of the
    triangle A, B, C is positive), M = −1 clockwise. With ``through_change_points: keep`` (the
    default) M holds for every position. With ``through_change_points: continuous`` M is the
    mode on the arc just after φ = 0 and flips at each change point (a double zero of h², where
    both assemblies meet), so a parallelogram stays a parallelogram (solver.singular).
Conditioning
    |p × q| / (l₁·l₂) = |sin| of the angle between the links (the transmission angle in a
    four-bar): 0 at a toggle. There the system is singular; the analogs returned are the limit
    along the branch where it exists, else NaN, and the sample is flagged (solver.singular).
Assembly fails where h² < 0 (|l₁ − l₂| ≤ D ≤ l₁ + l₂ violated) by more than h²'s rounding bound
(``closure_slack``: relative to the lengths and to the conditioning of D, tolerances.
CLOSURE_ROUNDING); the φ intervals come from ``assembly_residual`` (solver.assembly).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np

from .._backend import abs2, cross, dot, minus
from .._fields import Entry, Units
from ..jet import Jet
from ..tolerances import ASSEMBLY_SLACK, CLOSURE_ROUNDING
from .base import Context, Group

__all__ = ["RRR", "CrankFeed", "solve_linear", "branch_sign", "circle_point", "dyad_analogs", "closes"]


class CrankFeed(NamedTuple):
    """The crank that drives a dyad's end directly, against the dyad's fixed other end F."""

    point: str  # the crank's moving point A
    center: complex  # O
    length: float  # L
    distance: float  # R = |F − O|
    turn: complex  # e^{−jθ}/L with θ = arg(F − O)

    @classmethod
    def of(cls, point: str, center: complex, length: float, fixed: complex) -> CrankFeed:
        r = fixed - center
        return cls(point, center, length, abs(r), (r.conjugate() / abs(r)) / length)


def solve_linear(p: Any, q: Any, jdet: Any, s1: Any, s2: Any) -> Any:
    """The planar vector X with X·p = s₁ and X·q = s₂, given ``jdet = j/(p × q)``."""
    if isinstance(s2, float) and s2 == 0.0:
        x = -s1 * q
    elif isinstance(s1, float) and s1 == 0.0:
        x = s2 * p
    else:
        x = s2 * p
        x -= s1 * q
    x *= jdet  # in place on the fresh product (the same order of operations as (…)·jdet)
    return x


#: The smallest normal double: for |det| ≥ this, 1/det is finite.
_NORMAL = float(np.finfo(float).tiny)


def _j_over(det: np.ndarray) -> np.ndarray:
    """``j/det`` for a real array with every |det| ≥ ``_NORMAL`` (±∞ included), in two real
    divisions instead of one complex division: there numpy's complex division gives exactly
    (0/det, 1/det), signed zeros included. (Below, or at NaN, it gives NaN or ∞ parts that this
    would not reproduce: the caller divides as before.)"""
    out = np.empty(det.shape, np.complex128)
    np.divide(0.0, det, out=out.real)
    np.divide(1.0, det, out=out.imag)
    return out


def closure_slack(lengths: tuple[float, float], dd: Any, size: Any) -> Any:
    """The rounding bound of h²·4D⁴ = f₁·f₂ = ((l₁+l₂)² − D²)·(D² − (l₁−l₂)²) for D² = ``dd``
    taken from coordinates of magnitude ``size`` = |A| + |C|: CLOSURE_ROUNDING·(|f₁|·m₂ + |f₂|·m₁)
    with m₁,₂ = (l₁ ± l₂)² + D² + 2·D·size, the magnitudes each factor is a difference of."""
    l1, l2 = lengths
    cross_term = 2.0 * dd**0.5 * size
    f1, f2 = (l1 + l2) ** 2 - dd, dd - (l1 - l2) ** 2
    m1, m2 = (l1 + l2) ** 2 + dd + cross_term, (l1 - l2) ** 2 + dd + cross_term
    return CLOSURE_ROUNDING * (abs(f1) * m2 + abs(f2) * m1)


def closes(lengths: tuple[Any, Any], h2n: Any, dd: Any, a_: Any, c_: Any) -> Any:
    """Where the dyad closes: h² ≥ 0, or below by no more than its rounding bound.

    Each factor of h²·4D⁴ rounds to EPS times the magnitudes it is the difference of:
    m₁ = (l₁+l₂)² + D² + 2·D·S and m₂ = (l₁−l₂)² + D² + 2·D·S, with S = |A| + |C| (D² from
    coordinates of that size carries 2·D·S·EPS); the product is accepted down to
    −CLOSURE_ROUNDING·(|f₁|·m₂ + |f₂|·m₁). Relative to the lengths and to the conditioning of
    D, not to the largest D²: a folded dyad with |l₁ − l₂| ≪ l₁ + l₂ no longer passes
    positions that miss the circles' intersection by ~1e-8·(l₁ + l₂). Only the samples with
    h² < 0 pay for the bound.
    """
    ok = h2n >= 0.0
    if ok is True or (ok.__class__ is np.ndarray and ok.all()):  # (no numpy call per tick)
        return ok
    return h2n >= -closure_slack(lengths, dd, abs(a_) + abs(c_))


def circle_point(
    ctx: Context,
    group: Group,
    a_: Any,
    c_: Any,
    lengths: tuple[Any, Any],
    mode_of: Callable[[Context], Any],
    *,
    factors: Callable[[Any], tuple[Any, Any]] | None = None,
) -> tuple[Any, Any, Any, Any, Any]:
    """The circle intersection B of the module docstring: |B − A| = l₁, |B − C| = l₂, assembly
    mode ``mode_of(ctx)``; ``(B, p = B − A, q = B − C, j/(p × q), |p × q|)``.

    The lengths may vary with the input (an actuator's stroke, solver.groups.actuator): plain
    arithmetic on them. ``factors(xp)`` gives the two factors of h²·4D⁴ where the caller has
    them without cancellation (a crank-fed dyad). Written so that every array temporary is fresh
    and reused in place (augmented assignments, ``out=``): the same operations in the same order
    as the formulas, so the same bits, with fewer allocations. Never writes into its inputs.
    """
    xp = ctx.xp
    l1, l2 = lengths
    d = c_ - a_
    dd = abs2(d)
    ctx.require(group, dd > 0.0, reason="has its two ends on one point")
    # (per tick in mask mode the sample is flagged above and solved on: inf as numpy gives)
    half_inv = 0.5 / dd if dd.__class__ is not float or dd != 0.0 else math.inf
    a = l1 * l1 - l2 * l2 + dd
    a *= half_inv
    # h²·4D⁴ = ((l₁+l₂)² − D²)(D² − (l₁−l₂)²): the factored form is exactly 0 at a toggle
    # whenever D² rounds to the toggle's value (no cancellation in l₁²/D² − a²).
    if factors is None:
        h2n = (l1 + l2) ** 2 - dd
        h2n *= dd - (l1 - l2) ** 2
    else:
        h2n, f2 = factors(xp)
        h2n *= f2
    # rounding at a toggle can leave h² a few ulps below zero: clamp that, report the rest
    ctx.require(group, closes(lengths, h2n, dd, a_, c_))
    h = xp.sqrt0(h2n)
    h *= half_inv
    mode = mode_of(ctx)
    p: Any
    if isinstance(h, np.ndarray) and h.ndim:  # p = d·(a − j·M·h), in one complex temporary
        p = np.multiply(1j * mode, h)
        np.multiply(d, np.subtract(a, p, out=p), out=p)
    else:
        p = d * (a - 1j * mode * h)  # B − A
    b, q = a_ + p, p - d  # q = B − C
    det = cross(p, q)
    cond = abs(det)
    jdet: Any
    if isinstance(det, np.ndarray):
        jdet = _j_over(det) if det.size and cond.min() >= _NORMAL else 1j / det
    elif xp.vectorised or det != 0.0:
        jdet = 1j / det
    else:  # an exact toggle on the scalar path: the limit is taken below
        jdet = complex(math.nan, math.nan)
    return b, p, q, jdet, cond


def dyad_analogs(p: Any, q: Any, jdet: Any, ja: Jet, jc: Jet, grow: tuple[Any, Any] | None = None) -> tuple[Any, Any]:
    """B' and B'' from the linear system of the module docstring, given the circle point's
    ``p``, ``q``, ``jdet`` and the ends' jets. ``grow = (e₁, e₂)`` adds the derivatives of a
    varying l₁²/2 to the first row: (l₁·l₁', l₁'² + l₁·l₁'') — an actuator's stroke."""
    r1 = dot(ja.d1, p)
    if grow is not None:  # (a fixed A: the structural float 0.0, no operation on it)
        r1 = grow[0] if type(r1) is float and r1 == 0.0 else r1 + grow[0]
    b1 = solve_linear(p, q, jdet, r1, dot(jc.d1, q))
    s1 = dot(ja.d2, p)
    s1 -= abs2(minus(b1, ja.d1))
    if grow is not None:
        s1 += grow[1]
    s2 = dot(jc.d2, q) - abs2(minus(b1, jc.d1))
    return b1, solve_linear(p, q, jdet, s1, s2)


@dataclass(frozen=True)
class RRR(Group):
    kind = "rrr"
    ends: tuple[str, str]  # A, C
    point: str  # B
    lengths: tuple[float, float]  # |AB|, |CB|
    mode: int  # M = ±1 (with continuous: M on the arc just after φ = 0)
    continuous: bool = False  # through_change_points: continuous
    #: set when one end is a crank's point A = O + L·e^{jφ} and the other a fixed point F: then
    #: both factors of h² are evaluated without cancellation next to a toggle (``_fed_factors``)
    feed: CrankFeed | None = None

    def requires(self) -> tuple[str, ...]:
        return self.ends

    def provides(self) -> tuple[str, ...]:
        return (self.point,)

    def rigid_pairs(self) -> tuple[tuple[str, str, float], ...]:
        return ((self.ends[0], self.point, self.lengths[0]), (self.ends[1], self.point, self.lengths[1]))

    def links(self) -> tuple[tuple[str, ...], ...]:
        return ((self.ends[0], self.point, self.ends[1]),)

    def solve(self, ctx: Context) -> None:
        vals = ctx.values
        ja, jc = vals[self.ends[0]], vals[self.ends[1]]
        l1, l2 = self.lengths
        factors = None
        if self.feed is not None:
            feed_point = self.feed.point
            factors = lambda xp: self._fed_factors(vals[feed_point].value, xp)
        b, p, q, jdet, cond = circle_point(ctx, self, ja.value, jc.value, (l1, l2), self._mode, factors=factors)
        b1, b2 = dyad_analogs(p, q, jdet, ja, jc)
        vals[self.point] = Jet(b, b1, b2)
        cond /= l1 * l2
        ctx.conditioning[self.name] = cond

    def _mode(self, ctx: Context) -> Any:
        return self.mode if not self.continuous else self.mode * branch_sign(ctx.phi, self.flips(ctx))

    def _fed_factors(self, crank_point: Any, xp: Any) -> tuple[Any, Any]:
        """(l₁+l₂)² − D² and D² − (l₁−l₂)² for a crank-fed dyad.

        With R = |F − O|, θ = arg(F − O) and x = φ − θ, D² = (R − L)² + 4LR·sin²(x/2)
        = (R + L)² − 4LR·cos²(x/2), so each factor is a constant made of differences of the
        given lengths (exactly 0 for a parallelogram) plus a term proportional to sin²(x/2) or
        cos²(x/2). Those come from w = e^{jx} = (A − O)·e^{−jθ}/L without cancellation:
        sin²(x/2) = sin²x / (2(1 + cos x)) where cos x ≥ 0, (1 − cos x)/2 elsewhere, and likewise
        for cos²(x/2). The rounding of w is then multiplied by sin x in h², so B stays exact to
        rounding even for φ within 1e-8 of a toggle — where D² computed from coordinates would
        leave an error of ε·D² under the square root (√ε ≈ 1.5e-8 of the scale in B's position).
        """
        feed = self.feed
        assert feed is not None
        l1, l2 = self.lengths
        big_r, crank = feed.distance, feed.length
        w = (crank_point - feed.center) * feed.turn
        c, sn = w.real, w.imag
        sn2 = sn * sn
        if xp.vectorised:  # each branch evaluated only where it is taken (``where=``)
            ahead = c >= 0.0
            opc, omc = 1.0 + c, 1.0 - c
            sin2 = 0.5 * omc
            cos2 = 0.5 * opc
            opc *= 2.0
            omc *= 2.0
            np.divide(sn2, opc, out=sin2, where=ahead)
            np.divide(sn2, omc, out=cos2, where=~ahead)
        elif c >= 0.0:
            sin2, cos2 = sn2 / (2.0 * (1.0 + c)), 0.5 * (1.0 + c)
        else:
            sin2, cos2 = 0.5 * (1.0 - c), sn2 / (2.0 * (1.0 - c))
        four_lr = 4.0 * crank * big_r
        # (l₁+l₂)² − D² = (l₁+l₂)² − (R+L)² + 4LR·cos²(x/2): accurate near the stretched toggle
        f1 = four_lr * cos2
        f1 += ((l1 - big_r) + (l2 - crank)) * ((l1 + l2) + (big_r + crank))
        # D² − (l₁−l₂)² = (R−L)² − (l₁−l₂)² + 4LR·sin²(x/2): accurate near the folded toggle
        f2 = four_lr * sin2
        f2 += ((big_r - l1) - (crank - l2)) * ((big_r + l1) - (crank + l2))
        return f1, f2

    def singular_names(self) -> tuple[str, ...]:
        return (self.point,)

    def flips(self, ctx: Context) -> tuple[float, ...]:
        """The change points where a continuous branch flips M (none without the owning scene,
        which finds them: ``owner.change_points_of``, solver.singular)."""
        return () if ctx.owner is None else tuple(ctx.owner.change_points_of(self))

    def assembly_residual(self, vals: Mapping[str, Jet]) -> tuple[Any, Any, Any]:
        """``R = ((l₁+l₂)² − D²)(D² − (l₁−l₂)²)`` (≥ 0 where assemblable), ``dR/dφ``, and R's
        scale: ASSEMBLY_SLACK·scale is the bound below which :meth:`solve` refuses a sample
        (:func:`closure_slack`, per sample), so that the gaps found agree with the solve."""
        l1, l2 = self.lengths
        ja, jc = vals[self.ends[0]], vals[self.ends[1]]
        d, d1 = jc.value - ja.value, jc.d1 - ja.d1
        dd = abs2(d)
        dd1 = 2.0 * dot(d, d1)
        f1, f2 = (l1 + l2) ** 2 - dd, dd - (l1 - l2) ** 2
        slack = closure_slack(self.lengths, dd, abs(ja.value) + abs(jc.value))
        return f1 * f2, dd1 * (f1 - f2), slack / ASSEMBLY_SLACK

    @classmethod
    def from_entry(cls, e: Entry, units: Units, fixed: Mapping[str, Any]) -> RRR:
        """``{type: rrr, name, ends: [A, C], point: B, lengths: [AB, CB], M: ±1}``."""
        ends = e.names("ends", 2)
        raw = e.raw("lengths")
        if not isinstance(raw, (list, tuple)) or len(raw) != 2:
            raise e.error(f"must be [|AB|, |CB|], got {raw!r}", "lengths")
        sub = e.child("lengths", {"AB": raw[0], "CB": raw[1]})
        return cls(
            name=e.name("name"),
            ends=(ends[0], ends[1]),
            point=e.name("point"),
            lengths=(sub.length("AB", units), sub.length("CB", units)),
            mode=e.mode(),
            continuous=_through(e),
        )


def branch_sign(phi: Any, points: Sequence[float]) -> Any:
    """(−1)^(number of change points in (0, φ mod 2π]): +1 on the arc just after φ = 0.

    For one φ in plain Python (``%`` is numpy's ``mod`` for floats, and a comparison per change
    point, which the tracing evaluator records), for an array with numpy."""
    if not points:
        return 1.0
    if not isinstance(phi, np.ndarray):
        u = phi % (2.0 * math.pi)
        flips = sum(1 for c in points if c <= u) - sum(1 for c in points if c <= 0.0)
        return 1.0 - 2.0 * (flips % 2)
    c = np.asarray(points, float)
    at_zero = int(np.count_nonzero(c <= 0.0))
    u = np.mod(phi, 2.0 * math.pi)
    count = np.searchsorted(c, u, side="right") - at_zero
    sign = 1.0 - 2.0 * (count % 2)
    return float(sign) if np.ndim(sign) == 0 else sign


def _through(e: Entry) -> bool:
    value = e.raw("through_change_points", "keep")
    if value not in ("keep", "continuous"):
        raise e.error(
            f"must be 'keep' (M holds at every position, seed 003) or 'continuous' (M flips at "
            f"change points so that the analogs stay continuous), got {value!r}",
            "through_change_points",
        )
    return value == "continuous"
