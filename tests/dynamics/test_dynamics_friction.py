"""Forward dynamics with Coulomb friction (issue 29 item 3; docs/dynamics.md#friction)."""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import solver
from solver.dynamics.reduced import reduced_model
from solver.forces.friction import breakaway
from tests.scene_builders import build

ROOT = Path(__file__).resolve().parents[2]
SCENE = ROOT / "tests/dynamics/scenes/friction_four_bar_pendulum.yaml"
REFERENCE = ROOT / "tests/data/friction_ref_four_bar_pendulum.json"
#: the issue's agreement with the 50-digit reference: the time and angle where it sticks
STICK = 1e-8
#: the issue's energy balance, relative to the initial energy
BALANCE = 1e-9
#: one state's equations against the kinetostatics: a few ulps of the largest term
ROUNDING = 1e-12
#: the integrator's tolerance of the reference comparison (rtol = atol)
TIGHT = 1e-12


def _scene(**friction: Any) -> Any:
    data = yaml.safe_load(SCENE.read_text(encoding="utf-8"))
    if friction:
        data["friction"] = friction
    return build(data)


@pytest.fixture(scope="module")
def pendulum() -> Any:
    return solver.load_scene(str(SCENE))


@pytest.fixture(scope="module")
def released(pendulum: Any) -> Any:
    """Released from rest at φ = 0.3 rad, run until after it sticks (1.45 s)."""
    return pendulum.simulate(2.0, phi0=0.3, omega0=0.0, rtol=TIGHT, atol=TIGHT)


def test_each_state_solves_the_kinetostatics_with_friction(pendulum: Any) -> None:
    """The ε forward dynamics finds under an effort is the one at which the kinetostatics with
    friction (a separate solve: numpy, the kinetostatics' own directions) needs that effort, and
    the dissipated power is its friction power."""
    fd = reduced_model(pendulum).friction
    rng = np.random.default_rng(29)
    for _ in range(20):
        phi, omega, drive = rng.uniform(-math.pi, math.pi), rng.uniform(-6.0, 6.0), rng.uniform(-0.5, 0.5)
        st = fd.solve(phi, omega, drive)
        k = pendulum.solve(np.array([phi]), omega=omega, epsilon=st.epsilon)
        assert float(k.effort("crank")[0]) == pytest.approx(drive, abs=ROUNDING * max(1.0, abs(st.epsilon) * 0.01))
        assert float(k.friction_power[0]) == pytest.approx(st.loss, rel=ROUNDING)


def test_the_fallback_solve_gives_the_generated_ones_state(pendulum: Any, monkeypatch: pytest.MonkeyPatch) -> None:
    """Where the generated one-sample Newton gives up, the right-hand side takes the vectorised
    solve on the lists of the same compiled pass: the same ε, loss and other effort to round-off."""
    fd = reduced_model(pendulum).friction
    rng = np.random.default_rng(30)
    states = [(rng.uniform(-math.pi, math.pi), rng.uniform(-6.0, 6.0), rng.uniform(-0.5, 0.5)) for _ in range(10)]
    fast = [fd.solve_rates(*state) for state in states]
    size, start, iu, iv, _ = fd._layout
    monkeypatch.setattr(fd, "_layout", (size, start, iu, iv, lambda *args: None))
    for state, want in zip(states, fast):
        fd._last = fd._memo = (None, None, None)
        got = fd.solve_rates(*state)
        assert got[0] == pytest.approx(want[0], rel=ROUNDING, abs=ROUNDING)
        assert got[1] == pytest.approx(want[1], rel=ROUNDING, abs=ROUNDING)
        assert got[2:] == want[2:]


def test_the_holding_interval_is_the_kinetostatic_breakaway(pendulum: Any) -> None:
    fd = reduced_model(pendulum).friction
    for phi in (-2.5, -1.466, 0.3, 1.2, 2.9):
        lo, hi = fd.holding(phi)
        rlo, rhi = breakaway(pendulum, phi)
        assert lo < hi
        assert lo == pytest.approx(rlo, rel=ROUNDING, abs=ROUNDING)
        assert hi == pytest.approx(rhi, rel=ROUNDING, abs=ROUNDING)


def _initial_energy(pendulum: Any, run: Any) -> float:
    """T + V at the release, V measured from its lowest value over a turn (the energy there is to lose)."""
    model = reduced_model(pendulum)
    lowest = float(np.min(model.potential(np.linspace(-math.pi, math.pi, 20001))["gravity"]))
    e = run.energy()
    return float(e["kinetic"][0] + e["gravity"][0]) - lowest


def test_released_from_rest_it_swings_and_sticks(pendulum: Any, released: Any) -> None:
    run = released
    kinds = [kind for kind, _, _ in run.switches]
    assert kinds[-1] == "stick" and kinds[:-1] == ["slip"] * (len(kinds) - 1) and len(kinds) >= 3
    assert len(run.messages) == len(kinds)
    assert run.messages[-1].startswith("t = ") and "sticks: the holding effort 0 is inside the breakaway" in \
        run.messages[-1]
    _, t_stick, phi_stick = run.switches[-1]
    after = run.t >= t_stick
    assert np.all(run.omega[after] == 0.0) and np.all(run.phi[after] == phi_stick)
    assert np.all(run.epsilon[after] == 0.0)
    lo, hi = breakaway(pendulum, phi_stick)
    assert lo <= 0.0 <= hi  # gravity alone is held there
    assert run.status == "done" and run.t[-1] == 2.0


def test_the_energy_balance_gains_the_friction_work(pendulum: Any, released: Any) -> None:
    """T + V − W_friction is constant along the run to 1e-9 of the initial energy (issue 29)."""
    e = released.energy()
    e0 = _initial_energy(pendulum, released)
    assert np.max(np.abs(e["balance"])) <= BALANCE * e0
    w = e["work_friction"]
    assert w[0] == 0.0 and np.all(np.diff(w) <= 0.0)  # friction only ever takes energy
    assert -w[-1] == pytest.approx(e["kinetic"][0] + e["gravity"][0] - e["gravity"][-1], rel=BALANCE)


@pytest.mark.skipif(not REFERENCE.exists(), reason="tests/reference/friction_dynamics_mp.py not yet run")
def test_it_sticks_where_the_50_digit_reference_does(pendulum: Any, released: Any) -> None:
    """Against tests/reference/friction_dynamics_mp.py (Newton–Euler in absolute coordinates,
    Gauss–Legendre collocation at 50 digits): the time and angle where it sticks to 1e-8, every
    turning point on the way, and the friction's work E − E₀ there."""
    ref = json.loads(REFERENCE.read_text(encoding="utf-8"))
    assert ref["scene_file"] == str(SCENE.relative_to(ROOT))
    expected = ref["expected"]
    _, t_stick, phi_stick = released.switches[-1]
    assert abs(t_stick - float(expected["t_stick"])) <= STICK
    assert abs(phi_stick - float(expected["phi_stick"])) <= STICK
    turning = [s for s in expected["switches"] if s["kind"] in ("stick", "slip")]
    assert [s["kind"] for s in turning] == [kind for kind, _, _ in released.switches]
    for s, (_, t, q) in zip(turning, released.switches):
        assert abs(t - float(s["t"])) <= STICK and abs(q - float(s["phi"])) <= STICK
    e = released.energy()
    lost = float(expected["energy0"]) - float(expected["energy_stick"])
    assert -e["work_friction"][-1] == pytest.approx(lost, rel=BALANCE / 10)
    estimate = ref["truncation_estimate"]["against_twice_the_step"]
    if "t_stick" in estimate:  # (written by ``--check``)
        assert float(estimate["t_stick"]) < STICK / 10


def test_a_drive_that_grows_makes_it_slip_where_it_leaves_the_breakaway_interval() -> None:
    """Held at rest, a torque a·t on the crank: it slips at the t where a·t = Q₊ (one line), not before."""
    scene = _scene(all_pins={"mu": 0.3, "radius": 0.02})
    phi = -1.46
    lo, hi = breakaway(scene, phi)
    assert lo < 0.0 < hi
    rate = 0.5  # N·m/s
    run = scene.simulate(1.0, phi0=phi, omega0=0.0, drive=lambda t, q, qd: rate * t, rtol=1e-10, atol=1e-10)
    assert [kind for kind, _, _ in run.switches[:2]] == ["stick", "slip"]
    t_slip = run.switches[1][1]
    assert t_slip == pytest.approx(hi / rate, rel=1e-12)
    assert "slips toward +: the effort" in run.messages[1]
    held = run.t <= t_slip
    assert np.all(run.phi[held] == phi) and np.all(run.omega[held] == 0.0)
    assert run.omega[-1] > 0.0
    e = run.energy()
    assert np.max(np.abs(e["balance"])) <= 1e-8 * (abs(e["work_drive"][-1]) + 1.0)


def test_a_slide_in_the_dynamics_balances_its_energy() -> None:
    """A slider-crank with friction at every pin and in its guide: the run's
    energy balance with the friction's work, and each state against the kinetostatics."""
    scene = solver.load_scene(str(ROOT / "tests/forces/scenes/friction_slider_crank.yaml"))
    run = scene.simulate(0.2, phi0=0.4, omega0=20.0, drive=0.0, rtol=1e-11, atol=1e-11)
    e = run.energy()
    scale = float(e["kinetic"][0]) + float(np.ptp(e["gravity"])) + 1e-3
    assert np.max(np.abs(e["balance"])) <= 1e-9 * scale
    assert e["work_friction"][-1] < 0.0
    k = scene.solve(run.phi[1:6], omega=run.omega[1:6], epsilon=run.epsilon[1:6])
    np.testing.assert_allclose(k.effort("crank"), 0.0, atol=1e-9)


def test_a_cylinders_seal_and_pin_friction_on_a_stroke_input() -> None:
    """tipper (an input that is a cylinder's stroke, N) with a seal of 300 N and a friction circle
    at O, pushed from rest by 2000 N beyond its breakaway force: each state needs exactly that
    force in the kinetostatics, and the energy balance holds with the seal's and the pin's work."""
    from solver._loader import parse_scene

    data = yaml.safe_load((ROOT / "config/scenes/tipper.yaml").read_text(encoding="utf-8"))
    data["friction"] = {"pins": {"O": {"mu": 0.15, "radius": 0.03}}, "actuators": {"lift": {"force": 300.0}}}
    scene = solver.Scene(parse_scene(data, file=None))
    lo, hi = breakaway(scene, 1.0)
    assert hi - lo > 600.0  # the seal's 300 N either way, and the pin's
    push = hi + 2000.0
    run = scene.simulate(0.3, phi0=1.0, omega0=0.0, drive=push, rtol=1e-11, atol=1e-11)
    assert run.status == "done" and np.all(run.omega[1:] > 0.0)
    k = scene.solve(run.phi[1:8], omega=run.omega[1:8], epsilon=run.epsilon[1:8])
    np.testing.assert_allclose(k.effort("stroke"), push, rtol=ROUNDING)
    e = run.energy()
    assert np.max(np.abs(e["balance"])) <= 1e-9 * e["work_drive"][-1]
    seal_work = 300.0 * (run.phi[-1] - 1.0)
    assert -e["work_friction"][-1] > seal_work  # the seal's, and the pin's on top


def test_the_nodes_dynamic_mode_refuses_friction_in_one_line(pendulum: Any) -> None:
    """The node's fixed-step path (solver.dynamics.Stepper) does not model friction: its dynamic
    law says so in one line (the node reports it as the reason it cannot run the mode)."""
    from linkage_ros.dynamic import dynamic_law

    with pytest.raises(solver.DynamicsError, match=r"^friction_four_bar_pendulum: names friction: the fixed-step "
                                                   r"Stepper \(the node's dynamic mode\) does not model Coulomb"):
        dynamic_law(pendulum, {}, phi0=0.3, omega=0.0, t0=0.0)
