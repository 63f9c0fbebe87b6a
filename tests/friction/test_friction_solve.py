"""The friction magnitudes' solvers (solver/forces/_friction_solve.py) against each other.

x = c·|R₀ + Σⱼ xⱼ·dⱼ·B_j| on random systems of bounded gain: the columns' Newton (``solve``), the
pivoted per-sample Newton (``newton``, its fallback) and the one-sample straight-line Newton
(``solve_one``) agree to round-off, satisfy the equations to a few ulps, tell the same
self-locking (a gain beyond 1: no solution), and the reduced system ``shift`` forms is the
explicit one; ``solve_flat`` (the same generated Newton reading a compiled instant's flat output in
place, the dynamics' right-hand side) is ``solve_one`` with ``shift`` to the bit, and its sums of
x·d·u and x·d·v′ are Python's sums of those products.
"""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from solver.forces._friction_solve import CONVERGED, newton, solve, solve_flat, solve_one

#: agreement of two solvers of the same well-conditioned system (a few ulps, times 1/(1 − gain))
AGREE = 64 * CONVERGED


def _system(seed: int, n: int, m: int, gain: float) -> tuple[list[np.ndarray], list[list[np.ndarray]],
                                                               list[np.ndarray], np.ndarray]:
    """n samples of an m-element system whose friction moves every reaction by about ``gain``."""
    rng = np.random.default_rng(seed)
    r0 = [rng.normal(size=n) + 1j * rng.normal(size=n) + (2.0 + 1.0j) for _ in range(m)]
    c = rng.uniform(0.05, 0.15, size=m)
    b = [[gain / (m * c[k]) * (rng.uniform(-1, 1, size=n) + 1j * rng.uniform(-1, 1, size=n)) for k in range(m)]
         for _ in range(m)]
    dirs = [rng.choice([-1.0, 1.0], size=n) for _ in range(m)]
    return r0, b, dirs, c


def _residual(x: np.ndarray, r0: list[np.ndarray], b: list[list[np.ndarray]], dirs: list[np.ndarray],
              c: np.ndarray) -> float:
    m = len(r0)
    worst = 0.0
    for k in range(m):
        r = r0[k] + sum(x[:, j] * dirs[j] * b[j][k] for j in range(m))
        worst = max(worst, float(np.max(np.abs(x[:, k] - c[k] * np.abs(r)) / np.max(x, axis=1))))
    return worst


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), m=st.integers(1, 5), gain=st.floats(0.0, 0.5))
def test_columns_per_sample_and_one_sample_newton_agree(seed: int, m: int, gain: float) -> None:
    n = 40
    r0, b, dirs, c = _system(seed, n, m, gain)
    x, locked = solve(r0, b, dirs, list(range(m)), c, n)
    assert not locked.any()
    assert _residual(x, r0, b, dirs, c) <= 4 * CONVERGED
    ref, ref_locked = newton(r0, b, dirs, c, n, np.zeros((n, m)))
    assert not ref_locked.any()
    np.testing.assert_allclose(x, ref, rtol=AGREE, atol=AGREE * float(np.max(ref)))
    for i in range(0, n, 7):
        one = solve_one([r[i] for r in r0], [[bk[i] for bk in bj] for bj in b], [float(d[i]) for d in dirs],
                        [float(v) for v in c])
        assert one is not None
        np.testing.assert_allclose(one, x[i], rtol=AGREE, atol=AGREE * float(np.max(x[i])))


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), m=st.integers(1, 4), s=st.floats(-3.0, 3.0))
def test_shift_forms_the_reduced_system(seed: int, m: int, s: float) -> None:
    r0, b, dirs, c = _system(seed, 1, m, 0.3)
    rng = np.random.default_rng(seed + 1)
    a = [complex(rng.normal(), rng.normal()) * 0.1 for _ in range(m)]
    v = [float(rng.normal()) * 0.1 for _ in range(m)]
    r0s, ds, cs = [complex(r[0]) for r in r0], [float(d[0]) for d in dirs], [float(x) for x in c]
    bs = [[complex(bk[0]) for bk in bj] for bj in b]
    shifted = solve_one(r0s, bs, ds, cs, shift=(a, s, v))
    explicit = solve_one([r0s[k] + a[k] * s for k in range(m)],
                         [[bs[j][k] - a[k] * v[j] for k in range(m)] for j in range(m)], ds, cs)
    assert shifted is not None and explicit is not None
    np.testing.assert_allclose(shifted, explicit, rtol=AGREE, atol=AGREE * max(explicit))


@settings(max_examples=15, deadline=None)
@given(seed=st.integers(0, 2**31 - 1), m=st.integers(1, 5), s=st.floats(-3.0, 3.0), mass=st.floats(0.01, 10.0),
       pad=st.integers(0, 3))
def test_flat_layout_is_the_shifted_solve_to_the_bit(seed: int, m: int, s: float, mass: float, pad: int) -> None:
    r0, b, dirs, c = _system(seed, 1, m, 0.3)
    rng = np.random.default_rng(seed + 2)
    a = [complex(rng.normal(), rng.normal()) * 0.1 for _ in range(m)]
    u = [float(rng.normal()) * 0.1 * mass for _ in range(m)]  # uⱼ/M ≈ 0.1: a solvable system
    r0s, ds, cs = [complex(r[0]) for r in r0], [float(d[0]) for d in dirs], [float(x) for x in c]
    bs = [[complex(bk[0]) for bk in bj] for bj in b]
    # the dynamics' layout (solver.dynamics._friction.FrictionLayer): R₀, A, then per element uⱼ,
    # B_j·, two analogs, behind ``pad`` other values
    flat: list[complex | float] = [7.0] * pad + r0s + a
    iu = []
    for j in range(m):
        iu.append(len(flat))
        flat += [u[j], *bs[j], float(rng.normal()), -0.5]
    iv = [i + 1 + m for i in iu]
    fast = solve_flat(m, (pad, pad + m, iu, [i + 1 for i in iu], iv))
    shifted = solve_one(r0s, bs, ds, cs, shift=(a, s, [uj / mass for uj in u]))
    assert shifted is not None
    x, su, sv = fast(tuple(flat), ds, cs, s, mass)
    assert x == shifted
    assert su == sum([xj * dj * flat[i] for xj, dj, i in zip(x, ds, iu)])
    assert sv == sum([xj * dj * flat[i] for xj, dj, i in zip(x, ds, iv)])


def test_no_solution_is_self_locking_and_one_sample_gives_up() -> None:
    # one element whose own friction adds to its reaction: x = 0.1·|1 + B·x|, B = 20 (gain 2: no
    # x ≥ 0 solves x = 0.1 + 2x) and B = 5 (gain 0.5: x = 0.2)
    r0, c = [np.array([1.0 + 0j, 1.0 + 0j])], np.array([0.1])
    b = [[np.array([20.0 + 0j, 5.0 + 0j])]]
    dirs = [np.array([1.0, 1.0])]
    x, locked = solve(r0, b, dirs, [0], c, 2)
    assert locked.tolist() == [True, False]
    assert abs(x[1, 0] - 0.2) <= 4 * CONVERGED * 0.2  # x = 0.1 + 0.5·x
    assert solve_one([1.0 + 0j], [[20.0 + 0j]], [1.0], [0.1]) is None
    assert solve_one([], [], [], []) == []


def test_results_are_not_the_reused_workspace() -> None:
    r0, b, dirs, c = _system(1, 64, 3, 0.3)
    x1, _ = solve(r0, b, dirs, [0, 1, 2], c, 64)
    kept = x1.copy()
    solve(*_system(2, 64, 3, 0.3)[:3], [0, 1, 2], c, 64)
    assert np.array_equal(x1, kept)
