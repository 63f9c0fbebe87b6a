"""The triad candidate of the decomposition (solver.structure.decompose): a ternary link none of
whose points is placed, three of its points each pinned to a binary link whose other point is.

Taken after every dyad (rank 2: a dyad is always tried first, docs/structure.md). Its mode is
read off the drawn pose: ``angle`` = the drawn ternary-link angle arg(E − D), ``at`` = the drawn
input (one input), and the real root of the triad's polynomial nearest that angle must give the
drawn D, E, F back to round-off (``DRAWN_MATCH`` of the drawing's size) — else the drawing is
refused naming the triad. A triad drawn at a dead point (conditioning below SINGULAR) is refused
like a dyad at its toggle.
"""

from __future__ import annotations

import cmath
from collections.abc import Iterator
from functools import partial
from typing import Any

import numpy as np

from ..groups.triad import triad_analogs, triad_roots
from ..jet import Jet
from .step import Step
from .step import refuse_toggle as _toggle

__all__ = ["triad_candidates", "free_end", "DRAWN_MATCH"]

#: The drawn D, E, F and the nearest real root's agree to this fraction of the drawing's size.
DRAWN_MATCH: float = 1e-9


def _binary_partner(st: Any, q: str, ternary: str) -> tuple[str, str] | None:
    """A binary link (two points) at ``q``, not placed, whose other point is known: (link, end)."""
    for link in st.point_links[q]:
        if link == ternary or link in st.placed:
            continue
        pts = st.d.links[link]
        if len(pts) == 2:
            end = pts[0] if pts[1] == q else pts[1]
            if end in st.known:
                return link, end
    return None


def free_end(st: Any, link: str) -> str | None:
    """The one unknown point of ``link`` where it is an unplaced binary link with one known point
    (the arm a triad or a slider triad starts from), else None."""
    pts = st.d.links[link]
    if link in st.placed or len(pts) != 2:
        return None
    free = [q for q in pts if q not in st.known]
    return free[0] if len(free) == 1 else None


def triad_candidates(st: Any, link: str) -> Iterator[tuple[int, tuple[str, ...], Any]]:
    """The triads that ``link`` (a binary link with one known point) belongs to."""
    d = st.d
    end = free_end(st, link)
    if end is None:
        return
    free = [end]
    for ternary in st.point_links[free[0]]:
        tp = d.links[ternary]
        if ternary == link or ternary in st.placed or len(tp) < 3 or any(q in st.known for q in tp):
            continue
        arms: list[tuple[str, str, str]] = []
        for q in tp:
            hit = _binary_partner(st, q, ternary)
            if hit is not None and hit[0] not in {a[1] for a in arms}:
                arms.append((q, hit[0], hit[1]))
            if len(arms) == 3:
                yield 2, (ternary,), partial(_triad, st, ternary, tuple(arms))
                return


def _triad(st: Any, ternary: str, arms: tuple[tuple[str, str, str], ...]) -> None:
    d = st.d
    (pd, l1, a), (pe, l2, b), (pf, l3, c) = arms
    za, zb, zc, zd, ze, zf = (d.points[q] for q in (a, b, c, pd, pe, pf))
    lengths = (abs(zd - za), abs(ze - zb), abs(zf - zc))
    theta = cmath.phase(ze - zd)
    turn = cmath.exp(-1j * theta)
    u, v = complex(abs(ze - zd), 0.0), (zf - zd) * turn
    zero = Jet(0j, 0j, 0j)
    *_, det = triad_analogs(zd, cmath.exp(1j * theta), u, v, Jet(za, 0j, 0j), zero._replace(value=zb),
                            zero._replace(value=zc))
    cond = abs(det) / (lengths[0] * lengths[1] * lengths[2] * (abs(u) + abs(v)))
    _toggle(st, cond, f"links.{ternary}",
            f"the triad {l1}, {l2}, {l3}, {ternary} is drawn at a dead point (two of its modes merge there)")
    roots, dd = triad_roots(za, zb, zc, lengths, u, v)
    real = np.isfinite(roots)
    entry = f"links.{ternary}"
    if not real.any():
        raise d.error(f"the triad {l1}, {l2}, {l3}, {ternary} as drawn has no real assembly mode", entry)
    k = int(np.flatnonzero(real)[np.argmin(np.abs(np.angle(np.exp(1j * (roots[real] - theta)))))])
    if abs(dd[k] - zd) > DRAWN_MATCH * d.size or abs(roots[k] - theta) * max(abs(u), abs(v)) > DRAWN_MATCH * d.size:
        raise d.error(f"the triad {l1}, {l2}, {l3}, {ternary}: no assembly mode reproduces the drawn pose "
                      f"(nearest root {abs(dd[k] - zd):.3g} away)", entry)
    drawn = [s.drawn for s in st.steps if s.drawn is not None]
    fields: dict[str, Any] = {
        "ends": [a, b, c], "points": [pd, pe, pf], "lengths": list(lengths),
        "shape": {q: [d.points[q].real, d.points[q].imag] for q in (pd, pe, pf)},
        "angle": theta / d.units.angle,
    }
    if len(drawn) == 1 and len(d.inputs) == 1 and not d.actuators:
        fields["at"] = float(drawn[0]) / d.units.angle
    st.add(Step("triad", st.unique(ternary), (l1, l2, l3, ternary), (pd, pe, pf), fields, None, cond))
