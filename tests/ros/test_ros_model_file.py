"""mechanism_node on an imported model file (issue 31): ``-p scene:=robotiq_2f85.xml`` over DDS.

Clock mode publishes every joint of the MJCF under the model's names, in its convention (qpos),
equal to the solver at the published inputs; topic mode reads the user's own input joint names
(the three hinges the default picks: right driver, both spring links) and answers with the
passive joints — the coupled left driver among them — under the incoming stamp.
"""

from __future__ import annotations

import signal
import struct
from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import Client, decode

import solver
from linkage_ros.messages import topic_types

pytestmark = pytest.mark.dds
pytest.importorskip("mujoco")

NS = 1_000_000_000
NAMESPACE = "/gripper"
NODE = f"{NAMESPACE}/mechanism_node"
MODEL = Path(__file__).resolve().parents[1] / "data" / "models" / "robotiq_2f85.xml"
TYPES = dict(topic_types(["right_pad"]))
LISTENED = ("joint_states", "joint_kinematics", "points/right_pad/position")
INPUTS = ("right_driver_joint", "right_spring_link_joint", "left_spring_link_joint")
PASSIVE = ("right_coupler_joint", "right_follower_joint", "left_driver_joint", "left_coupler_joint",
           "left_follower_joint")
TOL = 1e-12
WAIT_S = 30.0


def full(topic: str) -> str:
    return f"{NAMESPACE}/{topic}"


def stamp_of(data: bytes) -> int:
    sec, nanosec = struct.unpack_from("<iI", data, 4)
    return sec * NS + nanosec


def by_stamp(listener: Any, topic: str, stamps: set[int] | None = None) -> dict[int, bytes]:
    return {stamp_of(d): d for d in listener.by_topic[full(topic)] if stamps is None or stamp_of(d) in stamps}


@pytest.fixture(scope="module")
def gripper(start_node: Any, client: Client) -> Any:
    listener = client.listen({full(t): TYPES[t] for t in LISTENED})
    process = start_node(
        "-r", f"__ns:={NAMESPACE}", "-p", f"scene:={MODEL}", "-p", "rate_hz:=50.0",
        "-p", "input_omegas:=[0.02, 0.02, 0.02]", "-p", "input_phi0s:=[0.1, 0.1, 0.1]",
        "-p", "points:=[right_pad]",
    )
    if not client.spin_until(lambda: len(listener.by_topic[full("joint_states")]) >= 3, WAIT_S):
        process.kill()
        pytest.fail("no joint_states from mechanism_node on the 2F-85:\n" + process.output())
    yield process, listener
    assert process.stop(signal.SIGTERM) == 0, process.output()


def test_clock_mode_publishes_the_models_joints_in_its_convention(gripper: Any, client: Client) -> None:
    _, listener = gripper
    assert client.spin_until(lambda: len(listener.by_topic[full("joint_states")]) >= 8, WAIT_S)
    scene = solver.load_scene(MODEL)
    states = by_stamp(listener, "joint_states")
    for data in list(states.values())[-5:]:
        js = decode(data, TYPES["joint_states"])
        assert set(INPUTS) | set(PASSIVE) <= set(js.name)
        q = tuple(js.position[js.name.index(n)] for n in INPUTS)
        k = scene.solve(q)
        for name in PASSIVE:
            assert js.position[js.name.index(name)] == pytest.approx(float(k.joint(name).position), abs=TOL)
        # the joint equality: the left driver turns with the right one
        assert js.position[js.name.index("left_driver_joint")] == pytest.approx(q[0], abs=TOL)


def test_topic_mode_reads_and_writes_the_models_joint_names(gripper: Any, client: Client) -> None:
    from builtin_interfaces.msg import Time
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Header

    process, listener = gripper
    (ok,) = client.set_parameters(NODE, input_source="topic")
    assert ok.successful, ok.reason
    publisher = client.node.create_publisher(JointState, full("input_joint_states"), 10)
    assert client.spin_until(lambda: publisher.get_subscription_count() >= 1, WAIT_S), process.output()
    q = np.array([[0.3, 0.25, 0.35], [0.6, 0.55, 0.6], [0.05, 0.0, 0.1]])
    stamps = [5_000 * NS + n * 1_000_000 + 3 for n in range(len(q))]

    def send_all() -> None:
        for row, s in zip(q, stamps):
            header = Header(stamp=Time(sec=s // NS, nanosec=s % NS), frame_id="")
            publisher.publish(JointState(header=header, name=list(INPUTS), position=[float(x) for x in row],
                                         velocity=[0.0, 0.0, 0.0]))
            client.spin_for(0.01)

    wanted = set(stamps)
    for _ in range(20):
        send_all()
        if client.spin_until(lambda: len(by_stamp(listener, "joint_states", wanted)) == len(q), 1.0):
            break
    states = by_stamp(listener, "joint_states", wanted)
    assert set(states) == wanted, process.output()
    scene = solver.load_scene(MODEL)
    for row, s in zip(q, stamps):
        js = decode(states[s], TYPES["joint_states"])
        assert not set(INPUTS) & set(js.name) and set(PASSIVE) <= set(js.name)
        k = scene.solve(tuple(row))
        for name in PASSIVE:
            assert js.position[js.name.index(name)] == pytest.approx(float(k.joint(name).position), abs=TOL)
    client.node.destroy_publisher(publisher)
