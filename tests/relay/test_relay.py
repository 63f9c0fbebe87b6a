"""linkage_ros.relay: JointState messages in, frames of the scene at the message's φ out.

Values against the solver at the same (φ, ω, ε), point B against the 50-digit reference
(tests/data/reference_four_bar.json), dropped and unassemblable messages, the ε and ω rules.
"""

from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import solver
from linkage_ros.engine import Engine
from linkage_ros.motion import Motion
from linkage_ros.relay import (
    ANSWER_DROPPED,
    ANSWER_FRAME,
    ANSWER_IGNORED,
    ANSWER_UNASSEMBLABLE,
    EPSILON_FROM_VELOCITIES,
    EPSILON_FROM_ZERO,
    OMEGA_FROM_MESSAGE,
    OMEGA_FROM_NONE,
    OMEGA_FROM_POSITIONS,
    Relay,
)

DATA = Path(__file__).resolve().parents[1] / "data"
#: B against the 50-digit reference (issue 12), m.
TOL_POS = 1e-12
#: Velocities against v_q·ω (issue 12), relative.
TOL_REL = 1e-9
NS = 1_000_000_000
MS = 1_000_000


def _relay(scene: str = "four_bar", **options: object) -> Relay:
    return Relay(Engine(scene, Motion()), **options)  # type: ignore[arg-type]


def _reference(scene: str) -> dict:
    return json.loads((DATA / f"reference_{scene}.json").read_text())


def test_every_message_is_answered_with_point_b_at_the_reference_and_v_equal_to_vq_omega() -> None:
    ref = _reference("four_bar")
    relay = _relay()
    phis = [float(p) for p in ref["phi"]]
    for i, phi in enumerate(phis):
        omega = 2.5 - 0.1 * i
        stamp = 1_700_000_000 * NS + i * 10 * MS + 123
        answer = relay.answer(["crank"], [phi], [omega], stamp)
        assert answer.kind == ANSWER_FRAME, answer.reason
        assert answer.stamp_ns == stamp and answer.frame is not None
        frame = answer.frame
        assert frame.phi == phi and frame.omega == omega and frame.t == stamp / NS
        b = frame.points["B"]
        expected = [float(x) for x in ref["points"]["B"]["position"][i]]
        assert np.max(np.abs(np.subtract(b.position, expected))) <= TOL_POS
        vq = [float(x) for x in ref["points"]["B"]["d_dphi"][i]]
        v = np.multiply(vq, omega)
        scale = max(float(np.max(np.abs(v))), 1e-300)
        assert np.max(np.abs(np.subtract(b.velocity, v))) <= TOL_REL * scale


def test_frame_equals_the_solver_at_the_same_phi_omega_epsilon() -> None:
    scene = solver.load_scene("harvester_finger").everything()
    relay = _relay("harvester_finger")
    for i, (phi, omega) in enumerate([(0.3, 2.0), (-4.0, -1.5), (12.0, 0.0), (1e-9, 3.0)]):
        answer = relay.answer(["drum"], [phi], [omega], (i + 1) * NS)
        assert answer.kind == ANSWER_FRAME and answer.frame is not None
        k = scene.solve(phi, omega=omega, epsilon=0.0)
        for name in scene.point_names:
            got = answer.frame.points[name]
            want = k.floats(name)
            assert tuple(got.position) == tuple(want[0]) and tuple(got.velocity) == tuple(want[1]), name
        for name in scene.joint_names:
            got_j = answer.frame.joints[name]
            assert (got_j.position, got_j.velocity) == tuple(k.floats(name)[:2]), name


def test_the_input_is_found_among_other_joints_in_any_order() -> None:
    relay = _relay()
    answer = relay.answer(["gripper", "crank", "wrist"], [9.0, 0.4, -1.0], [1.0, 2.0, 3.0], NS)
    assert answer.kind == ANSWER_FRAME and answer.phi == 0.4 and answer.omega == 2.0


@pytest.mark.parametrize(
    ("names", "positions", "velocities", "match"),
    [
        (["wheel"], [0.1], [1.0], "no joint 'crank' in the message"),
        ([], [], [], "no joint 'crank' in the message"),
        (["crank"], [math.nan], [1.0], "position is nan"),
        (["crank"], [math.inf], [1.0], "position is inf"),
        (["crank"], [-math.inf], [], "position is -inf"),
        (["crank"], [0.2], [math.nan], "velocity is nan"),
        (["crank"], [0.2], [math.inf], "velocity is inf"),
        (["wheel", "crank"], [0.1], [], r"no position \(2 names, 1 positions\)"),
        (["wheel", "crank"], [0.1, 0.2], [1.0], r"no velocity \(2 names, 1 velocities\)"),
    ],
)
def test_a_message_without_a_usable_input_is_dropped_with_the_reason(
    names: list[str], positions: list[float], velocities: list[float], match: str
) -> None:
    relay = _relay()
    answer = relay.answer(names, positions, velocities, NS)
    assert answer.kind == ANSWER_DROPPED and answer.frame is None and answer.phi is None
    assert re.search(match, answer.reason), answer.reason


def test_a_dropped_message_leaves_the_previous_state_for_the_differences() -> None:
    relay = _relay()
    relay.answer(["crank"], [0.10], [], NS)
    relay.answer(["crank"], [math.nan], [], NS + 10 * MS)
    answer = relay.answer(["crank"], [0.12], [], NS + 20 * MS)
    assert answer.omega_from == OMEGA_FROM_POSITIONS
    assert answer.omega == pytest.approx(0.02 / 0.020, rel=1e-12)


def test_the_relays_own_joint_states_coming_back_are_ignored() -> None:
    relay = _relay()
    names, q, dq = relay.joint_states(relay.answer(["crank"], [0.3], [1.0], NS).frame)  # type: ignore[arg-type]
    answer = relay.answer(list(names), list(q), list(dq), 2 * NS)
    assert answer.kind == ANSWER_IGNORED and answer.frame is None


def test_unassemblable_input_gets_no_frame_but_the_interval_and_the_next_message_is_answered() -> None:
    relay = _relay("hard/double_rocker")
    bad = relay.answer(["crank"], [math.radians(180.0)], [1.0], NS)
    assert bad.kind == ANSWER_UNASSEMBLABLE and bad.frame is None
    assert "group 'dyad' cannot be assembled for φ in (113.9695°, 246.0305°)" in bad.reason
    assert bad.interval is not None and bad.interval[0] < math.pi < bad.interval[1]
    # the same gap one turn on, and from below
    again = relay.answer(["crank"], [math.radians(180.0 + 360.0)], [1.0], NS + MS)
    assert again.kind == ANSWER_UNASSEMBLABLE and again.interval is not None
    assert again.interval[0] == pytest.approx(bad.interval[0] + 2 * math.pi)
    good = relay.answer(["crank"], [0.5], [1.0], NS + 2 * MS)
    assert good.kind == ANSWER_FRAME and good.frame is not None
    assert good.frame.status == "ok"


@settings(max_examples=60, deadline=None)
@given(
    phi=st.floats(-20.0, 20.0),
    omega=st.floats(-50.0, 50.0),
    scene=st.sampled_from(["hard/double_rocker", "hard/parallelogram", "four_bar", "slider_crank"]),
)
def test_a_frame_never_holds_a_non_finite_number(phi: float, omega: float, scene: str) -> None:
    relay = _relays(scene)
    answer = relay.answer(["crank"], [phi], [omega], NS)
    assert answer.kind in (ANSWER_FRAME, ANSWER_UNASSEMBLABLE)
    if answer.frame is None:
        return
    frame = answer.frame
    for ps in frame.points.values():
        assert all(math.isfinite(x) for x in (*ps.position, *ps.velocity, *ps.acceleration))
    for js in frame.joints.values():
        assert all(math.isfinite(x) for x in js)
    _, q, dq = relay.joint_states(frame)
    assert all(math.isfinite(x) for x in (*q, *dq))


_RELAYS: dict[str, Relay] = {}


def _relays(scene: str) -> Relay:
    if scene not in _RELAYS:
        _RELAYS[scene] = _relay(scene)
    return _RELAYS[scene]


# ------------------------------------------------------------------ ε and ω rules
def test_epsilon_is_zero_by_default_so_accelerations_are_aq_omega_squared() -> None:
    scene = solver.load_scene("four_bar").everything()
    relay = _relay()
    relay.answer(["crank"], [0.30], [1.0], NS)
    answer = relay.answer(["crank"], [0.31], [2.0], NS + 10 * MS)
    assert answer.epsilon == 0.0 and answer.epsilon_from == EPSILON_FROM_ZERO
    assert answer.frame is not None
    k = scene.solve(0.31, omega=1.0, epsilon=0.0)
    aq = k.floats("B")[2]
    np.testing.assert_allclose(answer.frame.points["B"].acceleration, np.multiply(aq, 4.0), rtol=1e-14)


def test_epsilon_difference_is_the_backward_difference_of_successive_velocities() -> None:
    scene = solver.load_scene("four_bar").everything()
    relay = _relay(epsilon="difference")
    first = relay.answer(["crank"], [0.30], [1.0], NS)
    assert first.epsilon == 0.0 and first.epsilon_from == EPSILON_FROM_ZERO  # nothing to difference yet
    answer = relay.answer(["crank"], [0.31], [1.5], NS + 20 * MS)
    assert answer.epsilon_from == EPSILON_FROM_VELOCITIES
    assert answer.epsilon == pytest.approx(0.5 / 0.020, rel=1e-12)
    assert answer.frame is not None
    k = scene.solve(0.31, omega=1.5, epsilon=answer.epsilon)
    assert tuple(answer.frame.points["B"].acceleration) == tuple(k.floats("B")[2])


def test_epsilon_difference_recovers_a_constant_acceleration_exactly_up_to_rounding() -> None:
    relay = _relay(epsilon="difference")
    eps, omega0 = 3.0, 1.0
    for i in range(5):
        t = i * 0.01
        answer = relay.answer(["crank"], [omega0 * t + eps * t * t / 2], [omega0 + eps * t], i * 10 * MS)
    assert answer.epsilon == pytest.approx(eps, rel=1e-9)


@pytest.mark.parametrize(
    ("second_stamp", "second_velocity", "why"),
    [
        (NS + 300 * MS, [2.0], "gap beyond max_gap"),
        (NS, [2.0], "same stamp"),
        (NS - 5 * MS, [2.0], "older stamp"),
        (NS + 10 * MS, [], "no velocity in this message"),
    ],
)
def test_epsilon_difference_falls_back_to_zero(second_stamp: int, second_velocity: list[float], why: str) -> None:
    relay = _relay(epsilon="difference")
    relay.answer(["crank"], [0.30], [1.0], NS)
    answer = relay.answer(["crank"], [0.31], second_velocity, second_stamp)
    assert answer.kind == ANSWER_FRAME
    assert answer.epsilon == 0.0 and answer.epsilon_from == EPSILON_FROM_ZERO, why


def test_omega_without_velocities_is_the_wrapped_difference_of_positions() -> None:
    relay = _relay()
    first = relay.answer(["crank"], [3.1], [], NS)
    assert first.omega == 0.0 and first.omega_from == OMEGA_FROM_NONE
    # across ±π: 3.1 → −3.1 is a step of 2π − 6.2 ≈ +0.0832 rad, not −6.2
    answer = relay.answer(["crank"], [-3.1], [], NS + 10 * MS)
    assert answer.omega_from == OMEGA_FROM_POSITIONS
    assert answer.omega == pytest.approx((2 * math.pi - 6.2) / 0.010, rel=1e-9)
    assert answer.frame is not None and answer.frame.omega == answer.omega
    late = relay.answer(["crank"], [-3.0], [], NS + 10 * MS + NS)
    assert late.omega == 0.0 and late.omega_from == OMEGA_FROM_NONE


def test_velocity_in_the_message_is_used_as_it_is() -> None:
    relay = _relay()
    relay.answer(["crank"], [0.0], [], NS)
    answer = relay.answer(["crank"], [1.0], [-0.25], NS + MS)
    assert answer.omega == -0.25 and answer.omega_from == OMEGA_FROM_MESSAGE


def test_reset_forgets_the_previous_message() -> None:
    relay = _relay()
    relay.answer(["crank"], [0.0], [], NS)
    relay.reset()
    assert relay.answer(["crank"], [0.1], [], NS + MS).omega_from == OMEGA_FROM_NONE


def test_bad_options_are_refused_with_a_reason() -> None:
    engine = Engine("four_bar", Motion())
    with pytest.raises(ValueError, match="epsilon must be one of zero, difference; got 'finite'"):
        Relay(engine, epsilon="finite")
    with pytest.raises(ValueError, match="max_gap must be a finite number of seconds > 0"):
        Relay(engine, max_gap=0.0)
    with pytest.raises(ValueError, match="input_joint 'rocker' does not drive scene 'four_bar'.*accepted: crank"):
        Relay(engine, input_joint="rocker")


# ------------------------------------------------------------------ outgoing joint_states
def test_published_joints_are_every_scene_and_tree_joint_but_the_input() -> None:
    relay = _relay()
    assert relay.input_joint == "crank" and _relay(input_joint="").input_joint == "crank"
    assert relay.published_joints == ("coupler", "rocker", "crank_joint", "dyad_AB_joint", "dyad_CB_joint")
    frame = relay.answer(["crank"], [0.7], [2.0], NS).frame
    assert frame is not None
    names, q, dq = relay.joint_states(frame)
    assert names == relay.published_joints and len(q) == len(dq) == len(names)
    assert q[:2] == (frame.joints["coupler"].position, frame.joints["rocker"].position)
    assert dq[:2] == (frame.joints["coupler"].velocity, frame.joints["rocker"].velocity)
    assert q[2] == pytest.approx(0.7) and dq[2] == pytest.approx(2.0)  # the crank's tree joint follows φ


def test_a_spatial_scene_publishes_its_passive_joints_and_tree_joints_without_the_shaft() -> None:
    relay = _relay("spherical_converter")
    assert relay.input_joint == "shaft"
    assert "shaft" not in relay.published_joints and "cage" in relay.published_joints
    assert "converter_ring_joint" in relay.published_joints
