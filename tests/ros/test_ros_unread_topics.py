"""mechanism_node publishes only the topics somebody subscribes to (issue 32: the dynamic node at
1 kHz); the recording keeps every topic. In process: a MechanismNode in a context of its own."""

from __future__ import annotations

import os
import time
from collections.abc import Iterator
from typing import Any

import pytest

pytest.importorskip("rclpy")

pytestmark = pytest.mark.dds

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


def test_a_topic_without_subscribers_is_rendered_but_not_published(context: Any) -> None:
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from sensor_msgs.msg import JointState

    from linkage_ros import node as node_module
    from linkage_ros.node import MechanismNode

    node = MechanismNode(context=context)
    reader = rclpy.create_node("unread_reader", context=context)
    try:
        assert node._publish and all(p is node_module._unread for p in node._publish.values()), node._publish
        reader.create_subscription(JointState, f"{NAMESPACE}/joint_states", lambda msg: None,
                                   QoSProfile(depth=10, reliability=ReliabilityPolicy.RELIABLE))
        publisher = node._topic_publishers["joint_states"]
        deadline = time.monotonic() + 10.0
        while not publisher.get_subscription_count() and time.monotonic() < deadline:
            time.sleep(0.01)
        assert publisher.get_subscription_count() == 1
        node._next_check_ns = 0  # the next tick reads the subscriber counts again
        node._on_timer()
        assert node._publish["joint_states"] == publisher.publish
        assert all(p is node_module._unread for t, p in node._publish.items() if t != "joint_states")
        assert 0 < node._next_check_ns - time.monotonic_ns() <= node_module.SUBSCRIBERS_CHECK_NS
    finally:
        reader.destroy_node()
        node.destroy_node()
