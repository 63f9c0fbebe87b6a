"""Forces live (issue 17), over DDS with the real node process: the input effort on joint_states
and joint_kinematics, a WrenchStamped per pin load, the load arrows in the markers, the same in
topic mode (ω and ε from the followed motion) and in the node's MCAP recording; a scene without
forces publishes exactly what it did before."""

from __future__ import annotations

import math
import signal
import struct
from collections import defaultdict
from typing import Any

import numpy as np
import pytest
from conftest import Client, decode

import solver
from linkage_ros.engine import Engine
from linkage_ros.messages import topic_types
from linkage_ros.motion import Motion

pytestmark = pytest.mark.dds

NS = 1_000_000_000
SCENE = "four_bar_loaded"
OMEGA = 3.0
WAIT_S = 20.0
TOL_REL = 1e-12
"""Relative to the largest load of the tick: the node and the test run the same one-instant solve."""


def topics_of(scene: str) -> dict[str, str]:
    return dict(topic_types(Engine(scene, Motion(omega=OMEGA))))


TOPICS = topics_of(SCENE)
PAIRS = Engine(SCENE, Motion(omega=OMEGA)).load_pairs


def stamp(topic: str, data: bytes) -> int:
    sec, nanosec = struct.unpack_from("<iI", data, 8 if topic.endswith("markers") else 4)
    return sec * NS + nanosec


def by_tick(listener: Any, namespace: str) -> dict[int, dict[str, bytes]]:
    out: dict[int, dict[str, bytes]] = defaultdict(dict)
    for topic, data in listener.messages:
        out[stamp(topic, data)][topic[len(namespace) + 1:]] = data
    return out


def check_loads(tick: dict[str, bytes], k: Any) -> float:
    """Every pin load of ``tick`` against ``k``; returns the largest load (N)."""
    largest = max(float(np.abs(k.reaction(p.point, on=p.body, by=p.other)).max()) for p in PAIRS)
    for pair in PAIRS:
        wrench = decode(tick[pair.topic], TOPICS[pair.topic]).wrench
        expected = k.reaction(pair.point, on=pair.body, by=pair.other)
        np.testing.assert_allclose([wrench.force.x, wrench.force.y], expected, rtol=0, atol=TOL_REL * largest)
        assert (wrench.force.z, wrench.torque.x, wrench.torque.y, wrench.torque.z) == (0.0, 0.0, 0.0, 0.0)
    return largest


@pytest.fixture(scope="module")
def loaded(start_node: Any, client: Client, tmp_path_factory: pytest.TempPathFactory) -> Any:
    """four_bar_loaded in clock mode at ω = 3 rad/s, 50 Hz, recording; listened to from the start."""
    recording = tmp_path_factory.mktemp("forces") / "loaded.mcap"
    listener = client.listen({f"/loaded/{t}": typename for t, typename in TOPICS.items()})
    process = start_node("-r", "__ns:=/loaded", "-p", f"scene:={SCENE}", "-p", f"omega:={OMEGA}",
                         "-p", "rate_hz:=50.0", "-p", f"record_mcap:={recording}")
    if not client.spin_until(lambda: len(listener.by_topic["/loaded/joint_states"]) >= 8, WAIT_S):
        process.kill()
        pytest.fail("no joint_states from mechanism_node:\n" + process.output())
    return process, listener, recording


def complete_ticks(listener: Any) -> list[dict[str, bytes]]:
    wanted = {t for t in TOPICS if t != "diagnostics"}
    return [tick for tick in by_tick(listener, "/loaded").values() if wanted <= set(tick)]


def test_joint_states_carry_the_solvers_input_effort_and_zero_for_passive_joints(loaded: Any) -> None:
    _, listener, _ = loaded
    scene = solver.load_scene(SCENE)
    ticks = complete_ticks(listener)
    assert len(ticks) >= 5
    for tick in ticks[-5:]:
        js = decode(tick["joint_states"], TOPICS["joint_states"])
        names = list(js.name)
        phi = js.position[names.index("crank")]
        assert js.velocity[names.index("crank")] == OMEGA
        k = scene.solve(phi, omega=OMEGA, epsilon=0.0)
        effort = dict(zip(names, js.effort))
        assert len(js.effort) == len(names)
        assert effort["crank"] == pytest.approx(k.effort("crank"), rel=TOL_REL)
        # the URDF tree's crank joint turns with φ: the same torque; the other pins carry none
        assert effort["crank_joint"] == effort["crank"]
        assert all(v == 0.0 for n, v in effort.items() if n not in ("crank", "crank_joint"))
        jk = decode(tick["joint_kinematics"], TOPICS["joint_kinematics"])
        assert list(jk.points[0].effort) == [effort[n] for n in jk.joint_names]


def test_each_pin_load_is_a_wrench_equal_to_the_solvers_reaction(loaded: Any) -> None:
    _, listener, _ = loaded
    scene = solver.load_scene(SCENE)
    assert [p.topic for p in PAIRS] == ["pin_loads/O", "pin_loads/A", "pin_loads/C", "pin_loads/B"]
    for tick in complete_ticks(listener)[-5:]:
        js = decode(tick["joint_states"], TOPICS["joint_states"])
        k = scene.solve(js.position[list(js.name).index("crank")], omega=OMEGA, epsilon=0.0)
        assert check_loads(tick, k) > 1.0  # gravity and the loads: newtons, not round-off


def test_markers_draw_an_arrow_per_load_from_its_pin_along_the_force(loaded: Any) -> None:
    _, listener, _ = loaded
    tick = complete_ticks(listener)[-1]
    arrows = [m for m in decode(tick["markers"], TOPICS["markers"]).markers if m.ns == "loads"]
    assert [m.id for m in arrows] == list(range(len(PAIRS)))
    assert arrows[3].text.startswith("pin_loads/B: force on coupler from rocker; arrow ")
    scale = float(arrows[0].text.split("arrow ")[1].split(" m per N")[0])
    floor = float(arrows[0].text.split("at least ")[1].split(" m")[0])  # a small load's shortest arrow
    assert scale > 0.0 and floor > 0.0
    labels = [m for m in decode(tick["markers"], TOPICS["markers"]).markers if m.ns == "load_labels"]
    assert [m.text for m in labels] == [f"R_{pair.key}" for pair in PAIRS]  # each arrow names its pin
    for marker, pair in zip(arrows, PAIRS):
        assert marker.type == marker.ARROW and len(marker.points) == 2
        assert marker.text.startswith(f"{pair.topic}: force on {pair.body} from {pair.other}; arrow {scale:g} m per N")
        wrench = decode(tick[pair.topic], TOPICS[pair.topic]).wrench
        start, end = marker.points
        f = math.hypot(wrench.force.x, wrench.force.y)
        s = max(scale * f, floor) / f  # the rule: proportional, never shorter than the floor
        assert (end.x - start.x, end.y - start.y) == pytest.approx(
            (s * wrench.force.x, s * wrench.force.y), rel=1e-2, abs=1e-15)


def test_the_recording_holds_the_load_topics_tick_for_tick(loaded: Any, client: Client) -> None:
    from rosbags.highlevel import AnyReader

    from linkage_ros.record.replay import run_data_from_mcap

    process, listener, recording = loaded
    assert process.stop(signal.SIGINT) == 0
    client.spin_for(0.2)
    counts: dict[str, int] = defaultdict(int)
    with AnyReader([recording]) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        for connection, _, raw in reader.messages():
            reader.deserialize(raw, connection.msgtype)
            counts[connection.topic] += 1
    for pair in PAIRS:
        assert types[f"/loaded/{pair.topic}"] == "geometry_msgs/msg/WrenchStamped"
        assert counts[f"/loaded/{pair.topic}"] == counts["/loaded/joint_states"] > 5
    data, _ = run_data_from_mcap(recording)
    assert set(data.loads) == {p.key for p in PAIRS} and set(data.efforts) == {"crank"}
    assert data.load_pins == {p.key: (p.point, p.body, p.other) for p in PAIRS}
    scene = solver.load_scene(SCENE)
    k = scene.solve(data.joints["crank"][0], omega=OMEGA, epsilon=0.0)
    np.testing.assert_allclose(data.efforts["crank"], k.effort("crank"), rtol=TOL_REL)
    np.testing.assert_allclose(data.loads["B"][:, :2], k.reaction("B", on="coupler", by="rocker"), rtol=TOL_REL,
                               atol=TOL_REL * 100.0)


def test_a_scene_without_forces_keeps_an_empty_effort_and_no_load_topics(start_node: Any, client: Client) -> None:
    plain = dict(topic_types(["A", "B"]))
    listener = client.listen({f"/plain/{t}": typename for t, typename in plain.items()})
    process = start_node("-r", "__ns:=/plain", "-p", "scene:=four_bar", "-p", "rate_hz:=50.0")
    try:
        assert client.spin_until(lambda: len(listener.by_topic["/plain/joint_states"]) >= 3, WAIT_S), process.output()
        js = decode(listener.by_topic["/plain/joint_states"][-1], plain["joint_states"])
        assert len(js.name) == 6 and len(js.effort) == 0
        expected = {f"/plain/{t}" for t in plain}
        assert client.spin_until(lambda: {n for n, _ in client.published_by("mechanism_node", "/plain")} >= expected,
                                 WAIT_S), client.published_by("mechanism_node", "/plain")
        found = client.published_by("mechanism_node", "/plain")
        assert not [name for name, _ in found if "loads" in name]
    finally:
        assert process.stop(signal.SIGTERM) == 0


# ---------------------------------------------------------------------------------------- topic mode
@pytest.fixture(scope="module")
def relay(start_node: Any, client: Client) -> Any:
    from sensor_msgs.msg import JointState

    listener = client.listen({f"/relay_forces/{t}": typename for t, typename in TOPICS.items()})
    process = start_node("-r", "__ns:=/relay_forces", "-p", f"scene:={SCENE}", "-p", "input_source:=topic",
                         "-p", "topic_epsilon:=difference")
    publisher = client.node.create_publisher(JointState, "/relay_forces/input_joint_states", 10)
    if not client.spin_until(lambda: publisher.get_subscription_count() >= 1, WAIT_S):
        process.kill()
        pytest.fail("mechanism_node did not subscribe to input_joint_states:\n" + process.output())
    probe = 1_000 * NS
    for _ in range(100):
        send(client, publisher, 0.0, OMEGA, probe)
        if client.spin_until(lambda: probe in answered(listener, "joint_states"), 0.2):
            break
    else:
        process.kill()
        pytest.fail("no answer to a probe JointState:\n" + process.output())
    yield process, listener, publisher
    client.node.destroy_publisher(publisher)
    assert process.stop(signal.SIGTERM) == 0


def send(client: Client, publisher: Any, phi: float, omega: float, stamp_ns: int) -> None:
    from builtin_interfaces.msg import Time
    from sensor_msgs.msg import JointState
    from std_msgs.msg import Header

    header = Header(stamp=Time(sec=stamp_ns // NS, nanosec=stamp_ns % NS), frame_id="")
    publisher.publish(JointState(header=header, name=["crank"], position=[phi], velocity=[omega]))
    client.spin_for(0.01)


def answered(listener: Any, topic: str) -> dict[int, bytes]:
    full = f"/relay_forces/{topic}"
    return {stamp(full, d): d for d in listener.by_topic[full]}


def test_topic_mode_effort_follows_the_driven_motion_with_epsilon_from_the_velocities(
        relay: Any, client: Client) -> None:
    """Two messages 20 ms apart: the first answered at ε = 0 (nothing to difference), the second
    at ε = (ω₂ − ω₁)/Δt; the input's effort is on joint_kinematics (joint_states leaves the input
    joint to the driver), and the tree's crank joint carries it on joint_states."""
    process, listener, publisher = relay
    scene = solver.load_scene(SCENE)
    s1, s2 = 5_000 * NS, 5_000 * NS + 20_000_000
    (phi1, w1), (phi2, w2) = (0.7, 2.0), (0.74, 2.5)
    send(client, publisher, phi1, w1, s1)
    send(client, publisher, phi2, w2, s2)
    assert client.spin_until(lambda: {s1, s2} <= set(answered(listener, "pin_loads/B")), WAIT_S), process.output()
    client.spin_for(0.1)
    for s, phi, w, eps in ((s1, phi1, w1, 0.0), (s2, phi2, w2, (w2 - w1) / 0.02)):
        k = scene.solve(phi, omega=w, epsilon=eps)
        jk = decode(answered(listener, "joint_kinematics")[s], TOPICS["joint_kinematics"])
        i = list(jk.joint_names).index("crank")
        assert jk.points[0].accelerations[i] == pytest.approx(eps, rel=1e-12)
        assert jk.points[0].effort[i] == pytest.approx(k.effort("crank"), rel=TOL_REL)
        js = decode(answered(listener, "joint_states")[s], TOPICS["joint_states"])
        assert "crank" not in js.name
        effort = dict(zip(js.name, js.effort))
        assert effort["crank_joint"] == jk.points[0].effort[i]
        tick = {t: answered(listener, t)[s] for t in TOPICS if t.startswith("pin_loads/")}
        check_loads(tick, k)


def test_the_effort_changes_with_the_acceleration_of_the_driver(relay: Any, client: Client) -> None:
    """Same φ, the velocity stepping by 1 rad/s in 10 ms: ε = 100 rad/s², and the links' inertia
    makes the torque the solver gives at that ε (not the one at ε = 0)."""
    _, listener, publisher = relay
    scene = solver.load_scene(SCENE)
    s0 = 7_000 * NS
    stamps = [s0, s0 + 10_000_000, s0 + 20_000_000]
    for s, w in zip(stamps, (2.0, 2.0, 3.0)):
        send(client, publisher, 1.1, w, s)
    assert client.spin_until(lambda: set(stamps) <= set(answered(listener, "joint_kinematics")), WAIT_S)
    for s, w, eps in ((stamps[1], 2.0, 0.0), (stamps[2], 3.0, 100.0)):
        jk = decode(answered(listener, "joint_kinematics")[s], TOPICS["joint_kinematics"])
        effort = jk.points[0].effort[list(jk.joint_names).index("crank")]
        assert effort == pytest.approx(scene.solve(1.1, omega=w, epsilon=eps).effort("crank"), rel=TOL_REL)
    assert scene.solve(1.1, omega=3.0, epsilon=100.0).effort("crank") != pytest.approx(
        scene.solve(1.1, omega=3.0, epsilon=0.0).effort("crank"), rel=1e-3)
