"""mechanism_node in dynamic mode at a high rate: ticks delivered and CPU (issues 22 and 32).

    .venv/bin/python -m bench.node_dynamic --scenes --rounds 2 --seconds 10   # issue 32: four scenes
    .venv/bin/python -m bench.node_dynamic --scenes --load all                # every topic read as well
    .venv/bin/python -m bench.node_dynamic                                    # issue 22: against the kinematic node
    .venv/bin/python -m bench.node_dynamic --rounds 5 --seconds 20 --scene four_bar_loaded

Node processes on localhost, one at a time, in a ROS domain of their own (``LINKAGE_ROS_DOMAIN_ID``,
else one from this process's id). ``--scenes``: the ``dynamic`` node alone on each of
:data:`SCENES` (engine at 200 rad/s, four_bar_loaded, harvester_finger, tipper inside its
stroke); without it: the ``kinematic`` node (``-p omega:=OMEGA``) and the ``dynamic`` node
(``-p mode:=dynamic -p phi0:=PHI0 -p omega:=0``: released from rest) on ``--scene``, alternating
order per round, against issue 22's targets (dynamic CPU ≤ 1.3 × the kinematic node's).

**What is counted.** The ticks delivered are counted by a *listener of its own*: a separate
process (this file, ``--listen``: its own rclpy context, node and EventsExecutor) subscribed to
the node's ``joint_states`` only (raw bytes, reliable, depth 1000). Over ``--seconds`` after
``--warmup`` s from the node's first message (not from its own start: a node still starting on
a loaded machine is not missing ticks) it counts the distinct ``joint_states`` stamps that lie in the window (the node's
stamps are its wall clock) over ``rate`` × the window — what a ROS subscriber of that one topic
receives — with the latency from each stamp to its receipt (the listener's wall clock when its
callback takes it: p50, p99, max, ms), whether the stamps came in increasing order and the longest
gap between two of them (periods), and reads the node's CPU (utime + stime of every thread, ``/proc/PID/stat``, as a
fraction of one core) over the same window. It does not count what the node computed but a
subscriber missed: a client whose one executor holds many subscriptions reads too slowly at
1 kHz, and the node's reliable keep-last-10 writers then drop what it has not read (the earlier
version of this bench, with one process subscribed to every topic, undercounted so:
tests/ros/conftest.py ``solo_listener`` is the same fix for the tests).

``--load all`` adds, in this process, a subscriber to every topic the node publishes (reliable,
depth 1000, ignored): each matched reliable reader adds to what a publish costs, so that is the
like-for-like CPU of the earlier figures (and what a node with RViz, a recorder and a controller
attached pays); ``--load listener`` (the default) leaves the listener alone, so topics nobody
reads cost the node nothing (it skips their publishing).

**What the node says.** This process also reads the node's ``diagnostics`` (about 1 Hz) and
reports, over the window (from 2 s into it: a message speaks of the last full second before
it), the node's own count: ``tick_share`` (the share of the ``rate_hz``
ticks its timer ran, per second of run time), ``compute_factor`` (run time per second of
computing the law) and how many diagnostics said ``behind`` (WARN: the law falling behind); the
line shows the mean and the lowest tick_share and the lowest compute_factor seen, so the
listener's count can be checked against the node's.

Prints a line per process and round, the medians, and a ``RESULT`` line against the targets.
The machine is shared: the load average is printed before and after.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from .node_floor import _STAMP, NS, _end, _ignore, cpu_seconds, delivered

TARGET_RATIO = 1.3
TARGET_DELIVERED = 0.99
ROOT = Path(__file__).resolve().parents[1]
LOADS = ("listener", "all")
#: The listener waits this long (s) at most for the node's first joint_states before its warm-up:
#: a node still starting (seconds on a loaded machine) must not count as ticks missed in the window.
FIRST_MESSAGE_S = 60.0
#: The listener's figures besides the count (:func:`latency_figures`).
LATENCY_KEYS = ("latency_p50", "latency_p99", "latency_max", "latency_min", "increasing", "max_gap", "min_gap")
#: A diagnostics message reports the law's last full second of run time, which ended up to a
#: second before it: those stamped within 2 s of the window's start may speak of the warm-up.
LAG_NS = 2_000_000_000

#: issue 32: every shipped scene with a motor or an effort input, with its start (tipper: inside
#: its stroke; under zero effort it sinks to the closed end and holds there)
SCENES: dict[str, list[str]] = {
    "engine": ["-p", "omega:=200.0"],
    "four_bar_loaded": ["-p", "phi0:=0.3", "-p", "omega:=0.0"],
    "harvester_finger": ["-p", "omega:=0.0"],
    "tipper": ["-p", "phi0:=1.0", "-p", "omega:=0.0"],
}


# ------------------------------------------------------------------------------- the listener
class StampCounter:
    """The stamps of the joint_states received while :attr:`active`, each with the wall-clock
    time (``time.time_ns``, the node's stamps' clock) the listener's callback took it."""

    def __init__(self) -> None:
        self.stamps: list[int] = []
        self.received: list[int] = []
        self.active = False
        self.seen = 0  # every message, counted or not (the node is up)

    def __call__(self, data: bytes) -> None:
        self.seen += 1
        if self.active:
            now = time.time_ns()
            sec, nsec = _STAMP.unpack_from(data, 4)
            self.stamps.append(sec * NS + nsec)
            self.received.append(now)


def latency_figures(stamps: Sequence[int], received: Sequence[int], start_ns: int, stop_ns: int,
                    rate: float) -> dict[str, float]:
    """Of the stamps in ``[start_ns, stop_ns)``: the latency from stamp to receipt (ms: p50, p99,
    max; negative would be a stamp ahead of the clock), whether the stamps came in increasing
    order, and the shortest and the longest gap between consecutive distinct stamps (in periods of
    ``rate``: 1–1 on the period grid without a miss)."""
    pairs = [(s, r) for s, r in zip(stamps, received) if start_ns <= s < stop_ns]
    if not pairs:
        return {"latency_p50": math.nan, "latency_p99": math.nan, "latency_max": math.nan,
                "latency_min": math.nan, "increasing": 0.0, "max_gap": math.nan, "min_gap": math.nan}
    lat = sorted((r - s) / 1e6 for s, r in pairs)
    ordered = [s for s, _ in pairs]
    distinct = sorted(set(ordered))
    gaps = [(b - a) * rate / NS for a, b in zip(distinct, distinct[1:])]
    return {"latency_p50": lat[len(lat) // 2], "latency_p99": lat[min(len(lat) - 1, int(0.99 * len(lat)))],
            "latency_max": lat[-1], "latency_min": lat[0],
            "increasing": float(all(b > a for a, b in zip(ordered, ordered[1:]))),
            "max_gap": max(gaps) if gaps else math.nan, "min_gap": min(gaps) if gaps else math.nan}


def listen_main(topic: str, pid: int, *, seconds: float, warmup: float, rate: float) -> int:
    """The listener process: ``topic`` (a joint_states) alone, its own context and EventsExecutor;
    prints one JSON line: delivered, received, the node's CPU, the window (wall clock, ns)."""
    import rclpy
    from rclpy.qos import QoSProfile, ReliabilityPolicy
    from rclpy.signals import SignalHandlerOptions
    from sensor_msgs.msg import JointState

    from linkage_ros.node import make_executor

    rclpy.init(signal_handler_options=SignalHandlerOptions.NO)
    try:
        node = rclpy.create_node("node_dynamic_listener")
        executor = make_executor("events")
        executor.add_node(node)
        counter = StampCounter()
        node.create_subscription(JointState, topic, counter, QoSProfile(depth=1000,
                                 reliability=ReliabilityPolicy.RELIABLE), raw=True)

        def spin(duration: float) -> None:
            end = time.monotonic() + duration
            while time.monotonic() < end:
                executor.spin_once(timeout_sec=0.01)

        deadline = time.monotonic() + FIRST_MESSAGE_S
        while not counter.seen and time.monotonic() < deadline:  # the node's start-up is not its window
            executor.spin_once(timeout_sec=0.01)
        spin(warmup)
        counter.active = True
        cpu0, wall0, start_ns = cpu_seconds(pid), time.monotonic(), time.time_ns()
        spin(seconds)
        cpu1, wall1, stop_ns = cpu_seconds(pid), time.monotonic(), time.time_ns()
        counter.active = False
        print(json.dumps({"cpu": (cpu1 - cpu0) / (wall1 - wall0),
                          "delivered": delivered(counter.stamps, start_ns, stop_ns, rate),
                          "received": len(counter.stamps), "window_s": wall1 - wall0,
                          "start_ns": start_ns, "stop_ns": stop_ns,
                          **latency_figures(counter.stamps, counter.received, start_ns, stop_ns, rate)}),
              flush=True)
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
    finally:
        rclpy.try_shutdown()
    return 0


# ------------------------------------------------------------------------------- the node's word
class Diagnostics:
    """The node's diagnostics as they arrive: (stamp ns, level, {key: value})."""

    def __init__(self) -> None:
        self.rows: list[tuple[int, int, dict[str, str]]] = []

    def __call__(self, message: Any) -> None:
        stamp = message.header.stamp
        for status in message.status:
            level = status.level if isinstance(status.level, int) else int.from_bytes(status.level, "little")
            self.rows.append((stamp.sec * 1_000_000_000 + stamp.nanosec, level,
                              {kv.key: kv.value for kv in status.values}))

    def between(self, start_ns: int, stop_ns: int) -> dict[str, float]:
        """Over ``[start_ns + LAG_NS, stop_ns)``: how many, how many say ``behind`` (WARN), the
        lowest and the mean tick_share, the lowest compute_factor (nan where none)."""
        rows = [r for r in self.rows if start_ns + LAG_NS <= r[0] < stop_ns]

        def finite(key: str) -> list[float]:
            values = [float(v[key]) for _, _, v in rows if key in v]
            return [v for v in values if math.isfinite(v)]

        shares, factors = finite("tick_share"), finite("compute_factor")
        behind = sum(1 for _, _, values in rows if values.get("status") == "behind")
        return {"diagnostics": float(len(rows)), "behind": float(behind),
                "tick_share": min(shares) if shares else math.nan,
                "tick_share_mean": statistics.fmean(shares) if shares else math.nan,
                "compute_factor": min(factors) if factors else math.nan}


class Bench:
    """This process's side: its rclpy node (diagnostics of every node, the ``--load all``
    subscribers) and the runs of a node with its listener."""

    def __init__(self, opts: argparse.Namespace) -> None:
        os.environ["ROS_DOMAIN_ID"] = os.environ.get("LINKAGE_ROS_DOMAIN_ID", str(150 + os.getpid() % 50))
        os.environ["ROS_AUTOMATIC_DISCOVERY_RANGE"] = "LOCALHOST"
        node_exe = str(Path(sys.prefix) / "bin" / "mechanism_node")
        if not Path(node_exe).is_file():
            node_exe = shutil.which("mechanism_node") or sys.exit("mechanism_node is not installed")
        self.node_exe = node_exe
        self.opts = opts
        import rclpy

        from linkage_ros.node import make_executor

        rclpy.init()
        self.node = rclpy.create_node("node_dynamic_bench")
        self.executor = make_executor("events")
        self.executor.add_node(self.node)
        self.diagnostics: dict[str, Diagnostics] = {}

    def watch(self, namespace: str, topics: dict[str, str]) -> None:
        """Read ``/namespace/diagnostics``; with ``--load all`` subscribe to every one of ``topics``."""
        from diagnostic_msgs.msg import DiagnosticArray
        from rclpy.qos import QoSProfile, ReliabilityPolicy

        from linkage_ros.messages import DIAGNOSTICS
        from linkage_ros.node import message_classes

        qos = QoSProfile(depth=1000, reliability=ReliabilityPolicy.RELIABLE)
        self.diagnostics[namespace] = Diagnostics()
        self.node.create_subscription(DiagnosticArray, f"/{namespace}/{DIAGNOSTICS}", self.diagnostics[namespace],
                                      qos)
        if self.opts.load == "all":
            classes = message_classes(sorted(set(topics.values())))
            for topic, typename in topics.items():
                if topic != DIAGNOSTICS:
                    self.node.create_subscription(classes[typename], f"/{namespace}/{topic}", _ignore, qos, raw=True)

    def run(self, namespace: str, argv: Sequence[str], *, env: dict[str, str] | None = None) -> dict[str, float]:
        """Start the node (``argv``, namespace ``namespace``, ``env`` added to its environment) and
        its listener; the listener's figures and the node's diagnostics over its window."""
        from linkage_ros.messages import JOINT_STATES

        opts = self.opts
        node = subprocess.Popen([self.node_exe, "--ros-args", "-r", f"__ns:=/{namespace}", *argv], cwd=ROOT,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env={**os.environ, **(env or {})})
        listener: subprocess.Popen[bytes] | None = None
        try:
            listener = subprocess.Popen(
                [sys.executable, "-m", "bench.node_dynamic", "--listen", f"/{namespace}/{JOINT_STATES}",
                 "--pid", str(node.pid), "--seconds", repr(opts.seconds), "--warmup", repr(opts.warmup),
                 "--rate", repr(float(opts.rate))], cwd=ROOT, stdout=subprocess.PIPE, env=dict(os.environ))
            while listener.poll() is None:
                self.executor.spin_once(timeout_sec=0.01)
            out = listener.stdout.read().decode() if listener.stdout is not None else ""
        finally:
            if listener is not None and listener.poll() is None:
                _end(listener)
            _end(node)
        lines = [line for line in out.splitlines() if line.startswith("{")]
        if not lines:
            sys.exit(f"the listener of {namespace} printed nothing (exit status {listener.returncode})")
        row = json.loads(lines[-1])
        result = {key: float(row[key]) for key in ("cpu", "delivered", "received", "window_s", *LATENCY_KEYS)}
        result.update(self.diagnostics[namespace].between(int(row["start_ns"]), int(row["stop_ns"])))
        return result

    def close(self) -> None:
        import rclpy

        self.executor.shutdown(timeout_sec=1.0)
        self.node.destroy_node()
        rclpy.try_shutdown()


def _print_round(k: int, name: str, r: dict[str, float]) -> None:
    node = ""
    if r.get("diagnostics"):
        node = (f"; node: tick_share {100 * r['tick_share_mean']:.2f} % (≥ {100 * r['tick_share']:.2f} % "
                f"a second), compute_factor ≥ {r['compute_factor']:.3g}, "
                f"{int(r['behind'])} of {int(r['diagnostics'])} diagnostics WARN behind")
    order = "increasing" if r.get("increasing") else "NOT increasing"
    print(f"  round {k}  {name}  CPU {100 * r['cpu']:5.1f} % of a core   delivered {100 * r['delivered']:6.2f} %   "
          f"({int(r['received'])} joint_states in {r['window_s']:.1f} s; stamp to receipt p50 "
          f"{r['latency_p50']:.2f} / p99 {r['latency_p99']:.2f} / max {r['latency_max']:.1f} ms, "
          f"min {r['latency_min']:.2f} ms; stamps {order}, gaps {r['min_gap']:.3g}–{r['max_gap']:.3g} periods){node}",
          flush=True)


def _load() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


# ------------------------------------------------------------------------------- issue 22: against the kinematic node
def run(opts: argparse.Namespace) -> list[dict[str, dict[str, float]]]:
    """``[{"kinematic": ..., "dynamic": ...} per round]``."""
    from .node_floor import _topics

    common = ["-p", f"scene:={opts.scene}", "-p", f"rate_hz:={float(opts.rate)!r}"]
    commands = {
        "kinematic": [*common, "-p", f"omega:={opts.omega!r}"],
        "dynamic": [*common, "-p", "mode:=dynamic", "-p", f"phi0:={opts.phi0!r}", "-p", "omega:=0.0"],
    }
    bench = Bench(opts)
    results: list[dict[str, dict[str, float]]] = []
    try:
        topics = dict(_topics(opts.scene))
        for name in commands:
            bench.watch(name, topics)
        order = list(commands)
        for k in range(opts.rounds):
            row = {}
            for name in order if k % 2 == 0 else order[::-1]:
                row[name] = bench.run(name, commands[name])
                _print_round(k + 1, name, row[name])
            results.append(row)
    finally:
        bench.close()
    return results


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


# ------------------------------------------------------------------------------- issue 32: four scenes
def run_scenes(opts: argparse.Namespace) -> dict[str, list[dict[str, float]]]:
    """The dynamic node alone on each of SCENES (or ``--only``): ``{scene: [figures per round]}``;
    with ``--catch-up A,B``, each scene under each catch-up limit in turn (alternating order per
    round), keyed ``scene catch-up N``."""
    from linkage_ros._tick_grid import CATCH_UP_ENV
    from linkage_ros.runtime import Runtime

    scenes = {name: SCENES[name] for name in (opts.only or SCENES)}
    limits: list[str | None] = list(opts.catch_up.split(",")) if opts.catch_up else [None]
    runs = {(f"{scene} catch-up {limit}" if limit is not None else scene): (scene, limit)
            for scene in scenes for limit in limits}
    bench = Bench(opts)
    results: dict[str, list[dict[str, float]]] = {name: [] for name in runs}
    try:
        for name, (scene, _) in runs.items():
            topics = Runtime({"scene": scene, "phi0": 1.0} if scene == "tipper" else {"scene": scene}).topics
            bench.watch(name.replace(" ", "_").replace("-", "_"), dict(topics))
        for k in range(opts.rounds):
            for name, (scene, limit) in (runs.items() if k % 2 == 0 else list(runs.items())[::-1]):
                row = bench.run(name.replace(" ", "_").replace("-", "_"),
                                ["-p", f"scene:={scene}", "-p", "mode:=dynamic", "-p",
                                 f"rate_hz:={float(opts.rate)!r}", *scenes[scene]],
                                env=None if limit is None else {CATCH_UP_ENV: limit})
                _print_round(k + 1, name, row)
                results[name].append(row)
    finally:
        bench.close()
    return results


def scenes_summary(results: dict[str, list[dict[str, float]]]) -> list[str]:
    """Per scene: the median [min–max] delivered, the median CPU, the node's lowest tick_share;
    RESULT against ≥ 99 % on every scene and round."""
    lines = []
    worst = 1.0
    for scene, rows in results.items():
        got = [r["delivered"] for r in rows]
        cpu = [r["cpu"] for r in rows]
        shares = [r["tick_share"] for r in rows if math.isfinite(r.get("tick_share", math.nan))]
        worst = min(worst, min(got))
        node = f", node's own tick_share ≥ {100 * min(shares):.2f} %" if shares else ""
        latency = ""
        if all("latency_p50" in r for r in rows):
            latency = (f", stamp to receipt p50 {statistics.median(r['latency_p50'] for r in rows):.2f} ms, "
                       f"p99 ≤ {max(r['latency_p99'] for r in rows):.2f} ms, "
                       f"max {max(r['latency_max'] for r in rows):.1f} ms")
        lines.append(f"{scene}: delivered {100 * statistics.median(got):.2f} % [{100 * min(got):.2f}–"
                     f"{100 * max(got):.2f}], CPU {100 * statistics.median(cpu):.1f} % of a core{latency}{node}")
    verdict = "PASS" if worst >= TARGET_DELIVERED else "FAIL"
    lines.append(f"RESULT {verdict}: every scene delivered >= {100 * worst:.2f} % of its ticks "
                 f"(target >= {100 * TARGET_DELIVERED:g} %)")
    return lines


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="python -m bench.node_dynamic", description=__doc__.split("\n")[0])
    parser.add_argument("--seconds", type=float, default=20.0, help="measurement window, s")
    parser.add_argument("--warmup", type=float, default=3.0, help="seconds before measuring")
    parser.add_argument("--rate", type=float, default=1000.0, help="rate_hz of the nodes")
    parser.add_argument("--rounds", type=int, default=3, help="rounds")
    parser.add_argument("--scene", default="four_bar_loaded")
    parser.add_argument("--omega", type=float, default=3.0, help="the kinematic node's omega, rad/s")
    parser.add_argument("--phi0", type=float, default=0.3, help="the dynamic node's phi0, rad (released from rest)")
    parser.add_argument("--scenes", action="store_true",
                        help="the dynamic node alone on engine (omega 200), four_bar_loaded, harvester_finger, "
                             "tipper (issue 32)")
    parser.add_argument("--only", action="append", choices=list(SCENES), help="with --scenes: these scenes only")
    parser.add_argument("--catch-up", help="with --scenes: compare these catch-up limits (LINKAGE_ROS_CATCH_UP "
                        "of the node, comma-separated; 0: none), e.g. 0,20")
    parser.add_argument("--load", choices=LOADS, default="listener",
                        help="listener: joint_states read by the listener only; all: every topic read as well")
    parser.add_argument("--listen", help=argparse.SUPPRESS)
    parser.add_argument("--pid", type=int, help=argparse.SUPPRESS)
    opts = parser.parse_args(argv)
    if opts.listen:
        return listen_main(opts.listen, opts.pid, seconds=opts.seconds, warmup=opts.warmup, rate=opts.rate)
    if opts.scenes:
        print(f"dynamic node on {', '.join(opts.only or SCENES)} at {opts.rate:g} Hz, {opts.seconds:g} s windows "
              f"after {opts.warmup:g} s warm-up, {opts.rounds} round(s), load {opts.load}, {os.cpu_count()} cores, "
              f"load average {_load()}", flush=True)
        for line in scenes_summary(run_scenes(opts)):
            print(line)
        print(f"load average {_load()}")
        return 0
    print(f"{opts.scene} at {opts.rate:g} Hz, {opts.seconds:g} s windows after {opts.warmup:g} s warm-up, "
          f"{opts.rounds} round(s) of the kinematic and the dynamic node, load {opts.load}, {os.cpu_count()} cores, "
          f"load average {_load()}", flush=True)
    for line in summary(run(opts)):
        print(line)
    print(f"load average {_load()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
