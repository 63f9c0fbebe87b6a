"""Topic mode over DDS with the URDF's names for the cylinders (issue 30, must fix 2): the
excavator node answers a JointState naming ``boom_cylinder_rod_joint``, ``arm_cylinder_rod_joint``,
``bucket_cylinder_rod_joint`` (what a ros2_control driver of ``linkage-urdf excavator`` publishes)
under its stamp, leaving those joints out of joint_states; a message without the inputs gets one
warning and diagnostics WARN, and a second kind of warning is not hidden by the first one's
throttle; ``input_joints`` maps the inputs at run time (a wrong name rejected with the reason);
``mechanism_node --help`` prints its usage and starts no node."""

from __future__ import annotations

import math
import signal
import subprocess
from typing import Any

import pytest
from conftest import Client, decode, node_executable, stamp_of

pytestmark = pytest.mark.dds

WAIT_S = 30.0
NODE = "/exc/mechanism_node"
STROKES = ["boom_stroke", "arm_stroke", "bucket_stroke"]
RODS = ["boom_cylinder_rod_joint", "arm_cylinder_rod_joint", "bucket_cylinder_rod_joint"]
AT = [1.2, 1.5, 1.1]


def test_help_prints_the_usage_and_starts_no_node() -> None:
    done = subprocess.run([node_executable(), "--help"], capture_output=True, text=True, timeout=60)
    assert done.returncode == 0 and done.stdout.startswith("usage: mechanism_node")
    assert "input_joints" in done.stdout and "publishing" not in done.stdout + done.stderr


@pytest.fixture(scope="module")
def excavator(start_node: Any, client: Client, tmp_path_factory: pytest.TempPathFactory) -> Any:
    from sensor_msgs.msg import JointState

    recording = tmp_path_factory.mktemp("exc") / "topic.mcap"
    listener = client.listen({"/exc/joint_states": "sensor_msgs/msg/JointState",
                              "/exc/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"})
    process = start_node("-r", "__ns:=/exc", "-p", "scene:=excavator", "-p", "input_source:=topic",
                         "-p", f"record_mcap:={recording}")
    publisher = client.node.create_publisher(JointState, "/exc/input_joint_states", 10)
    if not client.spin_until(lambda: publisher.get_subscription_count() > 0 and "publishing" in process.output(),
                             WAIT_S):
        process.kill()
        pytest.fail("mechanism_node in topic mode did not come up:\n" + process.output())
    yield process, listener, publisher, recording
    process.stop()


def send(client: Client, publisher: Any, names: list[str], positions: list[float], stamp_s: int) -> None:
    from sensor_msgs.msg import JointState

    message = JointState(name=names, position=positions, velocity=[0.0] * len(names))
    message.header.stamp.sec = stamp_s
    publisher.publish(message)
    client.spin_for(0.2)


def send_until_answered(client: Client, publisher: Any, listener: Any, names: list[str], positions: list[float],
                        stamp_s: int) -> list[Any]:
    """Send until an answer under ``stamp_s`` arrives (a best-effort reader may miss the first
    message right after discovery, on a loaded machine); the answers."""
    for _ in range(int(WAIT_S / 0.5)):
        send(client, publisher, names, positions, stamp_s)
        if client.spin_until(lambda: bool(answers(listener, stamp_s)), 0.3):
            return answers(listener, stamp_s)
    return []


def answers(listener: Any, stamp_s: int) -> list[Any]:
    return [decode(d, "sensor_msgs/msg/JointState") for d in listener.by_topic["/exc/joint_states"]
            if stamp_of(d) == stamp_s * 1_000_000_000]


def test_a_joint_state_of_the_urdf_rod_joints_is_answered(excavator: Any, client: Client) -> None:
    _, listener, publisher, _ = excavator
    js = send_until_answered(client, publisher, listener, RODS, AT, 100)[0]
    assert not set(RODS) & set(js.name)
    assert [js.position[list(js.name).index(n)] for n in STROKES] == AT
    js = send_until_answered(client, publisher, listener, STROKES, AT, 101)[0]  # the scene's names: rods published
    assert not set(STROKES) & set(js.name)
    assert [js.position[list(js.name).index(n)] for n in RODS] == pytest.approx(AT, abs=1e-15)


def test_messages_without_the_inputs_warn_once_per_kind_and_in_diagnostics(excavator: Any, client: Client) -> None:
    process, listener, publisher, _ = excavator
    for k in range(3):  # within a second: one line
        send(client, publisher, ["swing_joint"], [0.1], 200 + k)
    send(client, publisher, RODS, [math.nan, 1.5, 1.1], 210)  # another kind: not hidden by the first's throttle
    assert client.spin_until(lambda: "position is nan" in process.output(), WAIT_S), process.output()
    lines = process.output().splitlines()
    assert len([line for line in lines if "no joint 'boom_stroke' or 'boom_cylinder_rod_joint'" in line]) == 1
    assert len([line for line in lines if "'boom_cylinder_rod_joint' position is nan" in line]) == 1
    warn = [decode(d, "diagnostic_msgs/msg/DiagnosticArray").status[0] for d in listener.by_topic["/exc/diagnostics"]
            if stamp_of(d) in (200 * 1_000_000_000, 201 * 1_000_000_000, 202 * 1_000_000_000)]
    assert warn and warn[0].level in (1, b"\x01")  # WARN (stamps a second apart: one each)
    assert warn[0].message.startswith("JointState dropped: no joint")
    assert {kv.key: kv.value for kv in warn[0].values}["status"] == "input_dropped"


def test_input_joints_is_set_at_run_time_and_a_wrong_name_is_rejected(excavator: Any, client: Client) -> None:
    _, listener, publisher, _ = excavator
    (bad,) = client.set_parameters(NODE, input_joints=["", "", "bucket_joint"])
    assert not bad.successful and bad.reason.startswith(
        "input_joints 'bucket_joint' does not drive input 'bucket_stroke' of scene 'excavator'")
    (good,) = client.set_parameters(NODE, input_joints=RODS)
    assert good.successful
    assert send_until_answered(client, publisher, listener, RODS, AT, 300)
    send(client, publisher, STROKES, AT, 301)  # only the mapped names are read now
    client.spin_for(0.5)
    assert not answers(listener, 301)
    (back,) = client.set_parameters(NODE, input_joints=[""] * 3)
    assert back.successful


def test_robot_description_is_latched_and_follows_frame_id(excavator: Any, client: Client) -> None:
    from std_msgs.msg import String

    from linkage_ros.node import description_qos_profile
    from linkage_ros.urdf import generate_urdf

    texts: list[str] = []
    # subscribed long after the node started: transient local hands over the last one
    subscription = client.node.create_subscription(String, "/exc/robot_description", lambda m: texts.append(m.data),
                                                   description_qos_profile())
    try:
        assert client.spin_until(lambda: len(texts) >= 1, WAIT_S), "no latched robot_description"
        assert texts[0] == generate_urdf("excavator", frame_id="world")
        assert '<joint name="boom_cylinder_rod_joint" type="prismatic">' in texts[0]
        (result,) = client.set_parameters(NODE, frame_id="site")
        assert result.successful
        assert client.spin_until(lambda: len(texts) >= 2, WAIT_S)
        assert texts[1] == generate_urdf("excavator", frame_id="site")
    finally:
        client.node.destroy_subscription(subscription)


def test_the_recording_holds_the_driver_messages_as_received(excavator: Any) -> None:
    from rosbags.highlevel import AnyReader

    process, _, _, recording = excavator
    assert process.stop(signal.SIGINT) == 0
    inputs = []
    with AnyReader([recording]) as reader:
        for connection, _, raw in reader.messages():
            if connection.topic == "/exc/input_joint_states":
                inputs.append(reader.deserialize(raw, connection.msgtype))
    assert [list(m.name) for m in inputs if m.header.stamp.sec in (100, 101)][::1][:1] == [RODS]
    assert STROKES in [list(m.name) for m in inputs if m.header.stamp.sec == 101]
    assert len(inputs) >= 8 and inputs[0].header.stamp.sec == 100
