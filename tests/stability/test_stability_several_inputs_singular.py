"""What is exact at the five-bar's singular samples (docs/inputs.md): the loop closure, always;
P against the exact inputs only as far as the conditioning allows (against 50 digits)."""

from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

import solver
from solver.tolerances import EPS

#: the cranks' circles (radius 0.15 about (0, 0) and (0.2, 0)) cross at (0.1, Y): A1 = A2 there
Y = math.sqrt(0.15**2 - 0.1**2)
FOLDED = (math.atan2(Y, 0.1), math.atan2(Y, -0.1))


def _exact(q1: float, q2: float) -> tuple[complex, float]:
    """P and |A1A2| in 50 digits at the double (q1, q2) (M = −1, distal links 0.25 m)."""
    with mpmath.workdps(50):
        m = mpmath.mpf
        a1 = m("0.15") * mpmath.expj(m(q1))
        a2 = m("0.2") + m("0.15") * mpmath.expj(m(q2))
        d = a2 - a1
        dd = abs(d) ** 2
        h = mpmath.sqrt(m("0.0625") / dd - m("0.25"))
        return complex(a1 + d * (m("0.5") + 1j * h)), float(mpmath.sqrt(dd))


@pytest.mark.parametrize("offset", [1e-2, 1e-6, 1e-10, 1e-14])
def test_near_the_folded_singularity_the_loop_closes_and_p_is_as_good_as_its_conditioning(offset: float) -> None:
    scene = solver.load_scene("five_bar").everything()
    q = np.array([[FOLDED[0] + offset, FOLDED[1]]])
    k = scene.solve(q)
    p, a1, a2 = (k.point(n).position[0] for n in ("P", "A1", "A2"))
    for a in (a1, a2):
        assert abs(math.hypot(*(p - a)) - 0.25) <= 4 * EPS * 0.25
    want, gap = _exact(*q[0])
    # one ulp of the inputs turns A2 − A1 by EPS·0.2/|A1A2|: P moves 0.25 m times that
    bound = 16 * EPS * 0.2 * 0.25 / gap
    assert abs(complex(*p) - want) <= max(bound, 1e-15)
    if offset <= 1e-14:
        assert abs(complex(*p) - want) > 1e-4  # millimetres: the text says so, it is not exact
    assert bool(k.singular[0]) == (offset < 1e-4)


def test_at_the_stretched_singularity_p_is_exact() -> None:
    k = solver.load_scene("five_bar").solve(np.array([[math.pi, 0.0]]))
    assert bool(k.singular[0])
    assert abs(complex(*k.point("P").position[0]) - _exact(math.pi, 0.0)[0]) <= 1e-16
    assert np.isnan(k.point("P").jacobian[0]).all()
