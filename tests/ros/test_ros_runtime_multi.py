"""The node's logic for scenes with several inputs (issue 14), without rclpy: the per-input
parameters (input_omegas, input_epsilons, input_phi0s), the ticks of the five-bar, topic mode
reading every input from one JointState."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import pytest
from rosbags.typesys import Stores, get_typestore

import solver
from linkage_ros.messages import DIAGNOSTICS
from linkage_ros.parameters import per_input, per_input_reason, validate_parameter
from linkage_ros.runtime import Runtime

STORE = get_typestore(Stores.ROS2_JAZZY)
NS = 1_000_000_000
T0 = 1_700_000_000 * NS
MS = 1_000_000
SCENES = Path(__file__).resolve().parents[2] / "config" / "scenes"


def _runtime(**values: Any) -> Runtime:
    return Runtime({"scene": "five_bar", **values}, STORE.types, serialize=STORE.serialize_cdr)


def _decode(messages: list[tuple[str, bytes]], topic: str) -> Any:
    typename = {"joint_states": "sensor_msgs/msg/JointState", DIAGNOSTICS: "diagnostic_msgs/msg/DiagnosticArray",
                "joint_kinematics": "trajectory_msgs/msg/JointTrajectory"}[topic]
    return STORE.deserialize_cdr(dict(messages)[topic], typename)


@pytest.mark.parametrize(
    ("name", "value", "reason"),
    [
        ("input_omegas", "1,2", "input_omegas must be a list of numbers"),
        ("input_omegas", [1.0, math.nan], "input_omegas must hold finite numbers"),
        ("input_epsilons", [0.0, True], "input_epsilons must hold finite numbers"),
        ("input_omegas", [1.0, 2e4], r"input_omegas: every value must lie in \[-10000, 10000\]"),
        ("input_phi0s", [math.inf], "input_phi0s must hold finite numbers"),
    ],
)
def test_invalid_per_input_values_come_with_a_reason(name: str, value: Any, reason: str) -> None:
    message = validate_parameter(name, value)
    assert message is not None and re.search(reason, message), message


def test_a_wrong_number_of_per_input_values_is_refused_naming_the_inputs() -> None:
    with pytest.raises(ValueError, match=r"input_omegas needs 2 value\(s\), one per input of the scene "
                                         r"\(q1, q2\), or none \(omega for every input\); got 3"):
        _runtime(input_omegas=[1.0, 2.0, 3.0])
    assert per_input_reason({"input_phi0s": (1.0,)}, ("crank",)) is None
    assert per_input({"omega": 2.0, "input_omegas": ()}, "omega", ("q1", "q2")) == (2.0, 2.0)
    assert per_input({"omega": 2.0, "input_omegas": ()}, "omega", ("crank",)) == 2.0


def test_each_input_runs_its_own_law_and_the_frame_equals_the_solver() -> None:
    runtime = _runtime(input_omegas=[1.0, -2.0], input_epsilons=[0.5, 0.0], input_phi0s=[1.7, 1.3])
    runtime.tick(T0)
    messages = runtime.tick(T0 + 100 * MS)
    frame = runtime.last_frame
    assert frame is not None
    assert frame.phi == pytest.approx((1.7 + 0.1 + 0.25 * 0.01, 1.3 - 0.2), abs=1e-15)
    assert frame.omega == pytest.approx((1.05, -2.0), abs=1e-15) and frame.epsilon == (0.5, 0.0)
    k = solver.load_scene("five_bar").solve(frame.phi, omega=frame.omega, epsilon=frame.epsilon)
    assert frame.points["P"].position == pytest.approx(tuple(k.point("P").position), abs=1e-15)
    js = _decode(messages, "joint_states")
    assert [js.position[list(js.name).index(n)] for n in ("q1", "q2")] == list(frame.phi)
    # every per-tick topic comes from a byte template, checked against the builder
    assert set(runtime.wire.template_topics) == {t for t, _ in runtime.topics if t != DIAGNOSTICS}


def test_diagnostics_carry_each_inputs_phi_omega_and_epsilon() -> None:
    runtime = _runtime(input_omegas=[1.0, -2.0], input_phi0s=[1.7, 1.3])
    (status,) = _decode(runtime.tick(T0), DIAGNOSTICS).status
    values = {kv.key: kv.value for kv in status.values}
    assert [values[f"phi/{n}"] for n in ("q1", "q2")] == ["1.7", "1.3"]
    assert [values[f"omega/{n}"] for n in ("q1", "q2")] == ["1.0", "-2.0"]
    assert [values[f"epsilon/{n}"] for n in ("q1", "q2")] == ["0.0", "0.0"]
    assert "phi" not in values


def test_per_input_changes_start_new_segments_and_a_wrong_length_changes_nothing() -> None:
    runtime = _runtime(input_phi0s=[1.5, 1.2])
    runtime.tick(T0)
    assert runtime.update({"input_omegas": [3.0, -1.0]}, T0 + 100 * MS) is None
    runtime.tick(T0 + 200 * MS)
    frame = runtime.last_frame
    assert frame is not None and frame.omega == (3.0, -1.0)
    assert frame.phi == pytest.approx((1.6 + 0.3, 1.3 - 0.1), abs=1e-14)  # φ continuous at 0.1 s
    reason = runtime.update({"input_epsilons": [1.0]}, T0 + 200 * MS)
    assert reason is not None and "(q1, q2)" in reason
    assert runtime.update({"input_epsilons": [0.0, 2.0]}, T0 + 200 * MS) is None
    runtime.tick(T0 + 300 * MS)
    assert runtime.last_frame is not None and runtime.last_frame.omega == pytest.approx((3.0, -0.8))
    assert runtime.update({"input_phi0s": [1.0, 2.0]}, T0 + 300 * MS) is None  # restarts there
    runtime.tick(T0 + 300 * MS)
    assert runtime.last_frame is not None and runtime.last_frame.phi == (1.0, 2.0)
    # a scene with one input: the two-value arrays no longer fit, unless changed with it
    reason = runtime.update({"scene": "four_bar"}, T0 + 400 * MS)
    assert reason is not None and "one per input of the scene (crank)" in reason
    assert runtime.update({"scene": "four_bar", "input_phi0s": [], "input_omegas": [],
                           "input_epsilons": []}, T0 + 400 * MS) is None


def test_a_single_input_scene_takes_one_value_arrays_and_is_unchanged_without_them() -> None:
    plain = Runtime({"scene": "four_bar", "omega": 2.0}, STORE.types, serialize=STORE.serialize_cdr)
    same = Runtime({"scene": "four_bar", "omega": 2.0, "input_omegas": []}, STORE.types,
                   serialize=STORE.serialize_cdr)
    assert plain.tick(T0 + 5 * MS) == same.tick(T0 + 5 * MS)
    assert plain.tick(T0 + 15 * MS) == same.tick(T0 + 15 * MS)
    one = Runtime({"scene": "four_bar", "omega": 2.0, "input_omegas": [0.5]}, STORE.types,
                  serialize=STORE.serialize_cdr)
    one.tick(T0)
    assert one.last_frame is not None and one.last_frame.omega == 0.5


def test_topic_mode_reads_every_input_and_leaves_them_out_of_joint_states(tmp_path: Path) -> None:
    runtime = _runtime(input_source="topic")
    assert runtime.tick(T0) == []
    messages = runtime.answer(["q2", "q1"], [1.2, 1.6], [0.5, -0.5], T0)
    js = _decode(messages, "joint_states")
    assert not {"q1", "q2"} & set(js.name) and {"left_distal", "right_distal"} <= set(js.name)
    jk = _decode(messages, "joint_kinematics")
    assert list(jk.points[0].positions[:2]) == [1.6, 1.2]  # joint_kinematics keeps every joint
    assert [t for t, _ in runtime.answer(["q1"], [1.6], [0.5], T0 + NS)] == ["diagnostics"]  # WARN
    assert runtime.take_input_warnings() == [
        "JointState dropped: no joint 'q2' in the message (every input is needed: q1, q2)"
    ]
    # unassemblable: diagnostics ERROR naming the group and the sample, nothing else
    short = (SCENES / "five_bar.yaml").read_text().replace("lengths: [0.25, 0.25]", "lengths: [0.12, 0.12]")
    (tmp_path / "short.yaml").write_text(short)
    assert runtime.update({"scene": str(tmp_path / "short.yaml"), "input_phi0s": [1.5, 1.6]}, T0) is None
    messages = runtime.answer(["q1", "q2"], [math.pi, 0.0], [1.0, 1.0], T0 + 2 * NS)
    assert [t for t, _ in messages] == [DIAGNOSTICS]
    (status,) = _decode(messages, DIAGNOSTICS).status
    assert status.level == 2 and "group 'distal' cannot be assembled at (q1, q2) = (3.14159, 0) rad" in (
        status.message
    )
    values = {kv.key: kv.value for kv in status.values}
    assert float(values["phi/q1"]) == math.pi and float(values["phi/q2"]) == 0.0
    assert runtime.update({"input_joint": "q1"}, T0) is not None
