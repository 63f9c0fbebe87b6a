"""mechanism_node at a high rate against the floor rclpy allows, side by side in one run.

    .venv/bin/python -m bench.node_floor --seconds 30                  # four_bar, 1000 Hz
    .venv/bin/python -m bench.node_floor --seconds 30 --alternate      # one process at a time

Starts two processes on localhost, in a ROS domain of their own:

* ``node``: the installed ``mechanism_node`` (``-p scene:=SCENE -p rate_hz:=RATE``, default
  topics, namespace ``/node``);
* ``floor``: a minimal rclpy node (this file, ``--floor``) that publishes the very same messages —
  the same topics, types, QoS and per-topic rates (every topic each tick; the markers with the
  paths and the diagnostics once a second) — as bytes rendered once before it starts, from a
  plain timer at RATE (namespace ``/floor``). It is what publishing alone costs in rclpy.

Executors: the node spins rclpy's EventsExecutor by default (``linkage_ros.node.make_executor``),
the floor the SingleThreadedExecutor that ``rclpy.spin`` uses (the plain rclpy node).
``--node-executor`` and ``--floor-executor`` (``events`` | ``single``) choose; with the same
executor on both sides the ratio isolates the node's own work per tick.

This process subscribes to both ``joint_states`` (raw bytes, reliable; EventsExecutor, so that it
keeps up) and counts what arrives.
After ``--warmup`` seconds it measures, over ``--seconds``: each process's CPU (utime + stime from
``/proc/PID/stat``, as a fraction of one core) and the ticks delivered (distinct stamps received /
RATE × the stamp span; for the floor, whose stamps never change, messages received / RATE ×
the window). ``--alternate`` runs node and floor one after the other instead of together (on a
2-core machine two 1 kHz publishers and a subscriber compete for the cores). ``--all-topics``
subscribes to every topic of both, not only ``joint_states`` (each matched reliable reader adds
to what a publish costs, in the node and in the floor alike).

Prints one line per process and a ``RESULT`` line: node CPU / floor CPU (target ≤ 1.25) and the
node's delivered ticks (target ≥ 99 %).
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

NS = 1_000_000_000
T0 = 1_700_000_000 * NS
TARGET_RATIO = 1.25
TARGET_DELIVERED = 0.99


# ------------------------------------------------------------------------------- the floor node
def floor_main(scene: str, rate: float, ros_args: Sequence[str], executor_kind: str) -> int:
    """A minimal rclpy node: pre-rendered bytes of the same topics, published from a timer."""
    import rclpy
    from rclpy.node import Node
    from rclpy.signals import SignalHandlerOptions

    from linkage_ros.node import make_executor, message_classes, qos_profile
    from linkage_ros.runtime import Runtime

    runtime = Runtime({"scene": scene, "rate_hz": rate})
    once_a_second = runtime.tick(T0)  # paths on the markers, diagnostics
    every_tick = runtime.tick(T0 + int(NS / rate))  # the per-tick topics
    types = dict(runtime.topics)
    stop = [False]

    def request_stop(signum: int, frame: Any) -> None:
        stop[0] = True

    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, request_stop)
    rclpy.init(args=["floor", *ros_args], signal_handler_options=SignalHandlerOptions.NO)
    try:
        node = Node("floor")
        classes = message_classes(sorted(set(types.values())))
        publishers = {t: node.create_publisher(classes[types[t]], t, qos_profile()) for t in types}
        per_second = max(int(round(rate)), 1)
        count = [0]

        def on_timer() -> None:
            messages = once_a_second if count[0] % per_second == 0 else every_tick
            count[0] += 1
            for topic, data in messages:
                publishers[topic].publish(data)

        node.create_timer(1.0 / rate, on_timer)
        executor = make_executor(executor_kind)
        executor.add_node(node)
        while not stop[0] and executor.context.ok():
            executor.spin_once(timeout_sec=0.1)
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
    finally:
        rclpy.try_shutdown()
    return 0


# ------------------------------------------------------------------------------- measuring
def cpu_seconds(pid: int) -> float:
    """utime + stime of a process (all its threads), s."""
    text = Path(f"/proc/{pid}/stat").read_text()
    fields = text[text.rindex(")") + 2:].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


class Counter:
    def __init__(self) -> None:
        self.stamps: list[int] = []
        self.active = False

    def __call__(self, data: bytes) -> None:
        if self.active:
            self.stamps.append(int.from_bytes(data[4:8], "little", signed=True) * NS
                               + int.from_bytes(data[8:12], "little"))


def measure(names: Sequence[str], processes: dict[str, subprocess.Popen[bytes]],
            counters: dict[str, Counter], executor: Any, *, seconds: float, rate: float,
            warmup: float) -> dict[str, dict[str, float]]:
    def spin(duration: float) -> None:
        end = time.monotonic() + duration
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.01)

    spin(warmup)
    for name in names:
        counters[name].active = True
    cpu0 = {n: cpu_seconds(processes[n].pid) for n in names}
    wall0 = time.monotonic()
    spin(seconds)
    wall = time.monotonic() - wall0
    cpu1 = {n: cpu_seconds(processes[n].pid) for n in names}
    out = {}
    for name in names:
        counters[name].active = False
        stamps = counters[name].stamps
        distinct = sorted(set(stamps))
        if name == "node" and len(distinct) > 1:
            expected = (distinct[-1] - distinct[0]) * rate / NS + 1
            delivered = len(distinct) / expected
        else:
            delivered = len(stamps) / (rate * wall)
        out[name] = {"cpu": (cpu1[name] - cpu0[name]) / wall, "delivered": delivered,
                     "received": float(len(stamps)), "window_s": wall}
    return out


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.node_floor", description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="measurement window, s")
    parser.add_argument("--warmup", type=float, default=3.0, help="seconds before measuring")
    parser.add_argument("--rate", type=float, default=1000.0, help="rate_hz of both publishers")
    parser.add_argument("--scene", default="four_bar")
    parser.add_argument("--alternate", action="store_true", help="node and floor one after the other")
    parser.add_argument("--all-topics", action="store_true", help="subscribe to every topic, not only joint_states")
    parser.add_argument("--node-executor", choices=("events", "single"), default="events")
    parser.add_argument("--floor-executor", choices=("events", "single"), default="single")
    parser.add_argument("--floor", action="store_true", help=argparse.SUPPRESS)
    opts, ros_args = parser.parse_known_args(argv)
    if opts.floor:
        return floor_main(opts.scene, opts.rate, ros_args, opts.floor_executor)
    if ros_args:
        parser.error(f"unrecognised arguments: {' '.join(ros_args)}")

    os.environ.setdefault("ROS_DOMAIN_ID", str(150 + os.getpid() % 50))
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    node_exe = str(Path(sys.prefix) / "bin" / "mechanism_node")
    if not Path(node_exe).is_file():
        node_exe = shutil.which("mechanism_node") or sys.exit("mechanism_node is not installed")
    commands = {
        "node": [node_exe, "--ros-args", "-r", "__ns:=/node", "-p", f"scene:={opts.scene}",
                 "-p", f"rate_hz:={float(opts.rate)!r}"],
        "floor": [sys.executable, "-m", "bench.node_floor", "--floor", "--scene", opts.scene,
                  "--rate", repr(float(opts.rate)), "--floor-executor", opts.floor_executor,
                  "--ros-args", "-r", "__ns:=/floor"],
    }

    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    from linkage_ros.messages import topic_types
    from linkage_ros.node import make_executor, message_classes
    from linkage_ros.runtime import Runtime

    rclpy.init()
    node = rclpy.create_node("node_floor_bench")
    executor = make_executor("events")  # the subscriber must keep up with two 1 kHz publishers
    executor.add_node(node)
    counters = {name: Counter() for name in commands}
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
    topics = dict(topic_types(Runtime({"scene": opts.scene}).engine))
    classes = message_classes(sorted(set(topics.values())))
    for name, counter in counters.items():
        for topic, typename in topics.items():
            if topic == "joint_states":
                node.create_subscription(classes[typename], f"/{name}/{topic}", counter, qos, raw=True)
            elif opts.all_topics:
                node.create_subscription(classes[typename], f"/{name}/{topic}", lambda data: None, qos, raw=True)
    groups = [["node"], ["floor"]] if opts.alternate else [["node", "floor"]]
    results: dict[str, dict[str, float]] = {}
    processes: dict[str, subprocess.Popen[bytes]] = {}
    root = Path(__file__).resolve().parents[1]
    try:
        for group in groups:
            for name in group:
                env = {**os.environ, "LINKAGE_ROS_EXECUTOR": opts.node_executor}
                processes[name] = subprocess.Popen(commands[name], cwd=root, stdout=subprocess.DEVNULL,
                                                   stderr=subprocess.DEVNULL, env=env)
            results.update(measure(group, processes, counters, executor, seconds=opts.seconds,
                                   rate=opts.rate, warmup=opts.warmup))
            for name in group:
                processes[name].send_signal(signal.SIGTERM)
                processes[name].wait(timeout=15)
    finally:
        for process in processes.values():
            if process.poll() is None:
                process.kill()
                process.wait(timeout=15)
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
        rclpy.try_shutdown()

    mode = "one after the other" if opts.alternate else "side by side"
    print(f"{opts.scene} at {opts.rate:g} Hz, {opts.seconds:g} s after {opts.warmup:g} s warm-up, {mode}, "
          f"{os.cpu_count()} cores, subscriber on {'every topic' if opts.all_topics else 'joint_states'}; "
          f"executors: node {opts.node_executor}, floor {opts.floor_executor}")
    for name in ("node", "floor"):
        r = results[name]
        print(f"  {name:5s}  CPU {100 * r['cpu']:6.1f} % of a core   delivered {100 * r['delivered']:6.2f} %"
              f"   ({int(r['received'])} joint_states in {r['window_s']:.1f} s)")
    ratio = results["node"]["cpu"] / results["floor"]["cpu"] if results["floor"]["cpu"] else float("inf")
    delivered = results["node"]["delivered"]
    verdict = "PASS" if ratio <= TARGET_RATIO and delivered >= TARGET_DELIVERED else "FAIL"
    print(f"RESULT {verdict}: node/floor CPU = {ratio:.3f} (target <= {TARGET_RATIO}), "
          f"node ticks delivered = {100 * delivered:.2f} % (target >= {100 * TARGET_DELIVERED:g} %)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
