"""mechanism_node as its own process, over DDS: what a ROS user tripped on (issue 19).

Remapped topics are recorded under the names on the wire; the recording's start and end are
logged with the file name; every rejected parameter change is logged, also those rclpy's own
range checks reject; the relay's ε rule and gap are parameters; an accepted set resumes an
input stopped where the mechanism cannot be assembled; a scene that is a directory, and the
five-bar's singular corner, are refused in one line saying so.
"""

from __future__ import annotations

import math
import signal
from pathlib import Path
from typing import Any

import pytest
from conftest import Client, NodeProcess, decode

from linkage_ros.messages import topic_types

pytestmark = pytest.mark.dds

ROOT = Path(__file__).resolve().parents[2]
DOUBLE_ROCKER = ROOT / "config" / "scenes" / "hard" / "double_rocker.yaml"
WAIT_S = 20.0
TYPES = dict(topic_types(["A", "B"]))


def wait_for(client: Client, listener: Any, topic: str, count: int, process: NodeProcess) -> None:
    start = len(listener.by_topic[topic])
    assert client.spin_until(lambda: len(listener.by_topic[topic]) >= start + count, WAIT_S), (
        f"fewer than {count} messages on {topic}:\n" + process.output())


def logged(client: Client, process: NodeProcess, text: str) -> bool:
    """Whether the node's output shows ``text`` within a few seconds."""
    return client.spin_until(lambda: text in process.output(), 5.0)


def test_a_remapped_topic_is_recorded_under_its_wire_name_and_the_recording_is_logged(
    start_node: Any, client: Client, tmp_path: Path
) -> None:
    from linkage_ros.record.mcap import read_mcap
    from linkage_ros.record.replay import run_data_from_mcap

    target = tmp_path / "remapped.mcap"
    listener = client.listen({"/robot/joint_states": TYPES["joint_states"],
                              "/remap/points/B/position": TYPES["points/B/position"]})
    process = start_node("-r", "__ns:=/remap", "-r", "joint_states:=/robot/joint_states",
                         "-p", "scene:=four_bar", "-p", f"record_mcap:={target}")
    wait_for(client, listener, "/robot/joint_states", 10, process)

    def wire() -> set[str]:
        found = client.published_by("mechanism_node", "/remap")
        return {name for name, _ in found} - {"/rosout", "/parameter_events"}

    assert client.spin_until(lambda: len(wire()) >= len(TYPES), WAIT_S), wire()
    on_wire = wire()
    assert process.stop(signal.SIGINT) == 0
    output = process.output()
    assert f"recording to {target}" in output and f"recording finished: {target} (" in output, output
    recorded = set(read_mcap(target).topics())
    assert "/robot/joint_states" in recorded and "/remap/joint_states" not in recorded
    assert recorded == on_wire
    data, _ = run_data_from_mcap(target)
    assert data.n >= 10 and "rocker" in data.joints and data.t[0] == 0.0


def test_every_rejected_change_is_logged_and_the_relay_settings_are_parameters(
    start_node: Any, client: Client
) -> None:
    from rcl_interfaces.srv import DescribeParameters

    listener = client.listen({"/params/joint_states": TYPES["joint_states"]})
    process = start_node("-r", "__ns:=/params", "-p", "scene:=four_bar")
    node = "/params/mechanism_node"
    try:
        wait_for(client, listener, "/params/joint_states", 3, process)
        (by_rclpy,) = client.set_parameters(node, rate_hz=-1.0)  # the descriptor's range
        assert not by_rclpy.successful
        (by_us,) = client.set_parameters(node, scene="no_such_mechanism")
        assert not by_us.successful
        (gap,) = client.set_parameters(node, topic_max_gap=100.0)
        assert not gap.successful
        (rule,) = client.set_parameters(node, topic_epsilon="central")
        assert not rule.successful and "topic_epsilon must be one of zero, difference" in rule.reason
        assert all(r.successful for r in client.set_parameters(node, topic_epsilon="difference", topic_max_gap=0.5))
        assert [v for _, v in client.get_parameters(node, "topic_epsilon", "topic_max_gap")] == ["difference", 0.5]
        described = client.call(DescribeParameters, f"{node}/describe_parameters",
                                 DescribeParameters.Request(names=["topic_max_gap", "topic_epsilon"]))
        gap_descriptor, rule_descriptor = described.descriptors
        (limits,) = gap_descriptor.floating_point_range
        assert (limits.from_value, limits.to_value) == (0.001, 60.0) and gap_descriptor.description
        assert "difference" in rule_descriptor.description
        assert all(r.successful for r in client.set_parameters(node, scene="slider_crank"))
        for text in ("parameter change rejected (rate_hz): ", "parameter change rejected (scene): unknown scene",
                     "parameter change rejected (topic_max_gap): ", "parameter change rejected (topic_epsilon): ",
                     "scene slider_crank: publishing "):
            assert logged(client, process, text), f"not logged: {text}\n" + process.output()
    finally:
        assert process.stop(signal.SIGTERM) == 0


def test_setting_reverse_while_stopped_resumes_the_input(start_node: Any, client: Client) -> None:
    """Stopped at the double rocker's gap, an accepted set of on_unassemblable (no new omega)
    resumes the drive: it runs into the gap again and reverses."""
    topics = {f"/resume/{t}": TYPES[t] for t in ("joint_states", "diagnostics")}
    listener = client.listen(topics)
    process = start_node("-r", "__ns:=/resume", "-p", f"scene:={DOUBLE_ROCKER}", "-p", "omega:=5.0")
    try:
        def error_seen(text: str) -> bool:
            return any(s.level == b"\x02" and text in s.message
                       for d in listener.by_topic["/resume/diagnostics"]
                       for s in decode(d, TYPES["diagnostics"]).status)

        assert client.spin_until(lambda: error_seen("stopped"), WAIT_S), process.output()
        (ok,) = client.set_parameters("/resume/mechanism_node", on_unassemblable="reverse")
        assert ok.successful
        assert client.spin_until(lambda: error_seen("reversed"), WAIT_S), process.output()
        wait_for(client, listener, "/resume/joint_states", 10, process)
        assert client.spin_until_latest(listener, "/resume/joint_states", TYPES["joint_states"],
                                        lambda js: js.velocity[0] == pytest.approx(-5.0), WAIT_S), process.output()
    finally:
        assert process.stop(signal.SIGTERM) == 0


@pytest.mark.parametrize(
    ("args", "reason"),
    [
        (("-p", "scene:={tmp}"), "cannot start: scene '{tmp}': is a directory, not a scene file"),
        (("-p", "scene:=five_bar", "-p", f"input_phi0s:=[{math.pi!r}, 0.0]"),
         "cannot start: group 'distal' is at a singular position (conditioning 0) at 1 sample(s) of "
         "(q1, q2) = (180.0000°, 0.0000°)"),
    ],
)
def test_a_directory_scene_and_the_five_bar_corner_are_refused_in_one_line(
    start_node: Any, tmp_path: Path, args: tuple[str, ...], reason: str
) -> None:
    process = start_node("-r", "__ns:=/refused", *(a.format(tmp=tmp_path) for a in args))
    code = process.wait()
    output = process.output()
    lines = [line for line in output.splitlines() if "cannot start:" in line]
    assert code == 1 and len(lines) == 1 and reason.format(tmp=tmp_path) in lines[0], output
    assert "Traceback" not in output
