"""Friction live (issue 29), over DDS with the real node process: joint_states' effort is the
input effort with friction (the solver's ``k.effort``, not the ideal one), ``friction_power``
carries the power friction dissipates (total, then per pin), and the node's MCAP recording holds
it tick for tick."""

from __future__ import annotations

import signal
from typing import Any

import numpy as np
import pytest
from conftest import Client, decode

import solver
from linkage_ros.engine import Engine
from linkage_ros.messages import topic_types
from linkage_ros.motion import Motion

pytestmark = pytest.mark.dds

SCENE = "four_bar_loaded_friction"
OMEGA = 3.0
WAIT_S = 30.0
#: The node and the test run the same one-instant solve.
TOL_REL = 1e-12
TOPICS = dict(topic_types(Engine(SCENE, Motion(omega=OMEGA))))
NAMES = ["total", "O", "A", "C", "B"]




@pytest.fixture(scope="module")
def node(start_node: Any, client: Client, tmp_path_factory: pytest.TempPathFactory) -> Any:
    """four_bar_loaded_friction in clock mode at ω = 3 rad/s, 50 Hz, recording."""
    recording = tmp_path_factory.mktemp("friction") / "friction.mcap"
    listener = client.listen({f"/friction/{t}": typename for t, typename in TOPICS.items()})
    process = start_node("-r", "__ns:=/friction", "-p", f"scene:={SCENE}", "-p", f"omega:={OMEGA}",
                         "-p", "rate_hz:=50.0", "-p", f"record_mcap:={recording}")
    if not client.spin_until(lambda: len(listener.by_topic["/friction/friction_power"]) >= 8, WAIT_S):
        process.kill()
        pytest.fail("no friction_power from mechanism_node:\n" + process.output())
    return process, listener, recording


def test_the_topic_list_has_friction_power_after_the_loads() -> None:
    topics = list(TOPICS)
    assert TOPICS["friction_power"] == "std_msgs/msg/Float64MultiArray"
    assert topics.index("friction_power") == topics.index("pin_loads/B") + 1
    assert "friction_power" not in dict(topic_types(Engine("four_bar_loaded", Motion(omega=OMEGA))))


def test_joint_states_effort_includes_the_friction_and_friction_power_is_the_solvers(node: Any) -> None:
    """Each joint_states' effort is k.effort at its φ; each friction_power message is the solver's
    power of one of the ticks (it carries no header: matched to its tick by value, the ticks lie
    0.06 rad apart)."""
    _, listener, _ = node
    scene = solver.load_scene(SCENE)
    states = listener.by_topic["/friction/joint_states"]
    assert len(states) >= 8
    expected = []
    for data in states:
        js = decode(data, TOPICS["joint_states"])
        names = list(js.name)
        phi = js.position[names.index("crank")]
        k = scene.solve(phi, omega=OMEGA, epsilon=0.0)
        effort = dict(zip(names, js.effort))
        assert effort["crank"] == pytest.approx(k.effort("crank"), rel=TOL_REL)
        assert abs(effort["crank"] - k.ideal_effort("crank")) > 1e-4  # the friction's share: mN·m, not rounding
        expected.append([float(k.friction_power), *(float(k.friction_loss(n)) for n in NAMES[1:])])
        assert expected[-1][0] == pytest.approx((effort["crank"] - k.ideal_effort("crank")) * OMEGA, rel=1e-12)
    table = np.array(expected)
    for data in listener.by_topic["/friction/friction_power"][-5:]:
        power = decode(data, TOPICS["friction_power"])
        assert power.layout.dim[0].label == "W: " + " ".join(NAMES) and power.layout.dim[0].size == 5
        got = np.array(list(power.data))
        nearest = table[np.argmin(np.abs(table - got).max(axis=1))]
        np.testing.assert_allclose(got, nearest, rtol=TOL_REL)
        assert got[0] == pytest.approx(got[1:].sum(), rel=1e-14)


def test_the_recording_holds_friction_power_tick_for_tick(node: Any, client: Client) -> None:
    from rosbags.highlevel import AnyReader

    process, _, recording = node
    assert process.stop(signal.SIGINT) == 0
    client.spin_for(0.2)
    counts = {"/friction/friction_power": 0, "/friction/joint_states": 0}
    with AnyReader([recording]) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        for connection, _, raw in reader.messages():
            if connection.topic in counts:
                message = reader.deserialize(raw, connection.msgtype)
                counts[connection.topic] += 1
                if connection.topic.endswith("friction_power"):
                    assert len(message.data) == 5 and message.data[0] > 0.0
    assert types["/friction/friction_power"] == "std_msgs/msg/Float64MultiArray"
    assert counts["/friction/friction_power"] == counts["/friction/joint_states"] > 5
