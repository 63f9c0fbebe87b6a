"""mechanism_node in dynamic mode (issue 22) against the kinematic node, like for like.

    .venv/bin/python -m bench.node_dynamic                          # four_bar_loaded, 1 kHz, 3 rounds
    .venv/bin/python -m bench.node_dynamic --rounds 5 --seconds 20 --scene four_bar_loaded
    .venv/bin/python -m bench.node_dynamic --scenes --rounds 2 --seconds 10   # issue 32: four scenes

Two node processes on localhost, one at a time, in a ROS domain of their own (as
:mod:`bench.node_floor`, whose measuring it uses): the ``kinematic`` node (``-p omega:=OMEGA``,
the default mode) and the ``dynamic`` node (``-p mode:=dynamic -p phi0:=0.3 -p omega:=0``: the
scene released from rest, every tick a step of :class:`solver.dynamics.Stepper`), both at
``--rate`` with the same scene, the default executor (EventsExecutor) and this process subscribed
to every topic they publish. Per process and window: CPU (utime + stime, a fraction of a core)
and the ticks delivered (distinct joint_states stamps inside the window over rate × window).
The rounds alternate the order. Prints a line per process and round, the medians, and a
``RESULT`` line against the targets of issue 22: dynamic CPU ≤ 1.3 × the kinematic node's,
≥ 99 % of the ticks delivered.
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
from collections.abc import Sequence
from pathlib import Path

from .node_floor import Counter, _end, _ignore, _print_round, _topics, measure

TARGET_RATIO = 1.3
TARGET_DELIVERED = 0.99


def run(opts: argparse.Namespace) -> list[dict[str, dict[str, float]]]:
    """``[{"kinematic": ..., "dynamic": ...} per round]``."""
    os.environ["ROS_DOMAIN_ID"] = os.environ.get("LINKAGE_ROS_DOMAIN_ID", str(150 + os.getpid() % 50))
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    node_exe = str(Path(sys.prefix) / "bin" / "mechanism_node")
    if not Path(node_exe).is_file():
        node_exe = shutil.which("mechanism_node") or sys.exit("mechanism_node is not installed")
    common = ["-p", f"scene:={opts.scene}", "-p", f"rate_hz:={float(opts.rate)!r}"]
    commands = {
        "kinematic": [node_exe, "--ros-args", "-r", "__ns:=/kinematic", *common, "-p", f"omega:={opts.omega!r}"],
        "dynamic": [node_exe, "--ros-args", "-r", "__ns:=/dynamic", *common, "-p", "mode:=dynamic",
                    "-p", f"phi0:={opts.phi0!r}", "-p", "omega:=0.0"],
    }
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    from linkage_ros.messages import JOINT_STATES
    from linkage_ros.node import make_executor, message_classes

    rclpy.init()
    node = rclpy.create_node("node_dynamic_bench")
    executor = make_executor("events")
    executor.add_node(node)
    counters = {name: Counter() for name in commands}
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
    topics = dict(_topics(opts.scene))
    classes = message_classes(sorted(set(topics.values())))
    for name, counter in counters.items():
        for topic, typename in topics.items():
            node.create_subscription(classes[typename], f"/{name}/{topic}",
                                     counter if topic == JOINT_STATES else _ignore, qos, raw=True)
    root = Path(__file__).resolve().parents[1]
    order = list(commands)
    results: list[dict[str, dict[str, float]]] = []
    process: subprocess.Popen[bytes] | None = None
    try:
        for k in range(opts.rounds):
            row = {}
            for name in order if k % 2 == 0 else order[::-1]:
                process = subprocess.Popen(commands[name], cwd=root, stdout=subprocess.DEVNULL,
                                           stderr=subprocess.DEVNULL, env=dict(os.environ))
                row[name] = measure(process, counters[name], executor, seconds=opts.seconds, warmup=opts.warmup,
                                    rate=opts.rate)
                _end(process)
                process = None
                _print_round("events", k + 1, name, row[name])
            results.append(row)
    finally:
        if process is not None:
            _end(process)
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
        rclpy.try_shutdown()
    return results


#: issue 32: every shipped scene with a motor or an effort input, with its start (tipper: inside
#: its stroke; under zero effort it sinks to the closed end and holds there)
SCENES: dict[str, list[str]] = {
    "engine": ["-p", "omega:=200.0"],
    "four_bar_loaded": ["-p", "phi0:=0.3", "-p", "omega:=0.0"],
    "harvester_finger": ["-p", "omega:=0.0"],
    "tipper": ["-p", "phi0:=1.0", "-p", "omega:=0.0"],
}


def run_scenes(opts: argparse.Namespace) -> dict[str, list[dict[str, float]]]:
    """The dynamic node alone on each of SCENES: ``{scene: [measure per round]}``."""
    os.environ["ROS_DOMAIN_ID"] = os.environ.get("LINKAGE_ROS_DOMAIN_ID", str(150 + os.getpid() % 50))
    os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
    node_exe = str(Path(sys.prefix) / "bin" / "mechanism_node")
    if not Path(node_exe).is_file():
        node_exe = shutil.which("mechanism_node") or sys.exit("mechanism_node is not installed")
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy

    from linkage_ros.messages import JOINT_STATES
    from linkage_ros.node import make_executor, message_classes
    from linkage_ros.runtime import Runtime

    rclpy.init()
    node = rclpy.create_node("node_dynamic_scenes_bench")
    executor = make_executor("events")
    executor.add_node(node)
    qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
    counters = {}
    for scene in SCENES:
        counters[scene] = Counter()
        topics = dict(Runtime({"scene": scene, "phi0": 1.0}).topics if scene == "tipper" else _topics(scene))
        classes = message_classes(sorted(set(topics.values())))
        for topic, typename in topics.items():
            node.create_subscription(classes[typename], f"/{scene}/{topic}",
                                     counters[scene] if topic == JOINT_STATES else _ignore, qos, raw=True)
    root = Path(__file__).resolve().parents[1]
    results: dict[str, list[dict[str, float]]] = {scene: [] for scene in SCENES}
    process: subprocess.Popen[bytes] | None = None
    try:
        for k in range(opts.rounds):
            for scene, extra in SCENES.items():
                argv = [node_exe, "--ros-args", "-r", f"__ns:=/{scene}", "-p", f"scene:={scene}", "-p",
                        "mode:=dynamic", "-p", f"rate_hz:={float(opts.rate)!r}", *extra]
                process = subprocess.Popen(argv, cwd=root, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                           env=dict(os.environ))
                row = measure(process, counters[scene], executor, seconds=opts.seconds, warmup=opts.warmup,
                              rate=opts.rate)
                _end(process)
                process = None
                _print_round("events", k + 1, scene, row)
                results[scene].append(row)
    finally:
        if process is not None:
            _end(process)
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
        rclpy.try_shutdown()
    return results


def scenes_summary(results: dict[str, list[dict[str, float]]]) -> list[str]:
    lines = []
    worst = 1.0
    for scene, rows in results.items():
        got = [r["delivered"] for r in rows]
        cpu = [r["cpu"] for r in rows]
        worst = min(worst, min(got))
        lines.append(f"{scene}: delivered {100 * statistics.median(got):.2f} % [{100 * min(got):.2f}–"
                     f"{100 * max(got):.2f}], CPU {100 * statistics.median(cpu):.1f} % of a core")
    verdict = "PASS" if worst >= TARGET_DELIVERED else "FAIL"
    lines.append(f"RESULT {verdict}: every scene delivered >= {100 * worst:.2f} % of its ticks "
                 f"(target >= {100 * TARGET_DELIVERED:g} %)")
    return lines


def summary(results: Sequence[dict[str, dict[str, float]]]) -> list[str]:
    """The medians [min–max], the per-round ratio dynamic / kinematic, the worst delivered, RESULT."""
    def spread(values: list[float], scale: float = 100.0, fmt: str = ".1f") -> str:
        return f"{scale * statistics.median(values):{fmt}} [{scale * min(values):{fmt}}–{scale * max(values):{fmt}}]"

    kin = [r["kinematic"]["cpu"] for r in results]
    dyn = [r["dynamic"]["cpu"] for r in results]
    ratio = [d / k if k else float("inf") for d, k in zip(dyn, kin)]
    worst = min(r["dynamic"]["delivered"] for r in results)
    worst_kin = min(r["kinematic"]["delivered"] for r in results)
    verdict = "PASS" if statistics.median(ratio) <= TARGET_RATIO and worst >= TARGET_DELIVERED else "FAIL"
    return [
        f"kinematic CPU {spread(kin)} %, dynamic CPU {spread(dyn)} %, dynamic/kinematic {spread(ratio, 1.0, '.2f')}; "
        f"delivered: dynamic ≥ {100 * worst:.2f} %, kinematic ≥ {100 * worst_kin:.2f} %",
        f"RESULT {verdict}: dynamic/kinematic CPU median {statistics.median(ratio):.2f} (target <= {TARGET_RATIO}), "
        f"dynamic ticks delivered >= {100 * worst:.2f} % (target >= {100 * TARGET_DELIVERED:g} %)",
    ]


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.node_dynamic", description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="measurement window, s")
    parser.add_argument("--warmup", type=float, default=3.0, help="seconds before measuring")
    parser.add_argument("--rate", type=float, default=1000.0, help="rate_hz of both nodes")
    parser.add_argument("--rounds", type=int, default=3, help="rounds of kinematic and dynamic")
    parser.add_argument("--scene", default="four_bar_loaded")
    parser.add_argument("--omega", type=float, default=3.0, help="the kinematic node's omega, rad/s")
    parser.add_argument("--phi0", type=float, default=0.3, help="the dynamic node's phi0, rad (released from rest)")
    parser.add_argument("--scenes", action="store_true",
                        help="the dynamic node alone on engine (omega 200), four_bar_loaded, harvester_finger, "
                             "tipper (issue 32)")
    opts = parser.parse_args(argv)
    if opts.scenes:
        print(f"dynamic node on {', '.join(SCENES)} at {opts.rate:g} Hz, {opts.seconds:g} s windows after "
              f"{opts.warmup:g} s warm-up, {opts.rounds} round(s), {os.cpu_count()} cores, load "
              f"{' '.join(f'{v:.2f}' for v in os.getloadavg())}", flush=True)
        for line in scenes_summary(run_scenes(opts)):
            print(line)
        print(f"load {' '.join(f'{v:.2f}' for v in os.getloadavg())}")
        return 0
    print(f"{opts.scene} at {opts.rate:g} Hz, {opts.seconds:g} s windows after {opts.warmup:g} s warm-up, "
          f"{opts.rounds} round(s) of the kinematic and the dynamic node, {os.cpu_count()} cores, "
          "a subscriber on every topic", flush=True)
    for line in summary(run(opts)):
        print(line)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
