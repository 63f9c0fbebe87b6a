"""mechanism_node at a high rate against its floor, like for like, with both executors.

    .venv/bin/python -m bench.node_floor                                   # both executors, 3 rounds
    .venv/bin/python -m bench.node_floor --executor events --rounds 5 --seconds 30
    .venv/bin/python -m bench.node_floor --executor events --also before=/tmp/old   # paired A/B

Two processes on localhost, in a ROS domain of their own (``LINKAGE_ROS_DOMAIN_ID``, else one
from this process's id), one at a time:

* ``node``: the installed ``mechanism_node`` (``-p scene:=SCENE -p rate_hz:=RATE``, default
  topics, namespace ``/node``);
* ``floor``: a minimal rclpy node (this file, ``--floor``) that publishes the very same bytes on
  the same topics — same types, QoS and per-topic rates (every per-tick topic each tick; the path
  markers and diagnostics once a second) — rendered once, before it starts, by the node's own
  :class:`~linkage_ros.runtime.Runtime`, from a plain timer at RATE (namespace ``/floor``). Its
  ``joint_states`` carry the tick's stamp (8 bytes written per tick, as the node stamps its
  messages), so that both sides are counted the same way. It is what publishing alone costs.

Like for like: both processes spin the same executor (``--executor``: ``events``, rclpy's
EventsExecutor, the node's default; ``single``, the SingleThreadedExecutor of ``rclpy.spin``; or
``both``), and this process subscribes to *every* topic the running process publishes (raw
bytes, reliable, depth 1000: each matched reliable reader adds to what a publish costs). Node and
floor run back to back, ``--rounds`` times per executor; other load on the machine shows as the
spread between rounds.

``--also LABEL=DIR`` (repeatable) adds, in every round, the node run from another copy of the
package (``PYTHONPATH=DIR``: DIR holds a ``linkage_ros`` folder, e.g. a snapshot taken before a
change; the solver stays this tree's), in namespace ``/node_LABEL``: a paired before/after
comparison under the same load. The processes of a round run one at a time; odd rounds run them
in reverse order, so that drifting load favours neither.

Measured over ``--seconds`` after ``--warmup`` s, for each process: its CPU (utime + stime from
``/proc/PID/stat``, as a fraction of one core) and the ticks delivered: the distinct stamps of
the ``joint_states`` received during the window whose stamps lie in the window (wall clock, the
node's clock), over RATE × the window. A backlog of older ticks delivered late is not counted,
nor are ticks delivered after the window. Prints one line per process and round, then per
executor the median and range of the CPU, of node / floor (per round) and the worst delivered,
and a ``RESULT`` line against the targets (node CPU ≤ 1.15 × floor, ≥ 99 % of ticks delivered).
"""

from __future__ import annotations

import argparse
import os
import shutil
import signal
import statistics
import struct
import subprocess
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

NS = 1_000_000_000
T0 = 1_700_000_000 * NS
TARGET_RATIO = 1.15
TARGET_DELIVERED = 0.99
EXECUTORS = ("events", "single")
_STAMP = struct.Struct("<iI")  # header.stamp right after the 4-byte CDR encapsulation header


# ------------------------------------------------------------------------------- the floor node
def floor_messages(scene: str, rate: float) -> tuple[list[tuple[str, bytes]], list[tuple[str, bytes]]]:
    """The node's own bytes: a tick with the path markers and diagnostics (sent once a second),
    and an ordinary tick (every other tick)."""
    from linkage_ros.runtime import Runtime

    runtime = Runtime({"scene": scene, "rate_hz": rate})
    return runtime.tick(T0), runtime.tick(T0 + int(NS / rate))


def stamped(data: bytes, stamp_ns: int) -> bytes:
    """``data`` (a message whose header comes first) with its stamp set to ``stamp_ns``."""
    return data[:4] + _STAMP.pack(*divmod(stamp_ns, NS)) + data[12:]


def floor_callback(publishers: dict[str, Any], messages: tuple[list[tuple[str, bytes]], list[tuple[str, bytes]]],
                   rate: float, count: list[int]) -> Callable[[], None]:
    """The floor's timer callback: ``messages`` (:func:`floor_messages`) published on
    ``publishers`` (by topic), the first once a second, joint_states stamped now; ``count[0]``
    counts the ticks."""
    from linkage_ros.messages import JOINT_STATES

    rows = [[(publishers[t], t == JOINT_STATES, data) for t, data in tick] for tick in messages]
    per_second = max(int(round(rate)), 1)

    def on_timer() -> None:
        row = rows[0] if count[0] % per_second == 0 else rows[1]
        count[0] += 1
        now = time.time_ns()
        for publisher, stamp, data in row:
            publisher.publish(stamped(data, now) if stamp else data)

    return on_timer


def floor_main(scene: str, rate: float, ros_args: Sequence[str], executor_kind: str) -> int:
    """A minimal rclpy node: pre-rendered bytes of the same topics, published from a timer."""
    import rclpy
    from rclpy.node import Node
    from rclpy.signals import SignalHandlerOptions

    from linkage_ros.node import make_executor, message_classes, qos_profile

    once_a_second, every_tick = floor_messages(scene, rate)
    types = dict(_topics(scene))
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
        node.create_timer(1.0 / rate, floor_callback(publishers, (once_a_second, every_tick), rate, [0]))
        executor = make_executor(executor_kind)
        executor.add_node(node)
        while not stop[0] and executor.context.ok():
            executor.spin_once(timeout_sec=0.1)
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
    finally:
        rclpy.try_shutdown()
    return 0


def _topics(scene: str) -> list[tuple[str, str]]:
    from linkage_ros.runtime import Runtime

    return Runtime({"scene": scene}).topics


# ------------------------------------------------------------------------------- measuring
def cpu_seconds(pid: int) -> float:
    """utime + stime of a process (all its threads), s."""
    text = Path(f"/proc/{pid}/stat").read_text()
    fields = text[text.rindex(")") + 2:].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


class Counter:
    """The stamps of the joint_states received while :attr:`active`."""

    def __init__(self) -> None:
        self.stamps: list[int] = []
        self.active = False

    def __call__(self, data: bytes) -> None:
        if self.active:
            sec, nsec = _STAMP.unpack_from(data, 4)
            self.stamps.append(sec * NS + nsec)


def delivered(stamps: Sequence[int], start_ns: int, stop_ns: int, rate: float) -> float:
    """Distinct stamps in ``[start_ns, stop_ns)`` over the ticks a ``rate`` Hz timer has there."""
    inside = {s for s in stamps if start_ns <= s < stop_ns}
    return len(inside) / (rate * (stop_ns - start_ns) / NS)


def measure(process: subprocess.Popen[bytes], counter: Counter, executor: Any, *, seconds: float,
            warmup: float, rate: float) -> dict[str, float]:
    """CPU (fraction of a core) and delivered ticks of ``process`` over one window."""
    def spin(duration: float) -> None:
        end = time.monotonic() + duration
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.01)

    spin(warmup)
    counter.stamps.clear()
    counter.active = True
    cpu0, wall0, start_ns = cpu_seconds(process.pid), time.monotonic(), time.time_ns()
    spin(seconds)
    cpu1, wall1, stop_ns = cpu_seconds(process.pid), time.monotonic(), time.time_ns()
    counter.active = False
    return {"cpu": (cpu1 - cpu0) / (wall1 - wall0), "delivered": delivered(counter.stamps, start_ns, stop_ns, rate),
            "received": float(len(counter.stamps)), "window_s": wall1 - wall0}


def run(opts: argparse.Namespace) -> dict[str, list[dict[str, dict[str, float]]]]:
    """``{executor: [{"node": ..., "floor": ...} per round]}``."""
    os.environ["ROS_DOMAIN_ID"] = os.environ.get("LINKAGE_ROS_DOMAIN_ID", str(150 + os.getpid() % 50))
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    node_exe = str(Path(sys.prefix) / "bin" / "mechanism_node")
    if not Path(node_exe).is_file():
        node_exe = shutil.which("mechanism_node") or sys.exit("mechanism_node is not installed")
    rate = repr(float(opts.rate))
    commands = {  # argv by executor (the node reads LINKAGE_ROS_EXECUTOR)
        "node": lambda kind: [node_exe, "--ros-args", "-r", "__ns:=/node", "-p", f"scene:={opts.scene}",
                              "-p", f"rate_hz:={rate}"],
        "floor": lambda kind: [sys.executable, "-m", "bench.node_floor", "--floor", "--scene", opts.scene,
                               "--rate", rate, "--floor-executor", kind, "--ros-args", "-r", "__ns:=/floor"],
    }
    paths: dict[str, str] = {}  # extra node variants: name -> PYTHONPATH
    for label, where in variants(opts.also):
        name = f"node_{label}"
        paths[name] = where
        commands[name] = (lambda ns: lambda kind: [node_exe, "--ros-args", "-r", f"__ns:=/{ns}", "-p",
                                                   f"scene:={opts.scene}", "-p", f"rate_hz:={rate}"])(name)
    order = ["node", *paths, "floor"]
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    from linkage_ros.messages import JOINT_STATES
    from linkage_ros.node import make_executor, message_classes

    rclpy.init()
    node = rclpy.create_node("node_floor_bench")
    executor = make_executor("events")  # the subscriber must keep up with 10-odd topics at 1 kHz
    executor.add_node(node)
    counters = {name: Counter() for name in commands}
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
    topics = dict(_topics(opts.scene))
    classes = message_classes(sorted(set(topics.values())))
    for name, counter in counters.items():  # every topic, both sides
        for topic, typename in topics.items():
            callback = counter if topic == JOINT_STATES else _ignore
            node.create_subscription(classes[typename], f"/{name}/{topic}", callback, qos, raw=True)
    root = Path(__file__).resolve().parents[1]
    results: dict[str, list[dict[str, dict[str, float]]]] = {}
    process: subprocess.Popen[bytes] | None = None
    try:
        for kind in EXECUTORS if opts.executor == "both" else (opts.executor,):
            results[kind] = []
            for k in range(opts.rounds):
                row = {}
                for name in order if k % 2 == 0 else order[::-1]:
                    env = {**os.environ, "LINKAGE_ROS_EXECUTOR": kind}
                    if name in paths:
                        env["PYTHONPATH"] = os.pathsep.join(filter(None, (paths[name], env.get("PYTHONPATH"))))
                    process = subprocess.Popen(commands[name](kind), cwd=root, stdout=subprocess.DEVNULL,
                                               stderr=subprocess.DEVNULL, env=env)
                    row[name] = measure(process, counters[name], executor, seconds=opts.seconds,
                                        warmup=opts.warmup, rate=opts.rate)
                    _end(process)
                    process = None
                    _print_round(kind, len(results[kind]) + 1, name, row[name])
                results[kind].append(row)
    finally:
        if process is not None:
            _end(process)
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
        rclpy.try_shutdown()
    return results


def variants(specs: Sequence[str] | None) -> list[tuple[str, str]]:
    """``[(label, dir)]`` of ``--also LABEL=DIR`` options (SystemExit for a malformed one)."""
    out = []
    for spec in specs or ():
        label, sep, where = spec.partition("=")
        if not sep or not label.isidentifier() or not (Path(where) / "linkage_ros").is_dir():
            sys.exit(f"--also {spec!r}: expected LABEL=DIR, LABEL a name, DIR holding a linkage_ros folder")
        out.append((label, str(Path(where).resolve())))
    return out


def _ignore(data: bytes) -> None:
    pass


def _end(process: subprocess.Popen[bytes]) -> None:
    process.send_signal(signal.SIGTERM)
    try:
        process.wait(timeout=15)
    except subprocess.TimeoutExpired:
        process.kill()
        process.wait(timeout=15)


def _print_round(kind: str, k: int, name: str, r: dict[str, float]) -> None:
    print(f"  {kind:6s} round {k}  {name:5s}  CPU {100 * r['cpu']:5.1f} % of a core   "
          f"delivered {100 * r['delivered']:6.2f} %   ({int(r['received'])} joint_states in {r['window_s']:.1f} s)",
          flush=True)


def summary(results: dict[str, list[dict[str, dict[str, float]]]]) -> list[str]:
    """Per executor: median [min–max] of node and floor CPU and of their per-round ratio, the
    worst delivered of each, and a RESULT line; then a line per ``--also`` variant (its CPU, its
    ratio to the floor and to the node, per round)."""
    lines = []

    def spread(values: list[float], scale: float = 100.0, fmt: str = ".1f") -> str:
        return (f"{scale * statistics.median(values):{fmt}} [{scale * min(values):{fmt}}–"
                f"{scale * max(values):{fmt}}]")

    for kind, rounds in results.items():
        node = [r["node"]["cpu"] for r in rounds]
        floor = [r["floor"]["cpu"] for r in rounds]
        ratio = [n / f if f else float("inf") for n, f in zip(node, floor)]
        worst = min(r["node"]["delivered"] for r in rounds)
        worst_floor = min(r["floor"]["delivered"] for r in rounds)
        lines.append(f"{kind}: node CPU {spread(node)} %, floor CPU {spread(floor)} %, node/floor "
                     f"{spread(ratio, 1.0, '.2f')}; delivered: node ≥ {100 * worst:.2f} %, "
                     f"floor ≥ {100 * worst_floor:.2f} %")
        verdict = "PASS" if statistics.median(ratio) <= TARGET_RATIO and worst >= TARGET_DELIVERED else "FAIL"
        lines.append(f"RESULT {kind} {verdict}: node/floor CPU median {statistics.median(ratio):.2f} "
                     f"(target <= {TARGET_RATIO}), node ticks delivered >= {100 * worst:.2f} % "
                     f"(target >= {100 * TARGET_DELIVERED:g} %)")
        for name in [n for n in rounds[0] if n not in ("node", "floor")]:
            cpu = [r[name]["cpu"] for r in rounds]
            to_floor = [c / f if f else float("inf") for c, f in zip(cpu, floor)]
            to_node = [c / n if n else float("inf") for c, n in zip(cpu, node)]
            lines.append(f"{kind}: {name} CPU {spread(cpu)} %, {name}/floor {spread(to_floor, 1.0, '.2f')}, "
                         f"{name}/node {spread(to_node, 1.0, '.2f')}; delivered ≥ "
                         f"{100 * min(r[name]['delivered'] for r in rounds):.2f} %")
    return lines


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.node_floor", description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="measurement window, s")
    parser.add_argument("--warmup", type=float, default=3.0, help="seconds before measuring")
    parser.add_argument("--rate", type=float, default=1000.0, help="rate_hz of both publishers")
    parser.add_argument("--rounds", type=int, default=3, help="node-then-floor rounds per executor")
    parser.add_argument("--scene", default="four_bar")
    parser.add_argument("--executor", choices=(*EXECUTORS, "both"), default="both")
    parser.add_argument("--also", action="append", metavar="LABEL=DIR",
                        help="also run the node from DIR/linkage_ros in every round (paired A/B)")
    parser.add_argument("--floor", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--floor-executor", choices=EXECUTORS, default="events", help=argparse.SUPPRESS)
    opts, ros_args = parser.parse_known_args(argv)
    if opts.floor:
        return floor_main(opts.scene, opts.rate, ros_args, opts.floor_executor)
    if ros_args:
        parser.error(f"unrecognised arguments: {' '.join(ros_args)}")
    print(f"{opts.scene} at {opts.rate:g} Hz, {opts.seconds:g} s windows after {opts.warmup:g} s warm-up, "
          f"{opts.rounds} round(s) of node then floor per executor, {os.cpu_count()} cores, "
          f"{len(opts.also or ())} extra node variant(s), "
          "a subscriber on every topic", flush=True)
    for line in summary(run(opts)):
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
