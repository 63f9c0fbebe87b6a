"""The dynamic mode's frictions over DDS (issue 30), one pendulum node (four_bar_loaded without
its loads, released from rest at φ = 0.3 rad): an effort controller publishing with
``qos_profile_sensor_data`` (best effort) drives it; diagnostics carry the drive state
(``drive``, ``command_age``, ``stale``, ``efforts``, ``real_time_factor``); a set of ``phi0``
restarts the run exactly there, at rest, on the first tick after it; the recording holds the
effort commands as received and an ``energies`` row per tick."""

from __future__ import annotations

import signal
from pathlib import Path
from typing import Any

import pytest
from conftest import Client, decode
from test_ros_dynamic import pendulum_scene

pytestmark = pytest.mark.dds

WAIT_S = 20.0
NS = "/dd"
COMMAND = 0.05


@pytest.fixture(scope="module")
def drive(start_node: Any, client: Client, tmp_path_factory: pytest.TempPathFactory) -> Any:
    folder = tmp_path_factory.mktemp("drive")
    scene = pendulum_scene(folder)
    recording = folder / "run.mcap"
    listener = client.listen({f"{NS}/joint_states": "sensor_msgs/msg/JointState",
                              f"{NS}/joint_kinematics": "trajectory_msgs/msg/JointTrajectory",
                              f"{NS}/diagnostics": "diagnostic_msgs/msg/DiagnosticArray"})
    process = start_node("-r", f"__ns:={NS}", "-p", f"scene:={scene}", "-p", "mode:=dynamic", "-p", "phi0:=0.3",
                         "-p", "omega:=0.0", "-p", "rate_hz:=100.0", "-p", "effort_timeout:=0.5",
                         "-p", f"record_mcap:={recording}")
    if not client.spin_until(lambda: len(listener.by_topic[f"{NS}/joint_states"]) >= 50
                             and len(listener.by_topic[f"{NS}/diagnostics"]) >= 1, WAIT_S):
        process.kill()
        pytest.fail("no joint_states from mechanism_node in dynamic mode:\n" + process.output())
    from rclpy.qos import qos_profile_sensor_data
    from std_msgs.msg import Float64MultiArray

    publisher = client.node.create_publisher(Float64MultiArray, f"{NS}/effort_commands", qos_profile_sensor_data)
    if not client.spin_until(lambda: publisher.get_subscription_count() > 0, WAIT_S):
        pytest.fail("the effort publisher never matched the node's subscription:\n" + process.output())
    return process, listener, publisher, recording


def diagnostics(listener: Any, start: int = 0) -> list[dict[str, str]]:
    return [{kv.key: kv.value for kv in decode(d, "diagnostic_msgs/msg/DiagnosticArray").status[0].values}
            for d in listener.by_topic[f"{NS}/diagnostics"][start:]]


def test_a_best_effort_controller_drives_it_and_diagnostics_say_so(drive: Any, client: Client) -> None:
    from std_msgs.msg import Float64MultiArray

    _, listener, publisher, _ = drive
    before = diagnostics(listener)[-1]
    assert before["drive"] == "effort" and before["command_age"] == "none" and before["stale"] == "true"
    start = len(listener.by_topic[f"{NS}/diagnostics"])
    kinematics = len(listener.by_topic[f"{NS}/joint_kinematics"])
    for _ in range(30):  # 20 Hz for 1.5 s
        publisher.publish(Float64MultiArray(data=[COMMAND]))
        client.spin_for(0.05)
    client.spin_for(0.2)
    efforts = [decode(d, "trajectory_msgs/msg/JointTrajectory").points[0].effort[0]
               for d in listener.by_topic[f"{NS}/joint_kinematics"][kinematics:]]
    assert efforts[-1] == pytest.approx(COMMAND, rel=1e-9)  # the best-effort publisher reached it
    driven = diagnostics(listener, start)
    assert driven and all(d["stale"] == "false" and float(d["command_age"]) < 0.5 for d in driven[1:])
    assert driven[-1]["efforts"] == repr(COMMAND)
    assert all(float(d["real_time_factor"]) == pytest.approx(1.0, abs=0.2) for d in driven[1:])
    start = len(listener.by_topic[f"{NS}/diagnostics"])
    assert client.spin_until(lambda: any(d["stale"] == "true" for d in diagnostics(listener, start)), WAIT_S)
    stale = next(d for d in diagnostics(listener, start) if d["stale"] == "true")
    assert float(stale["command_age"]) > 0.5 and stale["efforts"] == "0.0"


def test_a_phi0_set_restarts_exactly_at_phi0_at_rest(drive: Any, client: Client) -> None:
    _, listener, _, _ = drive
    start = len(listener.by_topic[f"{NS}/joint_states"])
    (result,) = client.set_parameters(f"{NS}/mechanism_node", phi0=0.4)
    assert result.successful
    assert client.spin_until(lambda: len(listener.by_topic[f"{NS}/joint_states"]) >= start + 40, WAIT_S)
    states = [decode(d, "sensor_msgs/msg/JointState") for d in listener.by_topic[f"{NS}/joint_states"][start:]]
    crank = [(js.position[list(js.name).index("crank")], js.velocity[list(js.name).index("crank")]) for js in states]
    first = next(i for i, (phi, _) in enumerate(crank) if phi == 0.4)
    assert crank[first] == (0.4, 0.0)  # the new run's t = 0: φ0 at rest, not some instants later
    assert all(abs(phi - 0.4) > 0.0 for phi, _ in crank[first + 2:first + 10])  # then it falls


def test_the_recording_holds_the_commands_and_the_energies(drive: Any, client: Client) -> None:
    from rosbags.highlevel import AnyReader

    process, _, _, recording = drive
    assert process.stop(signal.SIGINT) == 0
    rows: dict[str, list[Any]] = {}
    with AnyReader([Path(recording)]) as reader:
        for connection, _, raw in reader.messages():
            rows.setdefault(connection.topic, []).append(reader.deserialize(raw, connection.msgtype))
    assert len(rows[f"{NS}/effort_commands"]) >= 25 and all(list(m.data) == [COMMAND]
                                                            for m in rows[f"{NS}/effort_commands"])
    energies = rows[f"{NS}/energies"]
    assert len(energies) == len(rows[f"{NS}/joint_states"]) > 100
    assert energies[0].layout.dim[0].label == "J: kinetic gravity springs total"
    for m in energies:
        kinetic, gravity, springs, total = m.data
        assert kinetic >= 0.0 and total == pytest.approx(kinetic + gravity + springs, abs=1e-12)
