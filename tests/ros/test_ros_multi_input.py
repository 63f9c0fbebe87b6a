"""mechanism_node with several inputs (issue 14): the five-bar over DDS, one node process.

Clock mode with per-input motion laws (``input_omegas``, ``input_phi0s``: start values and the
parameter service; a wrong length rejected with a reason naming the inputs), P against the solver
at the published (q1, q2), the rate held at 100 Hz and at 1 kHz; then the same process switched
to topic mode: JointState ['q1', 'q2'] in, P and its velocity J·ω out under the message's stamp,
joint_states without q1 and q2, a message without q2 dropped with a warning.
"""

from __future__ import annotations

import signal
import struct
from typing import Any

import numpy as np
import pytest
from conftest import Client, decode, solo_listener

import solver
from linkage_ros.messages import topic_types

pytestmark = pytest.mark.dds

NS = 1_000_000_000
NAMESPACE = "/five"
NODE = f"{NAMESPACE}/mechanism_node"
TYPES = dict(topic_types(["P"]))
LISTENED = ("joint_states", "joint_kinematics", "points/P/position", "points/P/velocity", "diagnostics")
INPUTS = ("q1", "q2")
START_OMEGAS = (1.0, -2.0)
START_PHI0S = (1.7, 1.3)  # rad: inside the workspace, moving away from the singular corners
TOL_POS = 1e-12  # m
TOL_REL = 1e-9
WAIT_S = 20.0


def full(topic: str) -> str:
    return f"{NAMESPACE}/{topic}"


def stamp_of(data: bytes) -> int:
    sec, nanosec = struct.unpack_from("<iI", data, 4)
    return sec * NS + nanosec


def by_stamp(listener: Any, topic: str, stamps: set[int] | None = None) -> dict[int, bytes]:
    return {stamp_of(d): d for d in listener.by_topic[full(topic)] if stamps is None or stamp_of(d) in stamps}


def wait_for(client: Client, listener: Any, topic: str, count: int) -> None:
    start = len(listener.by_topic[full(topic)])
    assert client.spin_until(lambda: len(listener.by_topic[full(topic)]) >= start + count, WAIT_S), (
        f"fewer than {count} messages on {topic}"
    )


def input_state(jk_bytes: bytes) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(q, ω, ε) of the inputs, in scene order, from one joint_kinematics message."""
    jk = decode(jk_bytes, TYPES["joint_kinematics"])
    idx = [jk.joint_names.index(n) for n in INPUTS]
    point = jk.points[0]
    return (np.array([point.positions[i] for i in idx]), np.array([point.velocities[i] for i in idx]),
            np.array([point.accelerations[i] for i in idx]))


@pytest.fixture(scope="module")
def five_bar(start_node: Any, client: Client) -> Any:
    listener = client.listen({full(t): TYPES[t] for t in LISTENED})
    process = start_node(
        "-r", f"__ns:={NAMESPACE}", "-p", "scene:=five_bar", "-p", "rate_hz:=100.0",
        "-p", f"input_omegas:=[{START_OMEGAS[0]}, {START_OMEGAS[1]}]",
        "-p", f"input_phi0s:=[{START_PHI0S[0]}, {START_PHI0S[1]}]",
    )
    if not client.spin_until(lambda: len(listener.by_topic[full("joint_states")]) >= 3, WAIT_S):
        process.kill()
        pytest.fail("no joint_states from mechanism_node on five_bar:\n" + process.output())
    yield process, listener
    assert process.stop(signal.SIGTERM) == 0, process.output()


def test_clock_mode_runs_each_input_on_its_own_law_from_the_start_values(five_bar: Any, client: Client) -> None:
    from rcl_interfaces.msg import ParameterType

    _, listener = five_bar
    first = input_state(listener.by_topic[full("joint_kinematics")][0])
    assert tuple(first[1]) == START_OMEGAS and tuple(first[2]) == (0.0, 0.0)
    # q_i(t) = q_i0 + ω_i t, with t the run time of that tick (≥ 0)
    t = (first[0] - np.array(START_PHI0S)) / np.array(START_OMEGAS)
    assert t[0] == pytest.approx(t[1], abs=1e-12) and t[0] >= 0.0
    (omegas,) = client.get_parameters(NODE, "input_omegas")
    assert omegas[0] == ParameterType.PARAMETER_DOUBLE_ARRAY and list(omegas[1]) == list(START_OMEGAS)
    # diagnostics: first tick (maybe before the subscription matched), then about once a second
    assert client.spin_until(lambda: bool(listener.by_topic[full("diagnostics")]), 5.0), "no diagnostics"
    diagnostics = by_stamp(listener, "diagnostics")
    (status,) = decode(next(iter(diagnostics.values())), TYPES["diagnostics"]).status
    keys = [kv.key for kv in status.values]
    assert keys == ["status", "t", "phi/q1", "phi/q2", "omega/q1", "omega/q2", "epsilon/q1", "epsilon/q2",
                    "conditioning"]
    assert status.name == "linkage_ros: five_bar" and status.level == b"\x00"


def test_clock_mode_values_equal_the_solver_at_the_published_inputs(five_bar: Any, client: Client) -> None:
    _, listener = five_bar
    wait_for(client, listener, "joint_states", 10)
    scene = solver.load_scene("five_bar").everything()
    kin = by_stamp(listener, "joint_kinematics")
    pos, vel = by_stamp(listener, "points/P/position"), by_stamp(listener, "points/P/velocity")
    states = by_stamp(listener, "joint_states")
    common = sorted(set(kin) & set(pos) & set(vel) & set(states))[-10:]
    assert len(common) >= 5
    for s in common:
        q, w, e = input_state(kin[s])
        k = scene.solve(tuple(q), omega=tuple(w), epsilon=tuple(e))
        p = decode(pos[s], TYPES["points/P/position"]).point
        v = decode(vel[s], TYPES["points/P/velocity"]).vector
        np.testing.assert_allclose([p.x, p.y], k.point("P").position, rtol=0, atol=TOL_POS)
        np.testing.assert_allclose([v.x, v.y], k.point("P").velocity, rtol=0, atol=TOL_POS * np.abs(w).max())
        js = decode(states[s], TYPES["joint_states"])
        assert {"q1", "q2", "left_distal", "right_distal"} <= set(js.name)  # clock mode: every input too
        assert [js.position[js.name.index(n)] for n in INPUTS] == list(q)
        assert js.position[js.name.index("left_distal")] == pytest.approx(
            float(k.joint("left_distal").position), abs=TOL_POS)


def test_per_input_omega_through_the_parameter_service_and_a_wrong_length_rejected(
    five_bar: Any, client: Client
) -> None:
    _, listener = five_bar
    (ok,) = client.set_parameters(NODE, input_omegas=[0.5, 0.25])
    assert ok.successful, ok.reason
    # messages published before the set took effect may still be in flight on a loaded machine:
    # wait for the first one with the new law (the node applies it at its next tick)
    def latest_omega() -> tuple[float, ...]:
        return tuple(input_state(listener.by_topic[full("joint_kinematics")][-1])[1])

    assert client.spin_until(lambda: latest_omega() == (0.5, 0.25), 10.0), latest_omega()
    wait_for(client, listener, "joint_kinematics", 5)
    assert latest_omega() == (0.5, 0.25)  # and it stays
    (as_ints,) = client.set_parameters(NODE, input_omegas=[1, -1])  # integers: taken as doubles
    assert as_ints.successful, as_ints.reason
    (bad,) = client.set_parameters(NODE, input_omegas=[1.0, 2.0, 3.0])
    assert not bad.successful
    assert "input_omegas needs 2 value(s), one per input of the scene (q1, q2)" in bad.reason
    (bad,) = client.set_parameters(NODE, input_epsilons=[1e9, 0.0])
    assert not bad.successful and "input_epsilons" in bad.reason
    wait_for(client, listener, "joint_kinematics", 5)  # still publishing, with the accepted law
    assert client.spin_until(lambda: latest_omega() == (1.0, -1.0), 10.0), latest_omega()
    results = client.set_parameters(NODE, input_omegas=[], omega=0.75)  # empty: omega for both
    assert all(r.successful for r in results), [r.reason for r in results]
    assert client.spin_until(lambda: latest_omega() == (0.75, 0.75), 10.0), latest_omega()
    (back,) = client.set_parameters(NODE, input_omegas=[0.2, -0.2])  # slow: stay in the workspace
    assert back.successful, back.reason


def test_the_five_bar_is_published_at_100_hz_and_at_1_khz(five_bar: Any, client: Client) -> None:
    topic = full("joint_states")
    # counted by a client of its own that reads joint_states only (conftest.solo_listener), so that
    # a 2-core machine counts the node's ticks rather than this process's reading
    with solo_listener(topic, TYPES["joint_states"]) as (solo, reader):
        try:
            for rate in (100.0, 1000.0):
                (ok,) = client.set_parameters(NODE, rate_hz=rate)
                assert ok.successful, ok.reason
                reader.spin_for(0.2)
                start = len(solo.by_topic[topic])
                reader.spin_for(2.0)  # one second of the node's own clock, counted by stamps once in
                received = [stamp_of(d) for d in solo.by_topic[topic][start:]]
                assert received, f"no joint_states at {rate} Hz"
                stamps = [s for s in received if s < received[0] + NS]
                assert len(stamps) >= 0.5 * rate, f"{len(stamps)} ticks in 1.00 s at {rate} Hz"
                assert float(np.median(np.diff(stamps))) == pytest.approx(NS / rate, rel=0.05)
                assert stamps == sorted(set(stamps))
        finally:  # back to 100 Hz even when a count fails, for the topic-mode tests that follow
            (ok,) = client.set_parameters(NODE, rate_hz=100.0)
        assert ok.successful, ok.reason


# ----------------------------------------------------------------------------------- topic mode
def send(client: Client, publisher: Any, names: list[str], position: list[float], velocity: list[float],
         stamp_ns: int) -> None:
    from builtin_interfaces.msg import Time
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Header

    header = Header(stamp=Time(sec=stamp_ns // NS, nanosec=stamp_ns % NS), frame_id="")
    publisher.publish(JointState(header=header, name=names, position=position, velocity=velocity))
    client.spin_for(0.01)


@pytest.fixture(scope="module")
def topic_mode(five_bar: Any, client: Client) -> Any:
    from sensor_msgs.msg import JointState

    process, listener = five_bar
    (ok,) = client.set_parameters(NODE, input_source="topic")
    assert ok.successful, ok.reason
    publisher = client.node.create_publisher(JointState, full("input_joint_states"), 10)
    if not client.spin_until(lambda: publisher.get_subscription_count() >= 1, WAIT_S):
        pytest.fail("mechanism_node did not subscribe to input_joint_states:\n" + process.output())
    probe = 1_000 * NS
    for _ in range(100):
        send(client, publisher, list(INPUTS), [1.6, 1.4], [0.0, 0.0], probe)
        if client.spin_until(lambda: bool(by_stamp(listener, "joint_states", {probe})), 0.2):
            break
    else:
        pytest.fail("no answer to a probe JointState:\n" + process.output())
    yield process, listener, publisher
    client.node.destroy_publisher(publisher)


def test_topic_mode_answers_each_joint_state_with_p_and_j_omega_under_its_stamp(
    topic_mode: Any, client: Client
) -> None:
    process, listener, publisher = topic_mode
    rng = np.random.default_rng(14)
    q = np.radians(rng.uniform(40.0, 140.0, size=(12, 2)))
    w = rng.uniform(-3.0, 3.0, size=(12, 2))
    stamps = [2_000 * NS + n * 10_000_000 + 7 for n in range(len(q))]
    for n, s in enumerate(stamps):
        names = list(INPUTS) if n % 2 else ["gripper", "q2", "q1"]  # any order, other joints beside
        pos = [*q[n]] if n % 2 else [0.3, q[n, 1], q[n, 0]]
        vel = [*w[n]] if n % 2 else [9.0, w[n, 1], w[n, 0]]
        send(client, publisher, names, [float(x) for x in pos], [float(x) for x in vel], s)
    wanted = set(stamps)
    assert client.spin_until(lambda: len(by_stamp(listener, "points/P/velocity", wanted)) == len(q), WAIT_S), (
        process.output()
    )
    client.spin_for(0.1)
    scene = solver.load_scene("five_bar")
    k = scene.solve(q, omega=w, epsilon=0.0)
    jac = np.asarray(k.point("P").jacobian)  # (N, 2, 2): ∂P/∂(q1, q2)
    positions = by_stamp(listener, "points/P/position", wanted)
    velocities = by_stamp(listener, "points/P/velocity", wanted)
    states = by_stamp(listener, "joint_states", wanted)
    assert set(positions) == set(velocities) == set(states) == wanted
    for n, s in enumerate(stamps):
        p = decode(positions[s], TYPES["points/P/position"]).point
        np.testing.assert_allclose([p.x, p.y], np.asarray(k.point("P").position)[n], rtol=0, atol=TOL_POS)
        v = decode(velocities[s], TYPES["points/P/velocity"]).vector
        expected = jac[n] @ w[n]
        assert np.abs(np.array([v.x, v.y]) - expected).max() <= TOL_REL * np.abs(expected).max()
        js = decode(states[s], TYPES["joint_states"])
        assert not set(INPUTS) & set(js.name) and {"left_distal", "right_distal"} <= set(js.name)
    (status,) = decode(by_stamp(listener, "diagnostics", {stamps[0]})[stamps[0]], TYPES["diagnostics"]).status
    values = {kv.key: kv.value for kv in status.values}
    assert (float(values["phi/q1"]), float(values["phi/q2"])) == (q[0, 0], q[0, 1])


def test_topic_mode_drops_a_message_without_every_input_with_a_warning(topic_mode: Any, client: Client) -> None:
    process, listener, publisher = topic_mode
    s = 3_000 * NS
    send(client, publisher, ["q1"], [1.2], [1.0], s)
    send(client, publisher, list(INPUTS), [1.2, 1.5], [1.0, 0.0], s + NS)
    assert client.spin_until(lambda: by_stamp(listener, "joint_states", {s + NS}), WAIT_S)
    client.spin_for(0.1)
    assert not by_stamp(listener, "joint_states", {s})
    assert client.spin_until(lambda: bool(by_stamp(listener, "diagnostics", {s})), 5.0)  # WARN (issue 30)
    assert client.spin_until(lambda: "JointState dropped: no joint 'q2' in the message" in process.output(), 5.0), (
        process.output()
    )
    (bad,) = client.set_parameters(NODE, input_joint="q1")
    assert not bad.successful and "has 2 inputs (q1, q2)" in bad.reason
