"""bench/relay.py's pieces: the Gauss–Newton anchor and the 50-digit reference it is judged by."""

from __future__ import annotations

import math

import pytest

import solver
from bench.relay import DEG, DOUBLE_ROCKER, FOUR_BAR, HARVESTER, GaussNewton, reference, run

#: The reference rounded to double, against the solver (rad or m; analogs relative to max(|v|, 1)).
TOL = 1e-13


@pytest.mark.parametrize("mech", [FOUR_BAR, HARVESTER, DOUBLE_ROCKER], ids=lambda m: m.scene)
def test_the_bench_reference_agrees_with_the_solver(mech: object) -> None:
    scene = solver.load_scene(mech.scene).everything()  # type: ignore[attr-defined]
    for phi in (0.3, 1.2, -1.0, 1.98):
        (q1, q2), (v1, v2) = reference(mech, phi)  # type: ignore[arg-type]
        k = scene.solve(phi)
        a, b = (k.joint(n) for n in mech.joints)  # type: ignore[attr-defined]
        assert abs(math.remainder(float(a.position) - q1, 2 * math.pi)) <= TOL
        assert abs(float(b.position) - q2) <= TOL or abs(math.remainder(float(b.position) - q2, 2 * math.pi)) <= TOL
        assert abs(float(a.velocity) - v1) <= TOL * max(abs(v1), 1.0)
        assert abs(float(b.velocity) - v2) <= TOL * max(abs(v2), 1.0)


@pytest.mark.parametrize("mech", [FOUR_BAR, HARVESTER], ids=lambda m: m.scene)
def test_warm_started_gauss_newton_follows_small_steps_on_the_scenes_assembly(mech: object) -> None:
    gn = GaussNewton(mech, 0.0)  # type: ignore[arg-type]
    for k in range(1, 361):
        phi = k * DEG
        (q1, q2), _, iterations = gn.solve(phi, 1.0)
        (r1, r2), _ = reference(mech, phi)  # type: ignore[arg-type]
        assert abs(math.remainder(q1 - r1, 2 * math.pi)) <= 1e-12 and iterations < 10
        assert abs(math.remainder(q2 - r2, 2 * math.pi)) <= 1e-12


def test_quick_bench_gives_a_row_per_method_and_case() -> None:
    rows = run(quick=True, repeat=1)
    cases = {r.case for r in rows}
    assert len(rows) == 2 * len(cases) and "hard/double_rocker toggle" in cases
    ours = [r for r in rows if r.method.startswith("ours")]
    assert all(r.lost == 0 and r.position_error < 1e-9 for r in ours)
