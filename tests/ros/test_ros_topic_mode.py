"""mechanism_node in topic mode (issue 12), over DDS: JointState in on input_joint_states, every
message answered under its stamp; the unassemblable case; the run-time switch."""

from __future__ import annotations

import json
import signal
import struct
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import Client, decode

from linkage_ros.messages import topic_types

pytestmark = pytest.mark.dds

NS = 1_000_000_000
ROOT = Path(__file__).resolve().parents[2]
REFERENCE = json.loads((ROOT / "tests" / "data" / "reference_four_bar.json").read_text())
DOUBLE_ROCKER = ROOT / "config" / "scenes" / "hard" / "double_rocker.yaml"
TYPES = dict(topic_types(["A", "B"]))
NAMESPACE = "/relay"
NODE = f"{NAMESPACE}/mechanism_node"
LISTENED = ("joint_states", "points/B/position", "points/B/velocity", "diagnostics")
TOL_POS = 1e-12
TOL_REL = 1e-9
OMEGA = 2.5
WAIT_S = 20.0


def stamp(topic: str, data: bytes) -> int:
    sec, nanosec = struct.unpack_from("<iI", data, 8 if topic.endswith("markers") else 4)
    return sec * NS + nanosec


@pytest.fixture(scope="module")
def relay(start_node: Any, client: Client) -> Any:
    from sensor_msgs.msg import JointState

    listener = client.listen({f"{NAMESPACE}/{t}": TYPES[t] for t in LISTENED})
    process = start_node("-r", f"__ns:={NAMESPACE}", "-p", "scene:=four_bar", "-p", "input_source:=topic",
                         "-p", "rate_hz:=100.0")
    publisher = client.node.create_publisher(JointState, f"{NAMESPACE}/input_joint_states", 10)
    if not client.spin_until(lambda: publisher.get_subscription_count() >= 1, WAIT_S):
        process.kill()
        pytest.fail("mechanism_node did not subscribe to input_joint_states:\n" + process.output())
    # until both ends have matched, a best-effort reader may miss a message: probe first
    probe = 1_000 * NS
    for _ in range(100):
        send(client, publisher, ["crank"], [0.0], [OMEGA], probe)
        if client.spin_until(lambda: bool(answers(listener, "joint_states", {probe})), 0.2):
            break
    else:
        process.kill()
        pytest.fail("no answer to a probe JointState:\n" + process.output())
    yield process, listener, publisher
    client.node.destroy_publisher(publisher)
    assert process.stop(signal.SIGTERM) == 0


def send(client: Client, publisher: Any, names: list[str], position: list[float], velocity: list[float],
         stamp_ns: int) -> None:
    from builtin_interfaces.msg import Time
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Header

    header = Header(stamp=Time(sec=stamp_ns // NS, nanosec=stamp_ns % NS), frame_id="")
    publisher.publish(JointState(header=header, name=names, position=position, velocity=velocity))
    client.spin_for(0.01)


def answers(listener: Any, topic: str, stamps: set[int]) -> dict[int, bytes]:
    full = f"{NAMESPACE}/{topic}"
    return {stamp(full, d): d for d in listener.by_topic[full] if stamp(full, d) in stamps}


def test_every_joint_state_is_answered_under_its_stamp_on_the_50_digit_reference(relay: Any, client: Client) -> None:
    process, listener, publisher = relay
    t0 = 2_000 * NS
    count = len(REFERENCE["phi"])
    stamps = [t0 + n * 10_000_000 for n in range(count)]
    for n, s in enumerate(stamps):
        send(client, publisher, ["crank"], [float(REFERENCE["phi"][n])], [OMEGA], s)
    wanted = set(stamps)
    assert client.spin_until(lambda: len(answers(listener, "points/B/velocity", wanted)) == count, WAIT_S), (
        f"unanswered: {sorted(wanted - set(answers(listener, 'points/B/velocity', wanted)))}\n" + process.output()
    )
    client.spin_for(0.1)
    states = answers(listener, "joint_states", wanted)
    positions = answers(listener, "points/B/position", wanted)
    velocities = answers(listener, "points/B/velocity", wanted)
    assert set(states) == set(positions) == set(velocities) == wanted  # every input answered
    length = float(REFERENCE["scale_length"])
    for n, s in enumerate(stamps):
        js = decode(states[s], TYPES["joint_states"])
        assert "crank" not in js.name and {"coupler", "rocker"} <= set(js.name)
        b = decode(positions[s], TYPES["points/B/position"]).point
        ref_b = [float(x) for x in REFERENCE["points"]["B"]["position"][n]]
        np.testing.assert_allclose([b.x, b.y], ref_b, rtol=0, atol=TOL_POS)
        v = decode(velocities[s], TYPES["points/B/velocity"]).vector
        ref_v = np.array([float(x) for x in REFERENCE["points"]["B"]["d_dphi"][n]]) * OMEGA
        np.testing.assert_allclose([v.x, v.y], ref_v, rtol=0, atol=TOL_REL * max(np.abs(ref_v).max(), length * OMEGA))
    # nothing else was published in topic mode (no clock ticks)
    received = {stamp(f"{NAMESPACE}/joint_states", d) for d in listener.by_topic[f"{NAMESPACE}/joint_states"]}
    assert received <= wanted | {1_000 * NS}  # and the probe


def test_a_message_without_the_input_joint_is_dropped_with_a_warning(relay: Any, client: Client) -> None:
    process, listener, publisher = relay
    s = 3_000 * NS
    send(client, publisher, ["elbow"], [0.3], [1.0], s)
    send(client, publisher, ["crank"], [0.4], [1.0], s + NS)
    assert client.spin_until(lambda: answers(listener, "joint_states", {s + NS}), WAIT_S)
    assert not answers(listener, "joint_states", {s})
    # dropped: diagnostics WARN under its stamp (issue 30), and a warning
    assert client.spin_until(lambda: answers(listener, "diagnostics", {s}), 5.0)
    status = decode(answers(listener, "diagnostics", {s})[s], TYPES["diagnostics"]).status[0]
    assert status.level in (1, b"\x01") and status.message.startswith("JointState dropped: no joint 'crank'")
    assert client.spin_until(lambda: "JointState dropped: no joint 'crank'" in process.output(), 5.0), process.output()


def test_input_source_switches_at_run_time(relay: Any, client: Client) -> None:
    _, listener, publisher = relay
    topic = f"{NAMESPACE}/joint_states"
    (ok,) = client.set_parameters(NODE, input_source="clock")
    assert ok.successful, ok.reason
    before = len(listener.by_topic[topic])
    assert client.spin_until(lambda: len(listener.by_topic[topic]) >= before + 20, WAIT_S)  # ticking at 100 Hz
    js = decode(listener.by_topic[topic][-1], TYPES["joint_states"])
    assert "crank" in js.name  # clock mode publishes the input joint too
    (ok,) = client.set_parameters(NODE, input_source="topic")
    assert ok.successful, ok.reason
    assert client.spin_until_quiet(listener, topic, 0.3, WAIT_S)  # the timer stopped (100 Hz before)
    s = 4_000 * NS
    send(client, publisher, ["crank"], [1.0], [OMEGA], s)
    assert client.spin_until(lambda: answers(listener, "joint_states", {s}), WAIT_S)
    (bad,) = client.set_parameters(NODE, input_source="sometimes")
    assert not bad.successful and "input_source must be one of clock, topic" in bad.reason
    (bad,) = client.set_parameters(NODE, input_joint="no_such_joint")
    assert not bad.successful and "no_such_joint" in bad.reason


def test_an_unassemblable_input_gets_diagnostics_error_and_no_joint_states(relay: Any, client: Client) -> None:
    _, listener, publisher = relay
    (ok,) = client.set_parameters(NODE, scene=str(DOUBLE_ROCKER))
    assert ok.successful, ok.reason
    inside, after = 5_000 * NS, 5_000 * NS + 10_000_000
    client.spin_for(0.2)
    send(client, publisher, ["crank"], [3.0], [OMEGA], inside)  # 172°: inside (113.97°, 246.03°)
    send(client, publisher, ["crank"], [0.5], [OMEGA], after)
    assert client.spin_until(lambda: answers(listener, "points/B/position", {after}), WAIT_S)
    client.spin_for(0.1)
    (diagnostics,) = answers(listener, "diagnostics", {inside}).values()
    (status,) = decode(diagnostics, TYPES["diagnostics"]).status
    assert status.level == b"\x02" and "cannot be assembled for φ in (113.9" in status.message
    values = {kv.key: kv.value for kv in status.values}
    assert float(values["phi"]) == 3.0
    assert not answers(listener, "joint_states", {inside}) and not answers(listener, "points/B/position", {inside})
    js = decode(answers(listener, "joint_states", {after})[after], TYPES["joint_states"])
    assert all(np.isfinite([*js.position, *js.velocity]))
    (ok_status,) = decode(answers(listener, "diagnostics", {after})[after], TYPES["diagnostics"]).status
    assert ok_status.level == b"\x00"  # the next message is answered normally, and says so
