"""The node's logic without rclpy: parameter checks, atomic updates, the run clock, what a tick
sends (CDR bytes, diagnostics about once a second), recording."""

from __future__ import annotations

import math
import re
from pathlib import Path
from typing import Any

import pytest
from rosbags.typesys import Stores, get_typestore

from linkage_ros.messages import DIAGNOSTICS
from linkage_ros.parameters import PARAMETERS, validate_parameter
from linkage_ros.runtime import DIAGNOSTICS_PERIOD_S, Runtime

STORE = get_typestore(Stores.ROS2_JAZZY)
NS = 1_000_000_000
T0 = 1_700_000_000 * NS
TOL = 1e-12
ROCKING = Path(__file__).parent / "data" / "rocking_four_bar.yaml"


@pytest.mark.parametrize(
    ("name", "value", "reason"),
    [
        ("rate_hz", 0.0, "rate_hz must be > 0"),
        ("rate_hz", -5.0, "rate_hz must be > 0"),
        ("omega", math.nan, "omega must be a finite number"),
        ("epsilon", -math.inf, "epsilon must be a finite number"),
        ("phi0", True, "phi0 must be a finite number"),
        ("omega", 1e9, r"omega must lie in \[-10000, 10000\]"),
        ("scene", "no_such_mechanism", "unknown scene 'no_such_mechanism'"),
        ("scene", "", "scene must name a scene file"),
        ("frame_id", "", "frame_id must be non-empty"),
        ("frame_id", "has space", "frame_id must be non-empty"),
        ("on_unassemblable", "bounce", "on_unassemblable must be one of stop, reverse"),
        ("points", "B", "points must be a list of strings"),
        ("points", ["B", "1x"], "cannot be part of a topic name"),
        ("record_mcap", 3, "record_mcap must be a string"),
    ],
)
def test_invalid_parameter_values_come_with_a_reason(name: str, value: Any, reason: str) -> None:
    message = validate_parameter(name, value)
    assert message is not None
    assert re.search(reason, message), message


@pytest.mark.parametrize(
    ("name", "value"),
    [("rate_hz", 1000.0), ("omega", -3), ("scene", "four_bar"), ("frame_id", "odom"),
     ("points", []), ("on_unassemblable", "reverse"), ("record_mcap", ""), ("use_sim_time", True)],
)
def test_valid_parameter_values_pass(name: str, value: Any) -> None:
    assert validate_parameter(name, value) is None


def test_every_parameter_default_is_valid() -> None:
    for spec in PARAMETERS:
        if spec.default is not None:
            assert validate_parameter(spec.name, spec.default) is None, spec.name


def test_a_rejected_update_changes_nothing() -> None:
    runtime = Runtime({"omega": 1.0}, STORE.types)
    runtime.tick(T0)
    engine, builder, settings = runtime.engine, runtime.builder, dict(runtime.settings)
    segments = engine.motion.segments
    reason = runtime.update({"omega": 5.0, "points": ["B", "nowhere"]}, T0 + NS)
    assert reason is not None and "nowhere" in reason
    assert runtime.engine is engine and runtime.builder is builder
    assert runtime.settings == settings and engine.motion.segments == segments


def test_ticks_run_on_the_clock_from_the_first_tick() -> None:
    runtime = Runtime({"phi0": 0.5, "omega": 2.0}, STORE.types)
    assert runtime.tick(0) == []  # simulated time before the first /clock message
    runtime.tick(T0)
    runtime.tick(T0 + 5 * NS // 4)
    frame = runtime.last_frame
    assert frame is not None
    assert frame.t == 1.25 and frame.phi == pytest.approx(0.5 + 2.5, abs=TOL)


def test_a_clock_jumping_backwards_restarts_the_run() -> None:
    runtime = Runtime({"phi0": 0.5, "omega": 2.0}, STORE.types)
    runtime.tick(T0)
    runtime.tick(T0 + NS)
    runtime.tick(T0 + NS // 2)
    assert runtime.last_frame is not None and runtime.last_frame.phi == 0.5
    assert runtime.take_events() == ["clock jumped backwards: restarting the run at phi0"]


def test_unassemblable_events_are_reported_once() -> None:
    runtime = Runtime({"scene": str(ROCKING), "omega": 1.0}, STORE.types)
    events = []
    for k in range(400):
        runtime.tick(T0 + k * NS // 100)
        events += runtime.take_events()
    assert len(events) == 1 and "stopped" in events[0]


def test_the_recorder_gets_the_bytes_of_every_tick(tmp_path: Path) -> None:
    written: list[tuple[int, list[tuple[str, bytes]]]] = []
    closed: list[bool] = []

    class Stub:
        def __init__(self, path: str, topics: Any, *, engine: Any, frame_id: str) -> None:
            self.topics = list(topics)
            assert engine.scene.name == "harvester_finger" and frame_id == "world"

        def write_serialized(self, stamp_ns: int, messages: Any) -> None:
            written.append((stamp_ns, list(messages)))

        def close(self) -> None:
            closed.append(True)

    runtime = Runtime({"record_mcap": str(tmp_path / "a.mcap")}, STORE.types, recorder_factory=Stub)
    first = runtime.tick(T0)
    second = runtime.tick(T0 + NS // 100)
    assert [s for s, _ in written] == [T0, T0 + NS // 100]
    assert [t for t, _ in first] == [t for t, _ in runtime.topics]
    assert written[0][1] == first and written[1][1] == second  # what is sent is what is recorded
    runtime.close()
    assert closed == [True]


def test_a_tick_is_cdr_bytes_that_decode_to_the_frame() -> None:
    runtime = Runtime({"scene": "four_bar", "omega": 2.0, "frame_id": "base"}, STORE.types)
    runtime.tick(T0)
    messages = dict(runtime.tick(T0 + NS // 4))
    frame = runtime.last_frame
    assert frame is not None
    js = STORE.deserialize_cdr(messages["joint_states"], "sensor_msgs/msg/JointState")
    assert (js.header.stamp.sec, js.header.stamp.nanosec, js.header.frame_id) == (1_700_000_000, NS // 4, "base")
    assert js.position[js.name.index("crank")] == frame.phi == pytest.approx(0.5, abs=TOL)
    b = STORE.deserialize_cdr(messages["points/B/velocity"], "geometry_msgs/msg/Vector3Stamped")
    assert (b.vector.x, b.vector.y) == tuple(frame.points["B"].velocity)


def test_diagnostics_go_out_about_once_a_second_and_on_a_change_of_status() -> None:
    runtime = Runtime({"scene": str(ROCKING), "omega": 1.0, "rate_hz": 100.0}, STORE.types)
    sent = []
    for k in range(400):
        messages = dict(runtime.tick(T0 + k * NS // 100))
        if DIAGNOSTICS in messages:
            sent.append(k)
    frames_status_change = 1  # the stop at the unassemblable interval
    assert sent[0] == 0 and len(sent) <= 400 / 100 / DIAGNOSTICS_PERIOD_S + 1 + frames_status_change
    assert all(b - a <= 100 for a, b in zip(sent, sent[1:]))
    last = STORE.deserialize_cdr(runtime.tick(T0 + 500 * NS // 100)[-1][1], "diagnostic_msgs/msg/DiagnosticArray")
    assert last.status[0].level == b"\x02"[0] and "stopped" in last.status[0].message


def test_recording_into_a_missing_directory_is_refused_with_a_reason(tmp_path: Path) -> None:
    def factory(path: str, topics: Any, **kwargs: Any) -> Any:
        raise AssertionError("the recorder must not be opened")

    runtime = Runtime({}, STORE.types, recorder_factory=factory)
    target = tmp_path / "missing" / "a.mcap"
    reason = runtime.update({"record_mcap": str(target)}, T0)
    assert reason is not None and "does not exist" in reason and str(target.parent) in reason
    assert not target.parent.exists()
    with pytest.raises(ValueError, match="does not exist"):
        Runtime({"record_mcap": str(target)}, STORE.types, recorder_factory=factory)


def test_recording_without_a_recorder_is_refused_with_a_reason(tmp_path: Path) -> None:
    runtime = Runtime({}, STORE.types)
    reason = runtime.update({"record_mcap": str(tmp_path / "a.mcap")}, T0)
    assert reason is not None and "no MCAP recorder" in reason
    assert runtime.settings["record_mcap"] == ""


def test_topic_mode_answers_a_joint_state_under_its_stamp_without_the_input_joint() -> None:
    runtime = Runtime({"scene": "four_bar", "input_source": "topic"}, STORE.types)
    assert runtime.topic_mode and runtime.tick(T0) == []  # no clock ticks in topic mode
    messages = dict(runtime.answer(["crank"], [0.7], [2.5], T0 + 123))
    assert set(messages) == {t for t, _ in runtime.topics}
    js = STORE.deserialize_cdr(messages["joint_states"], "sensor_msgs/msg/JointState")
    assert "crank" not in js.name and (js.header.stamp.sec, js.header.stamp.nanosec) == (1_700_000_000, 123)
    jk = STORE.deserialize_cdr(messages["joint_kinematics"], "trajectory_msgs/msg/JointTrajectory")
    assert jk.joint_names[0] == "crank" and jk.points[0].positions[0] == 0.7
    dropped = runtime.answer(["elbow"], [0.7], [2.5], T0 + 456)  # diagnostics WARN only
    assert [t for t, _ in dropped] == [DIAGNOSTICS]
    status = STORE.deserialize_cdr(dict(dropped)[DIAGNOSTICS], "diagnostic_msgs/msg/DiagnosticArray").status[0]
    assert status.level == 1 and status.message == (
        "JointState dropped: no joint 'crank' in the message (it carries: elbow)")
    assert runtime.take_input_warnings() == ["JointState dropped: no joint 'crank' in the message (it carries: elbow)"]


def test_topic_mode_reports_an_unassemblable_input_in_diagnostics_only() -> None:
    runtime = Runtime({"scene": str(ROCKING), "input_source": "topic"}, STORE.types)
    messages = runtime.answer(["crank"], [math.pi], [1.0], T0)
    assert [t for t, _ in messages] == [DIAGNOSTICS]
    (status,) = STORE.deserialize_cdr(messages[0][1], "diagnostic_msgs/msg/DiagnosticArray").status
    assert status.level == 2 and "cannot be assembled for φ in (" in status.message
    (warning,) = runtime.take_input_warnings()
    assert "cannot be assembled" in warning


def test_switching_back_to_the_clock_restarts_the_run_at_phi0() -> None:
    runtime = Runtime({"scene": "four_bar", "phi0": 0.25, "omega": 1.0}, STORE.types)
    runtime.tick(T0)
    runtime.tick(T0 + NS)
    assert runtime.update({"input_source": "topic"}, T0 + NS) is None
    assert runtime.tick(T0 + 2 * NS) == [] and runtime.answer(["crank"], [1.0], [0.0], T0 + 2 * NS)
    assert runtime.update({"input_source": "clock"}, T0 + 3 * NS) is None
    runtime.tick(T0 + 4 * NS)
    assert runtime.last_frame is not None and runtime.last_frame.phi == 0.25
    reason = runtime.update({"input_source": "topic", "input_joint": "elbow"}, T0 + 5 * NS)
    assert reason is not None and "elbow" in reason and not runtime.topic_mode
