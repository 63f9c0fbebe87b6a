"""linkage_ros.relay with several inputs (issue 14): every input joint read from one JointState.

The five-bar's (q1, q2) from one message: frames against the solver (P, and its velocity J·ω),
dropped messages naming the missing inputs, ω and ε input by input, the unassemblable region
named by the group and the failing sample, and joint_states without any input joint.
"""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import solver
from linkage_ros.engine import Engine
from linkage_ros.motion import Motions
from linkage_ros.relay import (
    ANSWER_DROPPED,
    ANSWER_FRAME,
    ANSWER_IGNORED,
    ANSWER_UNASSEMBLABLE,
    EPSILON_FROM_VELOCITIES,
    OMEGA_FROM_MESSAGE,
    OMEGA_FROM_NONE,
    OMEGA_FROM_POSITIONS,
    Relay,
)

SCENES = Path(__file__).resolve().parents[2] / "config" / "scenes"
#: P against the solver, m; velocities against J·ω, relative (issue 14, item 4).
TOL_POS = 1e-12
TOL_REL = 1e-9
NS = 1_000_000_000
MS = 1_000_000
INPUTS = ["q1", "q2"]


def _relay(scene: object = "five_bar", **options: object) -> Relay:
    engine = Engine(scene, Motions.of(2, phi0=(math.pi / 2, math.pi / 2)))
    return Relay(engine, **options)  # type: ignore[arg-type]


@pytest.fixture
def short_five_bar(tmp_path: Path) -> Path:
    """The five-bar with distal links of 0.12 m: it cannot close where |A1A2| > 0.24 m."""
    text = (SCENES / "five_bar.yaml").read_text().replace("lengths: [0.25, 0.25]", "lengths: [0.12, 0.12]")
    path = tmp_path / "short_five_bar.yaml"
    path.write_text(text.replace("scene: five_bar", "scene: short_five_bar"))
    return path


def test_every_input_is_read_from_one_message_and_p_equals_the_solver_with_v_equal_j_omega() -> None:
    relay = _relay()
    scene = solver.load_scene("five_bar")
    rng = np.random.default_rng(4)
    q = np.radians(rng.uniform(40.0, 140.0, size=(20, 2)))
    w = rng.uniform(-3.0, 3.0, size=(20, 2))
    k = scene.solve(q, omega=w, epsilon=0.0)
    jac = np.asarray(k.point("P").jacobian)
    for n in range(len(q)):
        stamp = 1_700_000_000 * NS + n * 10 * MS
        answer = relay.answer(INPUTS, [float(x) for x in q[n]], [float(x) for x in w[n]], stamp)
        assert answer.kind == ANSWER_FRAME, answer.reason
        assert answer.omega_from == OMEGA_FROM_MESSAGE and answer.interval is None
        frame = answer.frame
        assert frame is not None and frame.t == stamp / NS
        assert frame.phi == answer.phi == tuple(q[n]) and frame.omega == tuple(w[n])
        p = frame.points["P"]
        assert np.abs(np.subtract(p.position, np.asarray(k.point("P").position)[n])).max() <= TOL_POS
        expected = jac[n] @ w[n]
        assert np.abs(np.subtract(p.velocity, expected)).max() <= TOL_REL * np.abs(expected).max()
        assert frame.joints["q1"].position == q[n, 0] and frame.joints["q2"].velocity == w[n, 1]


def test_the_inputs_are_found_among_other_joints_in_any_order() -> None:
    answer = _relay().answer(["wrist", "q2", "gripper", "q1"], [9.0, 1.2, -1.0, 1.7], [1.0, 2.0, 3.0, 4.0], NS)
    assert answer.kind == ANSWER_FRAME and answer.phi == (1.7, 1.2) and answer.omega == (4.0, 2.0)


@pytest.mark.parametrize(
    ("names", "positions", "velocities", "match"),
    [
        (["q1"], [1.2], [1.0], r"no joint 'q2' in the message \(every input is needed: q1, q2\)"),
        (["wheel"], [0.1], [1.0], "no joint 'q1', 'q2' in the message"),
        ([], [], [], "no joint 'q1', 'q2' in the message"),
        (["q1", "q2"], [1.2, math.nan], [1.0, 1.0], "joint 'q2' position is nan"),
        (["q1", "q2"], [math.inf, 1.2], [], "joint 'q1' position is inf"),
        (["q1", "q2"], [1.2, 1.3], [1.0, -math.inf], "joint 'q2' velocity is -inf"),
        (["q1", "q2"], [1.2], [], r"joint 'q2' has no position \(2 names, 1 positions\)"),
        (["q1", "q2"], [1.2, 1.3], [1.0], r"joint 'q2' has no velocity \(2 names, 1 velocities\)"),
    ],
)
def test_a_message_without_every_usable_input_is_dropped_naming_the_missing_ones(
    names: list[str], positions: list[float], velocities: list[float], match: str
) -> None:
    answer = _relay().answer(names, positions, velocities, NS)
    assert answer.kind == ANSWER_DROPPED and answer.frame is None and answer.phi is None
    assert re.search(match, answer.reason), answer.reason


def test_joint_states_in_topic_mode_leave_out_every_input_and_come_back_ignored() -> None:
    relay = _relay()
    assert relay.input_joints == ("q1", "q2")
    assert not {"q1", "q2"} & set(relay.published_joints)
    assert {"left_distal", "right_distal"} <= set(relay.published_joints)
    frame = relay.answer(INPUTS, [1.6, 1.4], [1.0, 2.0], NS).frame
    assert frame is not None
    names, q, dq = relay.joint_states(frame)
    assert names == relay.published_joints and len(q) == len(dq) == len(names)
    assert all(math.isfinite(x) for x in (*q, *dq))
    assert relay.answer(list(names), list(q), list(dq), 2 * NS).kind == ANSWER_IGNORED


def test_omega_without_velocities_is_the_wrapped_difference_of_each_input() -> None:
    relay = _relay()
    first = relay.answer(INPUTS, [1.0, math.pi - 0.01], [], NS)
    assert first.omega_from == OMEGA_FROM_NONE and first.omega == (0.0, 0.0)
    second = relay.answer(INPUTS, [1.02, -math.pi + 0.01], [], NS + 10 * MS)
    assert second.omega_from == OMEGA_FROM_POSITIONS
    assert second.omega == pytest.approx((2.0, 2.0), rel=1e-9)  # q2 wrapped across ±π


def test_epsilon_difference_works_input_by_input() -> None:
    relay = _relay(epsilon="difference")
    relay.answer(INPUTS, [1.5, 1.5], [1.0, -2.0], NS)
    answer = relay.answer(INPUTS, [1.51, 1.48], [1.5, -1.0], NS + 20 * MS)
    assert answer.epsilon_from == EPSILON_FROM_VELOCITIES
    assert answer.epsilon == pytest.approx((25.0, 50.0), rel=1e-12)
    assert answer.frame is not None and answer.frame.epsilon == answer.epsilon
    relay.reset()
    assert relay.answer(INPUTS, [1.5, 1.5], [1.0, 1.0], 2 * NS).epsilon == (0.0, 0.0)


def test_an_unassemblable_sample_names_the_group_and_the_sample_and_the_next_is_answered(
    short_five_bar: Path,
) -> None:
    relay = _relay(short_five_bar)
    bad = relay.answer(INPUTS, [math.pi, 0.0], [1.0, 1.0], NS)
    assert bad.kind == ANSWER_UNASSEMBLABLE and bad.frame is None and bad.interval is None
    assert "group 'distal' cannot be assembled at (q1, q2) = (3.14159, 0) rad" in bad.reason
    assert bad.phi == (math.pi, 0.0)
    good = relay.answer(INPUTS, [math.pi / 2, math.pi / 2], [1.0, 1.0], NS + 10 * MS)
    assert good.kind == ANSWER_FRAME and good.frame is not None


_FIVE_BAR = _relay()
_CORNER = (math.pi, 0.0)  # distal links stretched: the singular corner
_COINCIDENT = (math.acos(2.0 / 3.0), math.pi - math.acos(2.0 / 3.0))  # A1 = A2


@settings(max_examples=80, deadline=None)
@given(
    q=st.one_of(
        st.tuples(st.floats(-7.0, 7.0), st.floats(-7.0, 7.0)),
        st.sampled_from([_CORNER, _COINCIDENT]),
    ),
    w=st.tuples(st.floats(-50.0, 50.0), st.floats(-50.0, 50.0)),
)
def test_a_five_bar_frame_never_holds_a_non_finite_number(q: tuple[float, float], w: tuple[float, float]) -> None:
    answer = _FIVE_BAR.answer(INPUTS, list(q), list(w), NS)
    assert answer.kind in (ANSWER_FRAME, ANSWER_UNASSEMBLABLE)
    if answer.frame is None:
        assert "at (q1, q2) = (" in answer.reason
        return
    frame = answer.frame
    for ps in frame.points.values():
        assert all(math.isfinite(x) for x in (*ps.position, *ps.velocity, *ps.acceleration))
    for js in frame.joints.values():
        assert all(math.isfinite(x) for x in js)
    _, positions, velocities = _FIVE_BAR.joint_states(frame)
    assert all(math.isfinite(x) for x in (*positions, *velocities))


def test_input_joint_is_refused_for_a_scene_with_several_inputs() -> None:
    with pytest.raises(ValueError, match=r"scene 'five_bar' has 2 inputs \(q1, q2\).*leave input_joint empty"):
        _relay(input_joint="q1")
    assert _relay(input_joint="").input_joints == ("q1", "q2")
