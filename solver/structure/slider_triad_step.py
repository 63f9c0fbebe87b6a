"""The slider-triad candidate of the decomposition (solver.structure.decompose): a ternary link
none of whose points is placed, one of its points the point of a slide on a ground line (or on
the line of a placed link: ``guide: {on: [P, Q]}``), two others each pinned to a binary link whose
other point is placed — the triad with one prismatic pair (solver.groups.slider_triad), emitted
as ``slider_triad``. Its swinging-block variant: instead of the slide on D, a slide whose point A
is placed and whose line is the ternary link's own (``block_at: A``, the line in the link's frame
through D, its third point, at ``angle`` from D→E, offset along its normal).

Taken after every dyad, as the RRR triad (solver.structure.triad_step). The slide's point must be
on its line (``ON_LINE`` of the drawing's size); the mode is read off the drawn pose as the
triad's: ``angle`` = the drawn arg(E − D), ``at`` = the drawn input (one input), and the mode
rule's root (the group's: nearest the drawn pose, so that two modes of one θ are told apart by
the drawn slide) must give the drawn D, E, F back (``DRAWN_MATCH``) — else the drawing is
refused naming the group. One drawn at a dead point (conditioning below SINGULAR) is refused.
"""

from __future__ import annotations

import cmath
import math
from collections.abc import Iterator
from functools import partial
from typing import Any

import numpy as np

from ..groups._slider_triad_math import pick, slider_analogs, slider_roots
from ..jet import Jet
from .drawing import GROUND
from .step import ON_LINE, Step, dot
from .step import refuse_toggle as _toggle
from .triad_step import DRAWN_MATCH, _binary_partner, free_end

__all__ = ["slider_triad_candidates"]


def slider_triad_candidates(st: Any, link: str) -> Iterator[tuple[int, tuple[str, ...], Any]]:
    """The slider triads that ``link`` (a binary link with one known point) belongs to."""
    d = st.d
    end = free_end(st, link)
    if end is None:
        return
    free = [end]
    open_slides = [s for s in d.slides.values() if s.name not in st.done_slides and s.name not in st.flagged]
    slides = {s.point: s for s in open_slides if s.on == GROUND or s.on in st.placed}
    for ternary in st.point_links[free[0]]:
        tp = d.links[ternary]
        if ternary == link or ternary in st.placed or len(tp) < 3 or any(q in st.known for q in tp):
            continue
        for q in tp:
            slide = slides.get(q)
            if slide is None:
                continue
            arms = _arms(st, ternary, tp, q)
            if arms is not None:
                yield 2, (ternary, slide.name), partial(_slider_triad, st, ternary, slide, arms)
                return
        for slide in open_slides:  # the swinging block: a placed point sliding along the ternary link
            if slide.on != ternary or slide.point not in st.known:
                continue
            arms = _arms(st, ternary, tp, None)
            rest = [] if arms is None else [q for q in tp if q not in (arms[0][0], arms[1][0])]
            if arms is not None and rest:
                yield 2, (ternary, slide.name), partial(_swinging, st, ternary, slide, arms, rest[0])
                return


def _arms(st: Any, ternary: str, tp: tuple[str, ...], skip: str | None) -> tuple[tuple[str, str, str], ...] | None:
    """Two points of the ternary link (not ``skip``) each pinned to a binary link whose other point
    is placed: ((point, binary link, its placed end), …), or None."""
    arms: list[tuple[str, str, str]] = []
    for r in tp:
        if r == skip:
            continue
        hit = _binary_partner(st, r, ternary)
        if hit is not None and hit[0] not in {a[1] for a in arms}:
            arms.append((r, hit[0], hit[1]))
        if len(arms) == 2:
            return tuple(arms)
    return None


def _slider_triad(st: Any, ternary: str, slide: Any, arms: tuple[tuple[str, str, str], ...]) -> None:

    d = st.d
    pd = slide.point
    (pe, l2, b), (pf, l3, c) = arms
    g0, g1 = slide.along
    zg, e = d.points[g0], d.points[g1] - d.points[g0]
    e /= abs(e)
    zb, zc, zd, ze, zf = (d.points[q] for q in (b, c, pd, pe, pf))
    miss = e.real * (zd - zg).imag - e.imag * (zd - zg).real
    what = f"the slider triad {slide.name}, {l2}, {l3}, {ternary}"
    if abs(miss) > ON_LINE * d.size:
        raise d.error(f"{pd} is drawn {abs(miss):.3g} off the line {g0}–{g1} it slides on: move it onto the line",
                      f"slides.{slide.name}.point")
    lengths = (abs(ze - zb), abs(zf - zc))
    theta = cmath.phase(ze - zd)
    u, v = complex(abs(ze - zd), 0.0), (zf - zd) * cmath.exp(-1j * theta)
    s_d = dot(e, zd - zg)
    zero = Jet(0j, 0j, 0j)
    *_, det = slider_analogs(s_d, cmath.exp(1j * theta), zg, e, u, v, zero._replace(value=zb),
                             zero._replace(value=zc))
    cond = abs(det) / (lengths[0] * lengths[1] * (abs(u) + abs(v)))
    entry = f"links.{ternary}"
    _toggle(st, cond, entry, f"{what} is drawn at a dead point (two of its modes merge there)")
    roots, ss = slider_roots(zg, e, zb, zc, lengths, u, v)
    real = np.isfinite(roots)
    if not real.any():
        raise d.error(f"{what} as drawn has no real assembly mode", entry)
    k = int(np.flatnonzero(real)[pick(roots[real].tolist(), ss[real].tolist(), theta, s_d, abs(u) + abs(v))])
    if abs(ss[k] - s_d) > DRAWN_MATCH * d.size or abs(roots[k] - theta) * max(abs(u), abs(v)) > DRAWN_MATCH * d.size:
        raise d.error(f"{what}: no assembly mode reproduces the drawn pose (nearest root "
                      f"{abs(ss[k] - s_d):.3g} away)", entry)
    on_ground = slide.on == GROUND
    fields: dict[str, Any] = {
        "guide": ({"through": g0, "angle": math.atan2(e.imag, e.real) / d.units.angle} if on_ground
                  else {"on": [g0, g1]}),
        "ends": [b, c], "points": [pd, pe, pf], "lengths": list(lengths),
        "shape": {q: [d.points[q].real, d.points[q].imag] for q in (pd, pe, pf)},
        "angle": theta / d.units.angle,
    }
    _emit(st, ternary, slide, (l2, l3), (pd, pe, pf), fields, cond)


def _emit(st: Any, ternary: str, slide: Any, binaries: tuple[str, str], points: tuple[str, str, str],
          fields: dict[str, Any], cond: float) -> None:
    d = st.d
    drawn = [s.drawn for s in st.steps if s.drawn is not None]
    if len(drawn) == 1 and len(d.inputs) == 1 and not d.actuators:
        fields["at"] = float(drawn[0]) / d.units.angle
    if slide.joint is not None:
        fields["slide"] = slide.joint
    st.done_slides.add(slide.name)
    st.add(Step("slider_triad", st.unique(ternary), (*binaries, ternary, slide.name), points, fields, None, cond))


def _swinging(st: Any, ternary: str, slide: Any, arms: tuple[tuple[str, str, str], ...], pd: str) -> None:
    """The swinging block: A (placed) slides along the line ``slide.along`` of the ternary link."""
    d = st.d
    pa = slide.point
    (pe, l2, b), (pf, l3, c) = arms
    g0, g1 = slide.along
    what = f"the slider triad {slide.name}, {l2}, {l3}, {ternary}"
    for g in (g0, g1):
        if g not in d.links[ternary]:
            raise d.error(f"{what}: the line {g0}–{g1} the block slides along must join two points of {ternary}",
                          f"slides.{slide.name}.along")
    e = d.points[g1] - d.points[g0]
    e /= abs(e)
    za, zb, zc, zd, ze, zf = (d.points[q] for q in (pa, b, c, pd, pe, pf))
    miss = e.real * (za - d.points[g0]).imag - e.imag * (za - d.points[g0]).real
    if abs(miss) > ON_LINE * d.size:
        raise d.error(f"{pa} is drawn {abs(miss):.3g} off the line {g0}–{g1} it slides on: move it onto the line",
                      f"slides.{slide.name}.point")
    lengths = (abs(ze - zb), abs(zf - zc))
    theta = cmath.phase(ze - zd)
    w = cmath.exp(1j * theta)
    u, v = complex(abs(ze - zd), 0.0), (zf - zd) / w
    et = e / w  # the line's direction in the ternary link's frame
    offset = (e.conjugate() * (d.points[g0] - zd) * -1j).real  # (X − D)·(j·e): the line's normal offset
    line = (-offset * 1j * et, -et)
    s_d = dot(e, za - zd)
    zero = Jet(0j, 0j, 0j)
    *_, det = slider_analogs(s_d, w, za, 0j, u, v, zero._replace(value=zb), zero._replace(value=zc), line=line)
    cond = abs(det) / (lengths[0] * lengths[1] * (abs(ze - za) + abs(zf - za)))
    entry = f"links.{ternary}"
    _toggle(st, cond, entry, f"{what} is drawn at a dead point (two of its modes merge there)")
    roots, ss = slider_roots(za, 0j, zb, zc, lengths, u, v, line=line)
    real = np.isfinite(roots)
    if not real.any():
        raise d.error(f"{what} as drawn has no real assembly mode", entry)
    # the group's rule for a moving guide: θ₀ alone (no drawn slide s₀: A is placed at run time)
    k = int(np.flatnonzero(real)[pick(roots[real].tolist(), ss[real].tolist(), theta, None, abs(u) + abs(v))])
    if abs(ss[k] - s_d) > DRAWN_MATCH * d.size or abs(roots[k] - theta) * max(abs(u), abs(v)) > DRAWN_MATCH * d.size:
        raise d.error(f"{what}: no assembly mode reproduces the drawn pose (nearest root "
                      f"{abs(ss[k] - s_d):.3g} away)", entry)
    fields: dict[str, Any] = {
        "block_at": pa, "guide": {"angle": cmath.phase(et) / d.units.angle, "offset": offset},
        "ends": [b, c], "points": [pd, pe, pf], "lengths": list(lengths),
        "shape": {q: [d.points[q].real, d.points[q].imag] for q in (pd, pe, pf)},
        "angle": theta / d.units.angle,
    }
    _emit(st, ternary, slide, (l2, l3), (pd, pe, pf), fields, cond)
