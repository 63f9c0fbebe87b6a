"""mechanism_node against the rclpy stand-in (tests/ros/fake_rclpy.py)."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

from linkage_ros.messages import topic_types
from linkage_ros.runtime import PARAMETERS

NS = 1_000_000_000
ROCKING_SCENE = Path(__file__).parent / "data" / "rocking_four_bar.yaml"
TOL = 1e-12


def make_node(ros: dict[str, Any], **overrides: Any) -> Any:
    Parameter = ros["rclpy.parameter"].Parameter
    node = ros["node"].MechanismNode(
        parameter_overrides=[Parameter(k, value=v) for k, v in overrides.items()]
    )
    return node


def set_param(ros: dict[str, Any], node: Any, name: str, value: Any) -> Any:
    (result,) = node.set_parameters([ros["rclpy.parameter"].Parameter(name, value=value)])
    return result


def last(node: Any, topic: str) -> Any:
    return node.publishers_by_topic[topic].published[-1]


def test_parameters_are_declared_with_descriptors(ros: dict[str, Any]) -> None:
    node = make_node(ros)
    PT = ros["rcl_interfaces.msg"].ParameterType
    kinds = {"string": PT.PARAMETER_STRING, "double": PT.PARAMETER_DOUBLE,
             "string_array": PT.PARAMETER_STRING_ARRAY}
    for spec in PARAMETERS:
        descriptor = node._descriptors[spec.name]
        assert descriptor.name == spec.name
        assert descriptor.type == kinds[spec.kind]
        assert descriptor.description
        if spec.float_range:
            (rng,) = descriptor.floating_point_range
            assert (rng.from_value, rng.to_value) == spec.float_range
    assert node._descriptors["rate_hz"].floating_point_range[0].from_value > 0
    assert node.get_parameter("points").value == ["B", "C", "E"]  # the scene's outputs


def test_publishers_cover_every_topic_with_depth_10_reliable(ros: dict[str, Any]) -> None:
    node = make_node(ros)
    assert set(node.publishers_by_topic) == {t for t, _ in topic_types(node.runtime.engine)}
    for publisher in node.publishers_by_topic.values():
        assert publisher.qos.depth == 10
        assert publisher.qos.reliability == "reliable"


def test_timer_publishes_all_topics_with_the_clock_stamp(ros: dict[str, Any]) -> None:
    node = make_node(ros, omega=2.0, phi0=0.25, rate_hz=50.0, frame_id="base")
    (timer,) = node.timers
    assert timer.period == pytest.approx(1 / 50.0)
    start = node.clock.ns
    node.fire_timer()
    node.clock.ns = start + 3 * NS // 10
    node.fire_timer()
    sec, nanosec = divmod(node.clock.ns, NS)
    for topic, publisher in node.publishers_by_topic.items():
        assert len(publisher.published) == 2, topic
        message = publisher.published[-1]
        headers = [m.header for m in message.markers] if topic == "markers" else [message.header]
        for header in headers:
            assert (header.stamp.sec, header.stamp.nanosec, header.frame_id) == (sec, nanosec, "base")
    js = last(node, "joint_states")
    drum = js.name.index("drum")
    assert js.position[drum] == pytest.approx(0.25 + 2.0 * 0.3, abs=TOL)
    assert js.velocity[drum] == pytest.approx(2.0, abs=TOL)


def test_invalid_values_are_rejected_with_a_reason_and_the_node_keeps_running(ros: dict[str, Any]) -> None:
    node = make_node(ros)
    node.fire_timer()
    bad = {
        "rate_hz": 0.0,
        "scene": "no_such_mechanism",
        "phi0": math.inf,
        "omega": math.nan,
        "epsilon": "fast",
        "on_unassemblable": "explode",
        "frame_id": "",
        "points": ["B", "nowhere"],
    }
    for name, value in bad.items():
        before = node.get_parameter(name).value
        result = set_param(ros, node, name, value)
        assert not result.successful, name
        assert result.reason, name
        assert node.get_parameter(name).value == before
    assert "unknown scene 'no_such_mechanism'" in set_param(ros, node, "scene", "no_such_mechanism").reason
    assert "phi0 must be a finite number" in set_param(ros, node, "phi0", math.inf).reason
    assert "unknown point(s) nowhere" in set_param(ros, node, "points", ["B", "nowhere"]).reason
    node.clock.ns += NS // 100
    node.fire_timer()
    assert len(node.publishers_by_topic["joint_states"].published) == 2


def test_a_phi0_that_cannot_be_assembled_is_rejected(ros: dict[str, Any]) -> None:
    node = make_node(ros, scene=str(ROCKING_SCENE))
    result = set_param(ros, node, "phi0", math.pi)
    assert not result.successful and "cannot be assembled" in result.reason


def test_an_omega_change_starts_a_new_segment_with_phi_continuous(ros: dict[str, Any]) -> None:
    node = make_node(ros, omega=1.0, phi0=0.0)
    start = node.clock.ns
    node.fire_timer()
    node.clock.ns = start + NS
    assert set_param(ros, node, "omega", -3.0).successful
    motion = node.runtime.engine.motion
    assert len(motion.segments) == 2
    assert motion.segments[-1].t0 == pytest.approx(1.0)
    assert motion.segments[-1].phi0 == pytest.approx(1.0, abs=TOL)
    node.clock.ns = start + 3 * NS // 2
    node.fire_timer()
    js = last(node, "joint_states")
    assert js.position[js.name.index("drum")] == pytest.approx(1.0 - 1.5, abs=TOL)
    assert set_param(ros, node, "epsilon", 2.0).successful
    assert motion.segments[-1].omega0 == pytest.approx(-3.0, abs=TOL)


def test_a_rate_change_restarts_the_timer(ros: dict[str, Any]) -> None:
    node = make_node(ros)
    assert set_param(ros, node, "rate_hz", 250.0).successful
    (timer,) = node.timers
    assert timer.period == pytest.approx(1 / 250.0)


def test_a_scene_change_republishes_and_the_points_follow_the_outputs(ros: dict[str, Any]) -> None:
    node = make_node(ros)
    node.fire_timer()
    assert set_param(ros, node, "scene", "four_bar").successful
    assert "points/A/position" in node.publishers_by_topic
    assert "points/C/position" not in node.publishers_by_topic
    node.clock.ns += NS // 100
    node.fire_timer()  # the followed points reach the parameter on the next tick
    assert node.get_parameter("points").value == ["A", "B"]
    assert last(node, "joint_states").name[:3] == ["crank", "coupler", "rocker"]


def test_choosing_points_changes_the_point_topics(ros: dict[str, Any]) -> None:
    node = make_node(ros)
    assert set_param(ros, node, "points", ["C"]).successful
    point_topics = sorted(t for t in node.publishers_by_topic if t.startswith("points/"))
    assert point_topics == ["points/C/acceleration", "points/C/position", "points/C/velocity"]


def test_an_unassemblable_position_is_logged_once_and_never_published_as_nan(ros: dict[str, Any]) -> None:
    node = make_node(ros, scene=str(ROCKING_SCENE), omega=1.0, rate_hz=100.0)
    start = node.clock.ns
    for k in range(300):
        node.clock.ns = start + k * NS // 100
        node.fire_timer()
    warnings = [text for level, text in node.logger.records if level == "warning"]
    assert len(warnings) == 1 and "cannot be assembled for φ in (78.58" in warnings[0]
    diagnostics = node.publishers_by_topic["diagnostics"].published
    levels = [d.status[0].level for d in diagnostics]
    S = ros["diagnostic_msgs.msg"].DiagnosticStatus
    assert levels[0] == S.OK and levels[-1] == S.ERROR
    for message in node.publishers_by_topic["joint_states"].published:
        assert all(math.isfinite(x) for x in [*message.position, *message.velocity])


def test_recording_is_plugged_in_through_the_recorder_factory(
    ros: dict[str, Any], tmp_path: Any, monkeypatch: pytest.MonkeyPatch
) -> None:
    opened: list[Any] = []

    class StubRecorder:
        def __init__(self, path: str, topics: Any) -> None:
            self.path, self.topics, self.writes, self.closed = path, list(topics), [], False
            opened.append(self)

        def write(self, stamp_ns: int, messages: Any) -> None:
            self.writes.append((stamp_ns, [t for t, _ in messages]))

        def close(self) -> None:
            self.closed = True

    monkeypatch.setattr(ros["node"], "mcap_recorder", lambda namespace: StubRecorder)
    node = make_node(ros)
    target = str(tmp_path / "run.mcap")
    assert set_param(ros, node, "record_mcap", target).successful
    node.fire_timer()
    (recorder,) = opened
    assert recorder.path == target
    assert recorder.topics == topic_types(node.runtime.engine)
    assert recorder.writes == [(node.clock.ns, [t for t, _ in recorder.topics])]
    assert set_param(ros, node, "record_mcap", "").successful
    assert recorder.closed


def test_main_spins_the_node_inside_init_and_shuts_down(ros: dict[str, Any]) -> None:
    assert ros["node"].main(args=[]) == 0
    state = ros["rclpy"].state
    assert state["shutdown"] and len(state["spun"]) == 1
    (node,) = state["spun"]
    assert node.destroyed
    assert len(node.publishers_by_topic["joint_states"].published) == 3


def test_main_reports_unusable_start_values(ros: dict[str, Any], monkeypatch: pytest.MonkeyPatch) -> None:
    node_module = ros["node"]
    original = node_module.MechanismNode

    def with_bad_scene(**kwargs: Any) -> Any:
        Parameter = ros["rclpy.parameter"].Parameter
        return original(parameter_overrides=[Parameter("scene", value="no_such_mechanism")])

    monkeypatch.setattr(node_module, "MechanismNode", with_bad_scene)
    assert node_module.main(args=[]) == 1
    (logger,) = ros["rclpy"].state["loggers"].values()
    assert "no_such_mechanism" in logger.records[-1][1]
