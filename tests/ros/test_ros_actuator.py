"""mechanism_node driving the tipper (an actuator's stroke as its input) over DDS: the prismatic
input joint in joint_states (m, m/s, N), the input parameters described in metres, a stroke
outside the cylinder's range rejected with the reason."""

from __future__ import annotations

from typing import Any

import pytest
from conftest import Client, decode

from linkage_ros.messages import topic_types

pytestmark = pytest.mark.dds

WAIT_S = 30.0


def test_the_tipper_node_publishes_its_stroke_and_rejects_one_outside_the_cylinder(
        start_node: Any, client: Client) -> None:
    from rcl_interfaces.srv import DescribeParameters

    types = dict(topic_types(["C", "F", "L"]))
    listener = client.listen({"/joint_states": types["joint_states"]})
    process = start_node("-p", "scene:=tipper", "-p", "omega:=0.05", "-p", "rate_hz:=50.0")
    try:
        if not client.spin_until(lambda: len(listener.by_topic["/joint_states"]) >= 3, WAIT_S):
            pytest.fail("no joint_states from mechanism_node:\n" + process.output())
        js = decode(listener.by_topic["/joint_states"][-1], types["joint_states"])
        i = js.name.index("stroke")
        assert 0.74 <= js.position[i] <= 1.3 and js.velocity[i] == 0.05  # m, m/s: from the closed length
        assert js.effort[i] > 0.0  # N: the cylinder holds the loaded body up
        assert js.position[js.name.index("lift_rod_joint")] == pytest.approx(js.position[i], abs=1e-15)
        described = client.call(DescribeParameters, "/mechanism_node/describe_parameters",
                                DescribeParameters.Request(names=["omega", "epsilon", "phi0"])).descriptors
        assert [d.description.split(",")[1].split(".")[0].strip() for d in described] == ["m/s", "m/s^2", "m"]
        (bad,) = client.set_parameters("/mechanism_node", phi0=1.5)
        assert not bad.successful and "group 'lift' is outside its stroke [0.74, 1.3] m" in bad.reason
        assert [v for _, v in client.get_parameters("/mechanism_node", "phi0")] == [0.74]
    finally:
        process.stop()


def test_the_excavator_node_starts_its_three_cylinders_closed_and_publishes_their_forces(
        start_node: Any, client: Client) -> None:
    types = dict(topic_types(["B", "D", "T"]))
    listener = client.listen({"/joint_states": types["joint_states"]})
    process = start_node("-p", "scene:=excavator", "-p", "rate_hz:=50.0")
    try:
        if not client.spin_until(lambda: len(listener.by_topic["/joint_states"]) >= 3, WAIT_S):
            pytest.fail("no joint_states from mechanism_node:\n" + process.output())
        js = decode(listener.by_topic["/joint_states"][-1], types["joint_states"])
        strokes = (("boom_stroke", 1.05, 1.6), ("arm_stroke", 1.3, 1.9), ("bucket_stroke", 1.0, 1.45))
        for name, closed, extended in strokes:
            i = js.name.index(name)
            assert closed < js.position[i] < extended and js.velocity[i] == 0.1  # m, m/s: extending from closed
            assert abs(js.effort[i]) > 0.0  # N
        values = [v for _, v in client.get_parameters("/mechanism_node", "input_phi0s", "input_omegas")]
        assert [list(v) for v in values] == [[1.05, 1.3, 1.0], [0.1, 0.1, 0.1]]
    finally:
        process.stop()
