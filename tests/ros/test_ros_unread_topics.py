"""mechanism_node publishes only the topics somebody subscribes to (every one for its first 2 s
and the run's first 2 s), and an ordinary tick renders
only those (issue 32: the dynamic node at 1 kHz); the recording keeps every topic. In process: a
MechanismNode in a context of its own, and the Runtime alone."""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("rclpy")

NAMESPACE = f"/unread_{os.getpid()}"


@pytest.fixture()
def context() -> Iterator[Any]:
    import rclpy
    from rclpy.context import Context
    from rclpy.signals import SignalHandlerOptions

    ctx = Context()
    rclpy.init(context=ctx, args=["--ros-args", "-r", f"__ns:={NAMESPACE}", "-p", "scene:=four_bar_loaded",
                                  "-p", "mode:=dynamic"], signal_handler_options=SignalHandlerOptions.NO)
    try:
        yield ctx
    finally:
        ctx.try_shutdown()


@pytest.mark.dds
def test_a_topic_without_subscribers_is_not_published(context: Any) -> None:
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import JointState

    from linkage_ros import node as node_module
    from linkage_ros.node import MechanismNode

    node = MechanismNode(context=context)
    reader = rclpy.create_node("unread_reader", context=context)
    try:
        # a new publisher is published for FRESH_PUBLISHER_NS whatever its count (discovery runs meanwhile)
        assert node._publish and not any(p is node_module._unread for p in node._publish.values())
        node._fresh.clear()
        node._check_subscribers()
        assert all(p is node_module._unread for p in node._publish.values()), node._publish
        reader.create_subscription(JointState, f"{NAMESPACE}/joint_states", lambda msg: None,
                                   QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
        publisher = node._topic_publishers["joint_states"]
        deadline = time.monotonic() + 10.0
        while not publisher.get_subscription_count() and time.monotonic() < deadline:
            time.sleep(0.01)
        assert publisher.get_subscription_count() == 1
        node._on_timer()  # the run's first tick: every topic published for FRESH_PUBLISHER_NS again
        assert not any(p is node_module._unread for p in node._publish.values())
        assert not node._first_tick and min(node._fresh.values()) > time.monotonic_ns()
        node._fresh.clear()
        node._next_check_ns = 0  # the next tick reads the subscriber counts again
        before = time.monotonic_ns()
        node._on_timer()
        after = time.monotonic_ns()
        assert node._publish["joint_states"] == publisher.publish
        assert all(p is node_module._unread for t, p in node._publish.items() if t != "joint_states")
        check = node_module.SUBSCRIBERS_CHECK_NS
        assert before + check <= node._next_check_ns <= after + check
        assert node.runtime._wanted == frozenset({"joint_states"})
    finally:
        reader.destroy_node()
        node.destroy_node()


NS = 1_000_000_000
T0 = 1_700_000_000 * NS


class _Recorder:
    def __init__(self) -> None:
        self.ticks: list[list[str]] = []

    def write_serialized(self, stamp_ns: int, messages: Any) -> None:
        self.ticks.append([topic for topic, _ in messages])

    def close(self) -> None:
        pass


def test_an_ordinary_tick_renders_the_topics_read_and_the_same_bytes() -> None:
    from linkage_ros.runtime import Runtime

    settings = {"scene": "harvester_finger", "rate_hz": 1000.0, "omega": 2.0}
    every, some = Runtime(settings), Runtime(settings)
    all_topics = [topic for topic, _ in every.topics]
    some.publish_only({"markers"})  # (joint_states comes with any subset: it carries the guards' verdict)
    seen = []
    for k in range(2500):
        stamp = T0 + k * NS // 1000
        full, part = every.tick(stamp), some.tick(stamp)
        got = [topic for topic, _ in part]
        seen.append(got)
        if len(got) < len(full):
            assert got == ["joint_states", "markers"] and part == [m for m in full if m[0] in got], k
        else:  # the Frame path's ticks (the first, path markers and diagnostics once a second): every topic
            assert part == full, k
    subsets = sum(1 for got in seen if got == ["joint_states", "markers"])
    assert subsets >= 2490 and "pin_loads/A" not in seen[-1] and len(all_topics) > 10
    some.publish_only(None)
    assert [t for t, _ in some.tick(T0 + 2500 * NS // 1000)] == [t for t, _ in every.tick(T0 + 2500 * NS // 1000)]
    some.publish_only(set())
    recorder = _Recorder()
    some.recorder = recorder  # a recording gets every topic
    some.tick(T0 + 2501 * NS // 1000)
    some.recorder = None
    assert [t for t, _ in some.tick(T0 + 2502 * NS // 1000)] == ["joint_states"]
    assert len(recorder.ticks) == 1 and len(recorder.ticks[0]) >= len(seen[-1]) and "joint_states" in recorder.ticks[0]
    assert set(recorder.ticks[0]) >= {t for t in all_topics if t != "diagnostics"}


def test_the_dynamic_node_s_ordinary_tick_renders_joint_states_alone() -> None:
    from linkage_ros.runtime import Runtime

    runtime = Runtime({"scene": "engine", "mode": "dynamic", "rate_hz": 1000.0, "omega": 200.0})
    runtime.publish_only(set())
    lengths = [len(runtime.tick(T0 + k * NS // 1000)) for k in range(1200)]
    assert lengths.count(1) >= 1190 and max(lengths) == len(runtime.topics)


def test_a_held_law_s_ticks_count_in_its_tick_share() -> None:
    from linkage_ros.runtime import Runtime

    runtime = Runtime({"scene": "tipper", "mode": "dynamic", "rate_hz": 1000.0, "phi0": 1.0, "omega": 0.0})
    law = runtime.engine.motion
    for k in range(2100):  # it reaches the closed end of its stroke within 0.3 s and holds there
        runtime.tick(T0 + k * NS // 1000)
    assert law._held and law.tick_share == 1.0 and law.behind == ""
    for k in range(2100, 4300, 2):  # every other tick
        runtime.tick(T0 + k * NS // 1000)
    assert law.tick_share == 0.5  # (a hold computes nothing: no factor in the message)
    assert law.behind == "dynamics fall behind real time: 50.0 % of the 1000 Hz ticks over the last 1.00 s"


def test_the_path_markers_are_drawn_only_while_markers_are_read_or_recorded() -> None:
    """Issue 32: the paths (markers serialised the generic way, 2–6 ms once a second: more than a
    1 kHz period) are not drawn while nobody reads markers; a reader matched later gets them."""
    from linkage_ros.runtime import Runtime

    settings = {"scene": "four_bar_loaded", "mode": "dynamic", "rate_hz": 1000.0, "phi0": 0.3}
    read, unread = Runtime(settings), Runtime(settings)
    read.publish_only({"markers"})
    unread.publish_only(set())

    def markers(runtime: Runtime, k: int) -> int:
        return len(dict(runtime.tick(T0 + k * NS // 1000)).get("markers", b""))

    for k in range(1000):
        markers(read, k), markers(unread, k)
    with_paths, without = markers(read, 1000), markers(unread, 1000)  # the diagnostics tick, a second in
    assert with_paths > 2 * without > 0
    unread.publish_only({"markers"})  # a reader comes: the paths on its next tick
    assert markers(unread, 1001) == with_paths
    unread.publish_only(set())
    unread.recorder = _Recorder()  # a recording gets them too
    assert markers(unread, 2001) == markers(read, 2001) == with_paths
