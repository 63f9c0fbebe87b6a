"""Forward dynamics with Coulomb friction and several inputs (issue 29 item 3;
docs/dynamics.md#friction-with-several-inputs)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import numpy as np
import pytest

import solver
from solver.dynamics.reduced import reduced_model

ROOT = Path(__file__).resolve().parents[2]
FIVE_BAR = ROOT / "tests/dynamics/scenes/friction_five_bar_pendulum.yaml"
#: the issue's energy balance, relative to the initial energy
BALANCE = 1e-9
#: one state's equations against the kinetostatics: a few ulps of the largest term
ROUNDING = 1e-12
#: the integrator's tolerance of the run from rest (rtol = atol)
TIGHT = 1e-11
#: the five-bar's release: its cranks' angles (rad), at rest
RELEASE = (-1.0, -1.9)


@pytest.fixture(scope="module")
def five_bar() -> Any:
    return solver.load_scene(str(FIVE_BAR))


@pytest.fixture(scope="module")
def excavator() -> Any:
    return solver.load_scene("excavator_friction")


@pytest.fixture(scope="module")
def released(five_bar: Any) -> Any:
    """Released from rest, run until after both cranks stick (1.46 s)."""
    return five_bar.simulate(2.0, phi0=RELEASE, omega0=0.0, rtol=TIGHT, atol=TIGHT)


def _states(scene: Any, rng: np.random.Generator, n: int) -> list[tuple[list[float], list[float], list[float]]]:
    """Random (q, q̇, Q_drive): the five-bar about its hanging position, the excavator over its
    strokes; the drives about the frictionless holding efforts (each input driven or back-driven)."""
    out = []
    for _ in range(n):
        if len(scene.inputs) == 2:
            q = [float(v) for v in rng.uniform([-2.1, -2.3], [-0.9, -1.1])]
            qd = [float(v) for v in rng.uniform(-4.0, 4.0, 2)]
        else:
            q = [float(rng.uniform(lo + 0.05, hi - 0.05)) for lo, hi in scene.input_ranges]
            qd = [float(v) for v in rng.uniform(-0.2, 0.2, 3)]
        k0 = scene.solve(tuple(q), omega=0.0, epsilon=0.0)
        static = [float(k0.ideal_effort(j)) for j in scene.inputs]
        spread = 0.5 if len(scene.inputs) == 2 else 3000.0
        out.append((q, qd, [s + float(rng.uniform(-spread, spread)) for s in static]))
    return out


@pytest.mark.parametrize("name", ["five_bar", "excavator"])
def test_each_state_solves_the_kinetostatics_with_friction(name: str, request: Any) -> None:
    """The ε forward dynamics finds under the drive's efforts (a k-vector, solved per right-hand
    side) is the one at which the kinetostatics with friction (a separate solve: numpy, its own
    directions) needs exactly those efforts, and the dissipated power is its friction power."""
    scene = request.getfixturevalue(name)
    fd = reduced_model(scene).friction
    for q, qd, drive in _states(scene, np.random.default_rng(29), 12):
        st = fd.solve(q, qd, drive)
        k = scene.solve(np.array([q]), omega=np.array([qd]), epsilon=np.array([st.epsilon]))
        scale = max(abs(v) for v in drive) + 1.0
        for i, j in enumerate(scene.inputs):
            assert float(k.effort(j)[0]) == pytest.approx(drive[i], abs=ROUNDING * scale)
        assert float(k.friction_power[0]) == pytest.approx(st.loss, rel=ROUNDING)
        assert st.loss > 0.0


@pytest.mark.parametrize("name", ["five_bar", "excavator"])
def test_a_holding_edge_is_the_kinetostatic_effort_at_the_start(name: str, request: Any) -> None:
    """Input i at rest, the others moving under their drives: each edge of its holding interval
    is its kinetostatic effort as εᵢ → 0 from the side of that start (the friction against it)
    with the others' ε of that edge — and their efforts there are their drives. (The limit is
    taken from εᵢ = ±δ and ±2δ, linearly: the kinetostatics' own εᵢ = ±1e-200 gives the start's
    direction only where no other input moves — else the relative accelerations' rounding, 1e-16,
    outweighs it.)"""
    scene = request.getfixturevalue(name)
    fd = reduced_model(scene).friction
    delta = 1e-7
    for n, (q, qd, drive) in enumerate(_states(scene, np.random.default_rng(7), 6)):
        i = n % len(q)
        qd[i] = 0.0
        lo, hi = fd.holding(q, qd, drive, i)
        assert lo < hi
        for side, edge in ((-1.0, lo), (1.0, hi)):
            st = fd.edge(q, qd, drive, i, side)
            assert st.epsilon[i] == 0.0 and st.efforts[i] == edge
            efforts = []
            for step in (delta, 2 * delta):
                eps = list(st.epsilon)
                eps[i] = side * step
                k = scene.solve(np.array([q]), omega=np.array([qd]), epsilon=np.array([eps]))
                efforts.append([float(k.effort(j)[0]) for j in scene.inputs])
            scale = max(abs(v) for v in drive) + abs(edge) + 1.0
            for n2 in range(len(q)):
                limit = 2 * efforts[0][n2] - efforts[1][n2]
                assert limit == pytest.approx(edge if n2 == i else drive[n2], abs=ROUNDING * scale)


def _initial_energy(scene: Any, run: Any) -> float:
    """T + V at the release, V measured from its lowest value over the cranks' range about the
    hanging position (the energy there is to lose)."""
    model = reduced_model(scene)
    g = np.linspace(-2.6, -0.6, 201)
    grid = np.stack([a.ravel() for a in np.meshgrid(g, g, indexing="ij")], axis=1)
    lowest = float(np.min(model.potential(grid)["gravity"]))
    e = run.energy()
    return float(e["kinetic"][0] + e["gravity"][0]) - lowest


def test_released_from_rest_each_crank_turns_back_and_both_stick(five_bar: Any, released: Any) -> None:
    run = released
    assert run.status == "done" and run.t[-1] == 2.0
    lines = [m for m in run.messages if " sticks: " in m or " slips toward " in m]  # the inputs' lines
    assert len(lines) == len(run.switches) == len(run.switch_inputs) >= 4
    assert run.messages[0].startswith("t = 0 s, q1 = -1, q2 = -1.9: pin A2 locks: its friction holds its relative "
                                      "motion while the inputs move")
    assert "pin A2 slips: its moment reaches its friction's" in run.messages[1]
    kinds = [kind for kind, _, _ in run.switches]
    assert kinds[-2:] == ["stick", "stick"] and sorted(run.switch_inputs[-2:]) == ["q1", "q2"]
    assert {"q1", "q2"} <= {j for (kind, _, _), j in zip(run.switches, run.switch_inputs) if kind == "slip"}
    first, last = run.switches[-2], run.switches[-1]
    assert first[1] < last[1]
    assert f"{run.switch_inputs[-1]} sticks: its holding effort 0 is inside its breakaway interval" in run.messages[-1]
    assert "(q1 stuck)" in run.messages[-1] or "(q2 stuck)" in run.messages[-1]
    assert "moving)" in run.messages[-2]  # the first to stick: the other still moving
    # while the first sticks its crank holds exactly, the other moves; after the second nothing moves
    i = ["q1", "q2"].index(run.switch_inputs[-2])
    between = (run.t >= first[1]) & (run.t < last[1])
    assert np.all(run.omega[between, i] == 0.0) and np.all(run.phi[between, i] == first[2])
    assert np.any(run.omega[between, 1 - i] != 0.0)
    after = run.t >= last[1]
    assert np.all(run.omega[after] == 0.0) and np.all(run.epsilon[after] == 0.0)
    fd = reduced_model(five_bar).friction
    q = [float(v) for v in run.phi[-1]]
    for n in range(2):  # gravity alone is held there, each crank with the other stuck
        lo, hi = fd.holding(q, [0.0, 0.0], [0.0, 0.0], n, stuck={1 - n})
        assert lo <= 0.0 <= hi


def test_the_energy_balance_gains_the_friction_work(five_bar: Any, released: Any) -> None:
    """T + V − W_friction is constant along the run to 1e-9 of the initial energy (issue 29)."""
    e = released.energy()
    e0 = _initial_energy(five_bar, released)
    assert np.max(np.abs(e["balance"])) <= BALANCE * e0
    w = e["work_friction"]
    assert w[0] == 0.0 and np.all(np.diff(w) <= 0.0)  # friction only ever takes energy
    assert -w[-1] == pytest.approx(e["kinetic"][0] + e["gravity"][0] - e["gravity"][-1], rel=BALANCE)


def test_a_torque_that_grows_makes_a_stuck_crank_slip_where_it_leaves_its_interval(five_bar: Any,
                                                                                    released: Any) -> None:
    """Both cranks stuck where the release came to rest; a torque a·t on q1: q1 slips at the t
    where a·t = Q₊ (its interval with q2 stuck), one line, not before."""
    q = [float(v) for v in released.phi[-1]]
    fd = reduced_model(five_bar).friction
    lo, hi = fd.holding(q, [0.0, 0.0], [0.0, 0.0], 0, stuck={1})
    assert lo < 0.0 < hi
    rate = 0.2  # N·m/s
    run = five_bar.simulate(0.5, phi0=q, omega0=0.0, drive=lambda t, q, qd: [rate * t, 0.0], rtol=1e-10,
                            atol=1e-10, on_singular="stop")
    assert [kind for kind, _, _ in run.switches[:3]] == ["stick", "stick", "slip"]
    assert run.switch_inputs[2] == "q1"
    t_slip = run.switches[2][1]
    assert t_slip == pytest.approx(hi / rate, rel=1e-12)
    assert "q1 slips toward +: the effort" in run.messages[2]
    held = run.t <= t_slip
    assert np.all(run.phi[held] == q) and np.all(run.omega[held] == 0.0)
    assert run.omega[-1, 0] > 0.0
    e = run.energy()
    assert np.max(np.abs(e["balance"])) <= 1e-8 * (abs(e["work_drive"][-1]) + 1.0)


def test_the_excavator_boom_sticks_while_the_arm_moves(excavator: Any) -> None:
    """excavator_friction from rest under its frictionless holding forces, the arm's cylinder
    pushed 3 kN beyond: the boom sticks (its holding force inside its interval, seals included),
    the arm slips out; every state needs exactly its drive in the kinetostatics; the energy balance
    holds with the seals' and the pins' work."""
    q = [1.3, 1.6, 1.2]
    k0 = excavator.solve(tuple(q), omega=0.0, epsilon=0.0)
    drive = [float(k0.ideal_effort(j)) for j in excavator.inputs]
    drive[1] += 3000.0
    run = excavator.simulate(0.25, phi0=q, omega0=0.0, drive=drive, rtol=1e-10, atol=1e-10)
    assert run.status == "done"
    assert run.switches[0][0] == "stick" and run.switch_inputs[0] == "boom_stroke"
    assert run.messages[0].startswith("t = 0 s, boom_stroke = 1.3 m: boom_stroke sticks: its holding effort")
    stuck = run.omega[:, 0] == 0.0
    assert np.all(run.phi[stuck, 0] == 1.3) and np.all(run.epsilon[stuck, 0] == 0.0)
    assert np.all(run.omega[1:, 1] > 0.0)  # the arm extends
    moving = np.all(run.omega[:, 1:] != 0.0, axis=1)
    k = excavator.solve(run.phi[moving], omega=run.omega[moving], epsilon=run.epsilon[moving])
    for i in (1, 2):
        np.testing.assert_allclose(k.effort(excavator.inputs[i]), drive[i], rtol=ROUNDING)
    e = run.energy()
    assert np.max(np.abs(e["balance"])) <= BALANCE * abs(e["work_drive"][-1])
    assert e["work_friction"][-1] < 0.0


def test_friction_with_several_inputs_refuses_scipys_methods(five_bar: Any) -> None:
    with pytest.raises(solver.DynamicsError, match=r"friction_five_bar_pendulum: .*method.*'DOP853' or 'RK4'"):
        five_bar.simulate(0.1, phi0=RELEASE, method="RK45")


def test_the_drive_may_hold_one_crank_at_rest_and_the_run_says_so_at_the_start(five_bar: Any) -> None:
    """Started at rest with q1's torque inside its interval both with q2 held and with q2
    slipping (q2 free, gravity turning it): q1 sticks at t = 0 (one line, naming q2 as moving)
    and holds while q2 swings."""
    q = [-1.3, -1.7]
    fd = reduced_model(five_bar).friction
    lo2, hi2 = fd.holding(q, [0.0, 0.0], [0.0, 0.0], 1, stuck={0})
    assert hi2 < 0.0  # q2 slips toward +
    held = fd.holding(q, [0.0, 0.0], [0.0, 0.0], 0, stuck={1})
    slipping = fd.holding(q, [0.0, 0.0], [0.0, 0.0], 0, starts=[0.0, 1.0])
    lo, hi = max(held[0], slipping[0]), min(held[1], slipping[1])
    assert lo < hi
    hold = 0.5 * (lo + hi)
    run = five_bar.simulate(0.05, phi0=q, omega0=0.0, drive=[hold, 0.0], rtol=1e-10, atol=1e-10)
    assert run.switches[0][:2] == ("stick", 0.0) and run.switch_inputs[0] == "q1"
    assert run.messages[0].endswith("(q2 moving)")
    assert run.omega[1, 1] > 0.0 and run.omega[1, 0] == 0.0 and run.phi[1, 0] == q[0]
    e = run.energy()
    assert np.max(np.abs(e["balance"])) <= BALANCE * (abs(e["gravity"][0] - e["gravity"][-1]) + 1e-3)


def test_a_pin_the_friction_holds_either_way_is_locked_at_the_release(five_bar: Any) -> None:
    """At the release from rest, pin A2's friction against either start of its relative rotation
    would drive that rotation (its relative acceleration has the friction's own sign both ways):
    it is locked — its moment λ the unknown that keeps its relative acceleration 0, within its
    friction (|λ| < c·|R|), and the efforts are the drives."""
    fd = reduced_model(five_bar).friction
    q, qd, drive = list(RELEASE), [0.0, 0.0], [0.0, 0.0]
    a2 = next(j for j, e in enumerate(fd.elements) if e.point == "A2")
    stuck, starts, _ = fd.settle(q, qd, drive, [0, 1])
    assert not stuck and all(starts)
    mode = fd.consistent(q, qd, drive, fd.mode(q, qd, drive, starts=starts))
    assert a2 in mode.locked and mode.dirs[a2] == 0.0
    st = fd.solve(q, qd, drive, mode=mode)
    acc = fd.relative_accelerations(q, qd, st.epsilon)
    assert abs(acc[a2]) <= ROUNDING * max(abs(v) for v in st.epsilon)
    lam, most = st.holds[a2]
    assert 0.0 < abs(lam) < most
    released = five_bar.simulate(0.02, phi0=RELEASE, omega0=0.0, rtol=TIGHT, atol=TIGHT)
    for n in range(2):  # the run's first samples: A2 held (the ε its integrator had)
        eps = [float(v) for v in released.epsilon[n]]
        rel = fd.relative_accelerations([float(v) for v in released.phi[n]], [float(v) for v in released.omega[n]],
                                        eps)[a2]
        assert abs(rel) <= ROUNDING * max(abs(v) for v in eps)
    for d in (-1.0, 1.0):  # either direction of its friction would drive its own rotation
        dirs = list(mode.dirs)
        dirs[a2] = d
        trial = fd.solve(q, qd, drive, mode=type(mode)(dirs, mode.sigma, frozenset(mode.locked - {a2})))
        assert fd.relative_accelerations(q, qd, trial.epsilon)[a2] * d > 0.0


REFERENCE = ROOT / "tests/data/friction_ref_five_bar_states.json"


def test_the_slip_accelerations_agree_with_the_50_digit_newton_euler_reference(five_bar: Any) -> None:
    """Against tests/reference/friction_multi_mp.py (Newton–Euler in absolute coordinates, 22
    unknowns at 50 digits, the five friction circles by fixed point): ε1, ε2 under the crank
    torques and the dissipated power at three states, to round-off."""
    ref = json.loads(REFERENCE.read_text(encoding="utf-8"))
    assert ref["scene_file"] == str(FIVE_BAR.relative_to(ROOT))
    fd = reduced_model(five_bar).friction
    for case in ref["expected"]:
        q1, q2, w1, w2, t1, t2 = (float(v) for v in case["state"])
        st = fd.solve([q1, q2], [w1, w2], [t1, t2])
        expected = [float(v) for v in case["epsilon"]]
        scale = max(abs(v) for v in expected)
        for got, want in zip(st.epsilon, expected):
            assert abs(got - want) <= ROUNDING * scale
        assert st.loss == pytest.approx(float(case["loss"]), rel=ROUNDING)


def test_the_holding_interval_agrees_with_the_50_digit_reference(five_bar: Any) -> None:
    """Crank 1 at rest while crank 2 moves: the edges of its holding interval, and crank 2's ε at
    each, against the reference's Newton–Euler with crank 1 held (its torque a 23rd unknown, its
    pivot's friction against each start), to round-off."""
    ref = json.loads(REFERENCE.read_text(encoding="utf-8"))
    fd = reduced_model(five_bar).friction
    assert len(ref["holding"]) == 4
    for case in ref["holding"]:
        q1, q2, w1, w2, t1, t2 = (float(v) for v in case["state"])
        side = float(case["held"])
        lo, hi = fd.holding([q1, q2], [w1, w2], [t1, t2], 0)
        edge = float(case["effort"])
        assert (lo if side < 0 else hi) == pytest.approx(edge, rel=ROUNDING)
        st = fd.edge([q1, q2], [w1, w2], [t1, t2], 0, side)
        assert st.epsilon[1] == pytest.approx(float(case["epsilon"][1]), rel=ROUNDING)
