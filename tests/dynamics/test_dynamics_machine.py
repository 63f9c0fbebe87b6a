"""Steady states that always converge (issue 32): the periodic solve in φ against a cycle in time,
the sweep of extra flywheels 1e-4 … 10 kg·m² on every shipped one-input machine, the bare engine
(no steady motion, said in one line) and its flywheel, and the docs' figures against the bench
that prints them (``python -m bench.machine_numbers``)."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

import solver
from bench.machine_numbers import MACHINES, SWEEP, bare_engine, numbers
from solver.dynamics import flywheel_for, steady_state

ROOT = Path(__file__).resolve().parents[2]


def test_the_periodic_solution_in_phi_closes_its_cycle_in_time() -> None:
    scene = solver.load_scene("harvester_finger")
    s = steady_state(scene)
    run = scene.simulate(10.0, phi0=0.0, omega0=float(s.omega[0]), until_phi=s.cycle, rtol=1e-11, atol=1e-11)
    assert run.status == "until"
    assert run.omega[-1] == pytest.approx(s.omega[0], rel=1e-8)  # the cycle returns to ω₀
    assert run.t[-1] == pytest.approx(s.period, rel=1e-8)
    w_time = run.at(s.t[1:-1])[1]
    np.testing.assert_allclose(s.omega[1:-1], w_time, rtol=1e-7)  # ω(φ) along the cycle, both ways


@pytest.mark.slow
@pytest.mark.parametrize("name", MACHINES)
def test_every_extra_flywheel_from_1e_4_to_10_converges(name: str) -> None:
    scene = solver.load_scene(name)
    deltas = []
    for jf in SWEEP:
        s = steady_state(scene, flywheel=jf)
        assert s.omega_min > 0 and s.period > 0
        deltas.append(s.delta)
    assert all(b < a for a, b in zip(deltas, deltas[1:]))  # more flywheel, less fluctuation
    print(f"{name}: δ from {deltas[0]:.4g} to {deltas[-1]:.4g} over {len(SWEEP)} flywheels, 100 % converged")


@pytest.mark.slow
def test_the_engine_without_its_flywheel_has_no_steady_motion_and_its_flywheel_is_the_shipped_one(
        tmp_path: Path) -> None:
    bare = bare_engine(tmp_path)
    with pytest.raises(solver.DynamicsError, match=r"engine: no steady periodic motion: from ω₀ below .* rad/s at "
                                                   r"φ₀ = 0 rad the machine stalls within the cycle, from above it "
                                                   r"ends the cycle slower than it began") as info:
        steady_state(bare)
    assert "\n" not in str(info.value)
    jf, state, estimate = flywheel_for(bare, 1 / 80)
    assert state.delta == pytest.approx(1 / 80, rel=1e-6)
    assert jf == pytest.approx(0.5913, abs=1e-4)  # what config/scenes/engine.yaml carries
    assert estimate == pytest.approx(jf, rel=0.01)


@pytest.mark.slow
def test_flywheel_for_the_shipped_engine_adds_next_to_nothing() -> None:
    jf, state, _ = flywheel_for(solver.load_scene("engine"), 1 / 80)
    assert 0 < jf < 1e-4 and state.delta == pytest.approx(1 / 80, rel=1e-6)


def _figures(text: str) -> str:
    section = text[text.index("## Machine dynamics"):text.index("## In ROS")]
    return re.sub(r"\s+", " ", section)


@pytest.mark.slow
def test_the_docs_machine_figures_are_the_bench_s(tmp_path: Path) -> None:
    got = numbers(tmp_path)
    text = _figures((ROOT / "docs" / "dynamics.md").read_text(encoding="utf-8"))
    expected = [
        f"{got['gas_work_J']:.0f} J per 720° cycle",
        f"steady {got['omega_mean']:.1f} rad/s ({got['rpm']:.0f} rpm)",
        f"`flywheel_for(bare, 1 / 80)` gives {got['flywheel_bare']:.4f} kg·m² (the classical estimate: "
        f"{got['flywheel_bare_estimate']:.4f})",
        f"its steady δ is 1/{got['inv_delta']:.1f}",
        f"adds {got['flywheel_engine']:.1e} kg·m²",
        f"enters its steady band in {got['harvester_run_up'] * 1e3:.0f} ms",
        f"a mean {got['harvester_mean']:.1f} rad/s with δ ≈ {got['harvester_delta']:.2f}",
    ]
    missing = [e for e in expected if e not in text]
    assert not missing, f"docs/dynamics.md does not say: {missing}"
    assert "no steady periodic motion" in got["bare"]
    assert math.isfinite(got["flywheel_bare_s"])


@pytest.mark.slow
def test_a_machine_without_losses_has_no_isolated_steady_motion_and_says_so() -> None:
    with pytest.raises(solver.DynamicsError, match=r"four_bar_pendulum: no isolated steady motion: the cycle closes "
                                                   r"at every ω₀ .* a machine without losses"):
        steady_state(solver.load_scene("four_bar_pendulum"))
