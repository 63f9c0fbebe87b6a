"""The node's dynamic mode (issue 22) over DDS with the real node process: φ(t) from the equation
of motion, joint_states with position, velocity and the applied effort, effort commands on
``effort_commands`` (std_msgs/Float64MultiArray) that change the motion, a command of the wrong
length refused with one log line while the node keeps publishing, and a conservative scene whose
total energy, computed from what joint_states publishes, stays constant.

One node for the module: the four-bar pendulum (four_bar_loaded without its force and torque:
gravity only), released from rest at φ = 0.3 rad, free until the first command."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest
from conftest import Client, decode

import solver
from solver.dynamics import reduced_model

pytestmark = pytest.mark.dds

NS = 1_000_000_000
WAIT_S = 20.0
PHI0 = 0.3
COMMAND = 0.05  # N·m on the crank (a constant torque speeds the pendulum up without bound: keep it small)
ENERGY_REL = 1e-6
"""The total energy's drift from joint_states, relative to the kinetic energy's swing (issue 22)."""
EFFORT_REL = 1e-9
"""The published effort (the kinetostatics of the published state) against the command: round-off."""


def pendulum_scene(folder: Path) -> Path:
    """four_bar_loaded without its loads: gravity alone, a conservative scene."""
    text = (Path(solver.find_scene("four_bar_loaded"))).read_text()
    head, _, _ = text.partition("\nloads:")
    path = folder / "four_bar_pendulum.yaml"
    path.write_text(head.replace("scene: four_bar_loaded", "scene: four_bar_pendulum") + "\n")
    return path


@pytest.fixture(scope="module")
def pendulum(start_node: Any, client: Client, tmp_path_factory: pytest.TempPathFactory) -> Any:
    scene_file = pendulum_scene(tmp_path_factory.mktemp("dynamic"))
    listener = client.listen({"/dyn/joint_states": "sensor_msgs/msg/JointState",
                              "/dyn/joint_kinematics": "trajectory_msgs/msg/JointTrajectory"})
    process = start_node("-r", "__ns:=/dyn", "-p", f"scene:={scene_file}", "-p", "mode:=dynamic",
                         "-p", f"phi0:={PHI0}", "-p", "omega:=0.0", "-p", "rate_hz:=100.0",
                         "-p", "effort_timeout:=5.0")
    if not client.spin_until(lambda: len(listener.by_topic["/dyn/joint_states"]) >= 120, WAIT_S):
        process.kill()
        pytest.fail("no joint_states from mechanism_node in dynamic mode:\n" + process.output())
    from std_msgs.msg import Float64MultiArray

    publisher = client.node.create_publisher(Float64MultiArray, "/dyn/effort_commands", 10)
    return process, listener, solver.load_scene(scene_file), publisher


def states(listener: Any, start: int = 0) -> list[tuple[int, dict[str, tuple[float, float, float]]]]:
    """(stamp, {joint: (position, velocity, effort)}) of every joint_states from ``start`` on."""
    out = []
    for data in listener.by_topic["/dyn/joint_states"][start:]:
        js = decode(data, "sensor_msgs/msg/JointState")
        stamp = js.header.stamp.sec * NS + js.header.stamp.nanosec
        out.append((stamp, {n: (p, v, e) for n, p, v, e in zip(js.name, js.position, js.velocity, js.effort)}))
    return out


def send(client: Client, publisher: Any, values: list[float]) -> None:
    from std_msgs.msg import Float64MultiArray

    publisher.publish(Float64MultiArray(data=values))
    client.spin_for(0.3)


def test_joint_states_carry_position_velocity_and_the_free_drives_zero_effort(pendulum: Any) -> None:
    _, listener, _, _ = pendulum
    ticks = states(listener)
    for _, joints in ticks:
        assert abs(joints["crank"][2]) < 1e-9  # free: no effort (round-off of M·ε + h)
    velocities = [j["crank"][1] for _, j in ticks]
    assert max(velocities) - min(velocities) > 1.0  # it falls


def test_total_energy_from_joint_states_stays_within_1e_6_of_the_kinetic_swing(pendulum: Any) -> None:
    _, listener, scene, _ = pendulum
    ticks = states(listener)
    phi = np.array([j["crank"][0] for _, j in ticks])
    omega = np.array([j["crank"][1] for _, j in ticks])
    model = reduced_model(scene)
    kinetic = model.kinetic(phi, omega)
    potential = model.potential(phi)
    total = kinetic + potential["gravity"] + potential["springs"]
    swing = float(np.ptp(kinetic))
    assert swing > 0.1
    # released from rest at φ0: the total is the potential energy there, at every tick received
    start = model.potential(np.array([PHI0]))
    released = float(start["gravity"][0] + start["springs"][0])
    assert float(np.max(np.abs(total - released))) <= ENERGY_REL * swing


def test_an_effort_command_over_dds_drives_the_crank(pendulum: Any, client: Client) -> None:
    _, listener, scene, publisher = pendulum
    send(client, publisher, [COMMAND])
    start = len(listener.by_topic["/dyn/joint_kinematics"])
    assert client.spin_until(lambda: len(listener.by_topic["/dyn/joint_kinematics"]) >= start + 20, WAIT_S)
    model = reduced_model(scene)
    for data in listener.by_topic["/dyn/joint_kinematics"][start:]:
        jk = decode(data, "trajectory_msgs/msg/JointTrajectory")
        i = list(jk.joint_names).index("crank")
        point = jk.points[0]
        phi, omega, eps = point.positions[i], point.velocities[i], point.accelerations[i]
        assert point.effort[i] == pytest.approx(COMMAND, rel=EFFORT_REL)
        # the published ε is the equation of motion's under the command: J(φ)·ε + h(φ, ω) = Q
        m, h, _ = model.instant((phi,), (omega,))
        assert m * eps + h[0] == pytest.approx(COMMAND, rel=1e-9, abs=1e-9)


def test_a_command_of_the_wrong_length_is_refused_and_the_node_keeps_its_last_good_one(
        pendulum: Any, client: Client) -> None:
    process, listener, _, publisher = pendulum
    send(client, publisher, [1.0, 5.0])
    start = len(listener.by_topic["/dyn/joint_states"])
    assert client.spin_until(lambda: len(listener.by_topic["/dyn/joint_states"]) >= start + 20, WAIT_S)
    assert all(j["crank"][2] == pytest.approx(COMMAND, rel=EFFORT_REL) for _, j in states(listener, start))
    assert client.spin_until(lambda: "effort command rejected" in process.output(), WAIT_S)
    lines = [line for line in process.output().splitlines() if "effort command rejected" in line]
    assert len(lines) == 1
    assert "2 value(s) for 1 input(s) (crank); keeping [0.05]" in lines[0]
