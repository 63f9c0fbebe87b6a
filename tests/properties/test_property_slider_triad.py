"""Hypothesis on bounded finite ranges: the slider triad's roots (solver.groups._slider_triad_math)
for any drawn slider triad — the drawn pose is a root, every root closes the loop, the count of real
modes at most six (even but where another mode sits exactly at a branch point, a double root
counted once), and the velocity analogs' linear system is solved exactly; where two modes share θ
(constructed), both are roots and the mode rule picks the drawn one."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from solver.groups._slider_triad_math import closest, pick, slider_analogs, slider_roots
from solver.jet import Jet
from solver.tolerances import NEAR_SINGULAR

SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
COORD = st.floats(-1.0, 1.0, allow_nan=False, allow_infinity=False)
ANGLE = st.floats(-math.pi, math.pi, allow_nan=False, allow_infinity=False)
#: loop closure of every root, relative to the size (round-off; the polish's acceptance is 256·ε·size²)
CLOSED = 1e-12


@SETTINGS
@given(ox=COORD, oy=COORD, gamma=ANGLE, s=COORD, bx=COORD, by=COORD, cx=COORD, cy=COORD, ex=COORD, ey=COORD,
       fx=COORD, fy=COORD, bvx=COORD, bvy=COORD)
def test_drawn_pose_is_a_root_and_every_root_closes_the_loop(ox: float, oy: float, gamma: float, s: float, bx: float,
                                                             by: float, cx: float, cy: float, ex: float, ey: float,
                                                             fx: float, fy: float, bvx: float, bvy: float) -> None:
    o, e = complex(ox, oy), complex(math.cos(gamma), math.sin(gamma))
    b_, c_ = complex(bx, by), complex(cx, cy)
    d = o + s * e
    pe, pf = complex(ex, ey), complex(fx, fy)
    assume(min(abs(pe - d), abs(pf - d), abs(pf - pe), abs(pe - b_), abs(pf - c_), abs(b_ - c_)) > 0.05)
    assume(abs(((pf - d) / (pe - d)).imag) > 0.05)
    theta = math.atan2((pe - d).imag, (pe - d).real)
    u, v = complex(abs(pe - d), 0.0), (pf - d) * complex(math.cos(-theta), math.sin(-theta))
    lengths = (abs(pe - b_), abs(pf - c_))
    roots, slides = slider_roots(o, e, b_, c_, lengths, u, v)
    real = np.isfinite(roots)
    size = abs(o) + abs(b_) + abs(c_) + sum(lengths) + abs(u) + abs(v) + 1.0
    w = np.exp(1j * roots[real])
    dd = o + slides[real] * e
    assert np.abs(np.abs(dd + u * w - b_) - lengths[0]).max() <= CLOSED * size
    assert np.abs(np.abs(dd + v * w - c_) - lengths[1]).max() <= CLOSED * size
    assert real.sum() <= 6
    k = closest(roots[real].tolist(), slides[real].tolist(), theta, s, abs(u) + abs(v))[0]  # the drawn pose's
    s1, t1, _, _, det = slider_analogs(slides[real][k], w[k], o, e, u, v, Jet(b_, complex(bvx, bvy), 0j),
                                       Jet(c_, 0j, 0j))
    cond = abs(det) / (lengths[0] * lengths[1] * (abs(u) + abs(v)))
    # away from a dead point (NEAR_SINGULAR), where the drawn mode is a double root known to ~√ε only
    assume(cond > NEAR_SINGULAR)
    # the drawn pose itself, also where another mode shares its θ (both quadratics in s one there:
    # Dn = N = 0, a double root of the polynomial — both its modes are roots)
    assert abs(math.remainder(roots[real][k] - theta, 2 * math.pi)) <= 1e-9
    assert abs(slides[real][k] - s) <= 1e-9 * size
    # the analogs solve the differentiated loop: q·q' = 0 with q' = E' − B', r·r' = 0
    q, r = dd[k] + u * w[k] - b_, dd[k] + v * w[k] - c_
    e1 = s1 * e + 1j * u * w[k] * t1 - complex(bvx, bvy)
    f1 = s1 * e + 1j * v * w[k] * t1
    scale = size * (abs(s1) + abs(t1) * size + 1.0)
    assert abs((q.conjugate() * e1).real) <= 1e-12 * scale * size
    assert abs((r.conjugate() * f1).real) <= 1e-12 * scale * size


@SETTINGS
@given(gamma=ANGLE, delta=st.floats(0.1, 0.5), te=COORD, tf=COORD, bx=COORD, by=COORD, cx=COORD, cy=COORD, dx=COORD,
       dy=COORD)
def test_two_modes_of_one_theta_are_both_roots_and_the_drawn_one_is_picked(gamma: float, delta: float, te: float,
                                                                          tf: float, bx: float, by: float, cx: float,
                                                                          cy: float, dx: float, dy: float) -> None:
    """Any pose where B and C lie on the perpendicular bisectors of E₁E₂ and F₁F₂ (the modes slid
    δ apart along the guide): both are roots of one θ, and the mode rule with either drawn slide
    picks that one."""
    e = complex(math.cos(gamma), math.sin(gamma))
    b_, c_, d = complex(bx, by), complex(cx, cy), complex(dx, dy)
    pe, pf = b_ - te * 1j * e - 0.5 * delta * e, c_ - tf * 1j * e - 0.5 * delta * e
    assume(min(abs(te), abs(tf), abs(pe - d), abs(pf - d), abs(pf - pe), abs(b_ - c_)) > 0.05)
    assume(abs(((pf - d) / (pe - d)).imag) > 0.05)
    theta = math.atan2((pe - d).imag, (pe - d).real)
    u, v = complex(abs(pe - d), 0.0), (pf - d) * complex(math.cos(-theta), math.sin(-theta))
    lengths = (abs(pe - b_), abs(pf - c_))
    w = complex(math.cos(theta), math.sin(theta))
    for s in (0.0, delta):  # both modes regular (away from a dead point, where a root is known to ~√ε only)
        *_, det = slider_analogs(s, w, d, e, u, v, Jet(b_, 0j, 0j), Jet(c_, 0j, 0j))
        assume(abs(det) / (lengths[0] * lengths[1] * (abs(u) + abs(v))) > NEAR_SINGULAR)
    roots, slides = slider_roots(d, e, b_, c_, lengths, u, v)
    real = np.isfinite(roots)
    size = abs(d) + abs(b_) + abs(c_) + sum(lengths) + abs(u) + abs(v) + 1.0
    for s in (0.0, delta):
        k = pick(roots[real].tolist(), slides[real].tolist(), theta, s, abs(u) + abs(v))
        assert abs(math.remainder(roots[real][k] - theta, 2 * math.pi)) <= 1e-9
        assert abs(slides[real][k] - s) <= 1e-9 * size
