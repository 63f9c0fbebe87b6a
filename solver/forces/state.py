"""The state of one reverse pass (route 2): each body's known wrench, and the results so far."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np

from .._backend import Backend, minus
from .structure import GROUND

__all__ = ["ForcePass"]

Term = tuple[bool, Any]  # (subtracted?, value)


class ForcePass:
    """The loads known so far on each link, as the terms of a wrench about the link's reference
    point ``ref[link]`` — the point its group takes its balance of moments about (a crank's
    pivot, an RRR's middle pin B, an RRP rod's end A and its block's pin, a slotted link's pivot
    and its block's eyelet): ``forces[link]`` the terms of the resultant force (complex, N),
    ``moments[link]`` those of its moment about ``ref[link]`` (N·m). A force F at P adds
    (F, (P − R) × F); a torque T adds (0, T); the reactions the groups solved after it hand back
    (sign flipped) are *subtracted* terms. A link's terms are summed once, when its group reads
    them (:meth:`force`, :meth:`moment`): no pass for a zero, none to negate a reaction first,
    and no moment to move from one point to another.

    Results: ``pins[i]`` the force on ``structure.pins[i].body`` from its other side,
    ``slides[i]`` the (normal force, couple) on ``structure.slides[i].body`` from its guide,
    ``efforts[joint]`` each input's generalized force.
    """

    __slots__ = ("values", "xp", "ref", "forces", "moments", "pins", "slides", "efforts", "_arms", "_conj")

    def __init__(self, values: Any, xp: Backend, ref: Mapping[str, str], pins: int, slides: int) -> None:
        self.values = values
        self.xp = xp
        self.ref = ref
        self.forces: dict[str, list[Term]] = {}
        self.moments: dict[str, list[Term]] = {}
        self.pins: list[Any] = [0j] * pins
        self.slides: list[Any] = [(0j, 0.0)] * slides
        self.efforts: dict[str, Any] = {}
        self._arms: dict[tuple[str, str], Any] = {}
        self._conj: dict[tuple[str, str], Any] = {}

    def point(self, name: str) -> Any:
        return self.values[name].value

    def arm(self, point: str, origin: str) -> Any:
        """``point − origin`` (complex), computed once per pass; never written in place."""
        a = self._arms.get((point, origin))
        if a is None:
            values = self.values
            a = self._arms[point, origin] = minus(values[point].value, values[origin].value)
        return a

    def arm_conj(self, point: str, origin: str) -> Any:
        """``conj(point − origin)``, computed once per pass (the left factor of r × f)."""
        c = self._conj.get((point, origin))
        if c is None:
            c = self._conj[point, origin] = self.arm(point, origin).conjugate()
        return c

    def cross(self, point: str, origin: str, f: Any) -> tuple[bool, Any]:
        """``(point − origin) × f`` as a term (subtracted?, value): ``Im(conj(r)·f)``, one complex
        product (the conjugate kept for the arm's next use); for a constant ``f`` (a Python
        number: an applied load's force, or any value per tick) ``−Im(conj(f)·r)`` instead,
        a product by a constant and no conjugate pass — the same value to rounding."""
        key = (point, origin)
        if key not in self._conj and f.__class__ is complex:
            t = self.arm(point, origin) * f.conjugate()
            return True, t.imag
        t = self.arm_conj(point, origin) * f
        return False, t.imag

    def add(self, link: str, force: Any, at: str, *, subtract: bool = False) -> None:
        """Put ``force`` acting at the point ``at`` on ``link`` (ground: nothing); ``subtract``
        puts ``−force`` (a reaction handed back) without a pass to negate it."""
        if link == GROUND:
            return
        self.forces.setdefault(link, []).append((subtract, force))
        ref = self.ref[link]
        if at != ref:
            neg, m = self.cross(at, ref, force)
            self.moments.setdefault(link, []).append((neg != subtract, m))

    def add_wrench(self, link: str, force: Any, moment: Any) -> None:
        """Put a force and its moment about the link's reference point (either may be None)."""
        if force is not None:
            self.forces.setdefault(link, []).append((False, force))
        if moment is not None:
            self.moments.setdefault(link, []).append((False, moment))

    def couple(self, link: str, torque: Any) -> None:
        """Put a pure torque (N·m about +z) on ``link``."""
        self.moments.setdefault(link, []).append((False, torque))

    def force(self, link: str, *, negate: bool = False) -> Any:
        """The resultant of ``link``'s known forces (``−`` it with ``negate``); 0j if none."""
        return _total(self.forces.get(link, ()), negate, self.xp, 0j)

    def moment(self, link: str, *, negate: bool = False) -> Any:
        """The moment of ``link``'s known loads about ``ref[link]`` (``−`` it with ``negate``)."""
        return _total(self.moments.get(link, ()), negate, self.xp, 0.0)


def _total(terms: list[Term] | tuple[()], negate: bool, xp: Backend, zero: Any) -> Any:
    """``Σ ±value`` of the terms (all negated with ``negate``), starting from a term that enters
    with a + sign (no pass to negate it; negated only when none does), then in place on the
    fresh sum: a term's own array (a load's, a jet's) is never written."""
    if not terms:
        return zero
    if len(terms) == 1:
        sub, acc = terms[0]
        return acc if sub == negate else xp.negative(acc)
    start = -1
    for i, (sub, _) in enumerate(terms):
        if sub == negate:
            start = i
            break
    if start < 0:
        acc, fresh, start = xp.negative(terms[0][1]), True, 0
    else:
        acc, fresh = terms[start][1], False
    for i, (sub, value) in enumerate(terms):
        if i == start:
            continue
        minus_it = sub != negate
        if fresh and acc.__class__ is np.ndarray and (acc.dtype.kind == "c" or not np.iscomplexobj(value)):
            (np.subtract if minus_it else np.add)(acc, value, out=acc)
        else:
            acc = acc - value if minus_it else acc + value
            fresh = True
    return acc
