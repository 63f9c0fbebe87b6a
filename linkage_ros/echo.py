"""linkage-echo: print the messages of one topic, like ``ros2 topic echo`` (which is not on PyPI).

    linkage-echo joint_states                    # every message, YAML-like, separated by ---
    linkage-echo points/B/position --count 5
    linkage-echo diagnostics --timeout 10 --ros-args -r __ns:=/robot

The topic's type is looked up in the ROS graph (it waits up to ``--timeout`` seconds for a
publisher). The subscription is best effort, so it receives from reliable and best-effort
publishers alike. Exit status: 0 after ``--count`` messages or Ctrl-C, 1 when no publisher of the
topic appeared in time.
"""

from __future__ import annotations

import argparse
import array
import importlib
import os
import signal
import sys
import time
from collections.abc import Sequence
from typing import Any, TextIO

__all__ = ["format_message", "main"]

WAIT_STEP_S = 0.1


def format_message(msg: Any, indent: str = "") -> str:
    """A YAML-like text of an rclpy message (nested messages indented, sequences inline when
    they hold numbers)."""
    lines: list[str] = []
    for name in msg.get_fields_and_field_types():
        value = getattr(msg, name)
        if hasattr(value, "get_fields_and_field_types"):
            lines.append(f"{indent}{name}:")
            lines.append(format_message(value, indent + "  "))
        elif isinstance(value, (list, tuple, array.array)) and value and hasattr(
            value[0], "get_fields_and_field_types"
        ):
            lines.append(f"{indent}{name}:")
            for item in value:
                body = format_message(item, indent + "  ")
                lines.append(f"{indent}- {body[len(indent) + 2:]}")
        elif isinstance(value, (list, tuple, array.array)):
            lines.append(f"{indent}{name}: [{', '.join(repr(v) for v in value)}]")
        else:
            lines.append(f"{indent}{name}: {value!r}")
    return "\n".join(lines)


def _message_class(typename: str) -> Any:
    package, _, name = typename.split("/")
    return getattr(importlib.import_module(f"{package}.msg"), name)


def main(argv: Sequence[str] | None = None, *, out: TextIO | None = None) -> int:
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from rclpy.signals import SignalHandlerOptions

    stream = out or sys.stdout
    argv = list(sys.argv[1:] if argv is None else argv)
    ros_args = argv[argv.index("--ros-args"):] if "--ros-args" in argv else []
    mine = argv[: len(argv) - len(ros_args)]
    parser = argparse.ArgumentParser(prog="linkage-echo", description=__doc__.split("\n")[0])
    parser.add_argument("topic", help="topic name (relative names resolve in --ros-args' namespace)")
    parser.add_argument("--count", type=int, default=0, help="stop after N messages (default 0: never)")
    parser.add_argument("--timeout", type=float, default=5.0, help="seconds to wait for a publisher (default 5)")
    opts = parser.parse_args(mine)
    stopped = [False]

    def stop(signum: int, frame: Any) -> None:
        stopped[0] = True

    previous = {sig: signal.signal(sig, stop) for sig in (signal.SIGINT, signal.SIGTERM)}
    rclpy.init(args=["linkage-echo", *ros_args], signal_handler_options=SignalHandlerOptions.NO)
    try:
        node = rclpy.create_node("linkage_echo")
        topic = node.resolve_topic_name(opts.topic)
        deadline = time.monotonic() + opts.timeout
        typename = None
        while typename is None and not stopped[0]:
            found = dict(node.get_topic_names_and_types()).get(topic)
            if found:
                typename = found[0]
            elif time.monotonic() > deadline:
                print(f"linkage-echo: no publisher of {topic} within {opts.timeout:g} s", file=sys.stderr)
                return 1
            else:
                rclpy.spin_once(node, timeout_sec=WAIT_STEP_S)
        if typename is None:
            return 0
        seen = [0]

        def show(msg: Any) -> None:
            seen[0] += 1
            print(format_message(msg), file=stream)
            print("---", file=stream, flush=True)

        qos = QoSProfile(depth=100, reliability=ReliabilityPolicy.BEST_EFFORT)
        node.create_subscription(_message_class(typename), topic, show, qos)
        try:
            while not stopped[0] and (opts.count <= 0 or seen[0] < opts.count):
                rclpy.spin_once(node, timeout_sec=WAIT_STEP_S)
        except BrokenPipeError:  # e.g. | head: the reader has gone
            sys.stdout = open(os.devnull, "w")  # nothing more is printed
        return 0
    finally:
        rclpy.try_shutdown()
        for sig, handler in previous.items():
            signal.signal(sig, handler)


if __name__ == "__main__":
    raise SystemExit(main())
