"""Cost of one node tick and of its parts, in-process; not a test.

    .venv/bin/python -m bench.node_tick [scene ...]        # default: four_bar harvester_finger
    .venv/bin/python -m bench.node_tick --in-situ [--scene four_bar] [--rounds 5] [--also before=DIR]

Best of 7 repeats, µs per tick, with the long-lived objects frozen out of the collector's way
(``gc.freeze()``, as ``mechanism_node`` does). Two lines per scene:

* ``node``: what ``mechanism_node`` does per timer tick. ``tick`` = ``Runtime.tick`` at 1 kHz
  (motion law, solve, frame, URDF tree joints, CDR bytes from the templates; the path markers and
  diagnostics once a second); ``frame`` = ``Engine.frame`` (its solve included); ``solve`` = the
  scalar solve of every point and joint; ``tree`` = the URDF tree joints of one frame;
  ``bytes`` = ``Serializer.render`` of one frame (the tree joints included; the Frame path).
* ``builder``: the message-object path (``linkage-run``, the recorders): ``tick`` =
  ``Engine.frame`` + ``MessageBuilder.build`` with rosbags' Jazzy classes; ``messages`` = the
  build alone.

Parts timed alone run warmer than inside a tick (the tick's code and data compete for the caches
and branch predictors), so they add up to less than ``tick``; in the running node, with the
executor and DDS between two ticks, a tick costs more again (about 2×, docs/ros.md).

``--in-situ``: the tick where it runs. Each round starts, one after the other, child processes
that each run a real :class:`~linkage_ros.node.MechanismNode` (rclpy, ``--executor`` events or
single, the same ``gc.freeze()`` as ``main``) at ``--rate`` for ``--seconds`` after ``--warmup``
s, in a ROS domain of their own, with nobody subscribed:

* ``node``: the node as it is; ``tick`` is the time in ``Runtime.tick`` per timer tick
  (``perf_counter`` around it, in the running process), ``callback`` the time in the timer
  callback (the clock read, the tick, the publishes), ``cpu`` the process's CPU time (every
  thread: rclpy's, DDS's) per timer tick;
  (Since issue 32's last round a node with nobody subscribed renders, after its first 2 s, joint_states alone on an
  ordinary tick and publishes nothing: ``node`` here is that.)
* ``floor``: the same node with its timer callback replaced by publishing the node's own
  bytes (rendered before it starts; joint_states stamped per tick), what ``bench.node_floor``'s
  floor does;
* ``node_LABEL`` for every ``--also LABEL=DIR``: the node from ``DIR/linkage_ros``
  (``PYTHONPATH``), e.g. a snapshot taken before a change, for a paired comparison.

The children of a round run in turn (odd rounds in reverse order); the lines give the median
[min–max] over the rounds, and ``cpu − floor`` per round: what the node costs beyond publishing.
Less noisy than ``bench.node_floor`` (no subscriber process; CPU time, not wall time), but the
machine's other load still warms or chills the caches: compare variants of one run.
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import statistics
import subprocess
import sys
import time
import timeit
from collections.abc import Callable, Sequence
from pathlib import Path

from rosbags.typesys import Stores, get_typestore

from linkage_ros.engine import Engine
from linkage_ros.messages import MessageBuilder
from linkage_ros.motion import Motion
from linkage_ros.runtime import Runtime

TICKS = 2000
REPEATS = 7
RATE_HZ = 1000
NS = 1_000_000_000
T0 = 1_700_000_000 * NS


def best(fn: Callable[[], object]) -> float:
    """Best of :data:`REPEATS` runs of :data:`TICKS` calls, µs per call."""
    return min(timeit.repeat(fn, number=TICKS, repeat=REPEATS)) / TICKS * 1e6


def bench_node(name: str) -> dict[str, float]:
    runtime = Runtime({"scene": name, "rate_hz": float(RATE_HZ)})
    runtime.tick(T0)
    engine, wire, builder = runtime.engine, runtime.wire, runtime.builder
    full = engine.scene.everything()
    frame = engine.frame(1.0)
    clock = [0]

    def tick() -> None:
        clock[0] += 1
        runtime.tick(T0 + clock[0] * (NS // RATE_HZ))

    gc.collect()
    gc.freeze()
    try:
        return {
            "tick": best(tick),
            "frame": best(lambda: engine.frame(1.0)),
            "solve": best(lambda: full.solve(1.3, omega=2.0, epsilon=0.1)),
            "tree": best(lambda: builder.tree_states(frame)),
            "bytes": best(lambda: wire.render(frame, T0, paths=False, diagnostics=False)),
        }
    finally:
        gc.unfreeze()


def bench_builder(name: str) -> dict[str, float]:
    types = get_typestore(Stores.ROS2_JAZZY).types
    engine = Engine(name, Motion(phi0=0.3, omega=2.0, epsilon=0.1))
    builder = MessageBuilder(engine, types)
    frame = engine.frame(1.0)
    clock = [0]

    def tick() -> None:
        clock[0] += 1
        t = clock[0] / RATE_HZ
        builder.build(engine.frame(t), clock[0] * (NS // RATE_HZ))

    return {
        "tick": best(tick),
        "messages": best(lambda: builder.build(frame, 5, include_paths=False)),
    }


def in_situ_child(scene: str, rate: float, seconds: float, warmup: float, floor: bool,
                  executor_kind: str = "events") -> dict[str, float]:
    """One running node (or the floor: the node's timer publishing its own pre-rendered bytes):
    µs of CPU per timer tick (the whole process) and µs in ``Runtime.tick`` per tick."""
    import rclpy
    from rclpy.parameter import Parameter
    from rclpy.signals import SignalHandlerOptions

    from linkage_ros.node import MechanismNode, make_executor

    from .node_floor import floor_callback, floor_messages

    rclpy.init(args=[], signal_handler_options=SignalHandlerOptions.NO)
    try:
        node = MechanismNode(parameter_overrides=[Parameter("scene", value=scene), Parameter("rate_hz", value=rate)])
        count = [0]
        spent = [0]
        whole = [0]
        clock = time.perf_counter_ns
        if floor:
            node._tick_timer.callback = floor_callback(node._topic_publishers, floor_messages(scene, rate), rate, count)
        else:
            runtime = node.runtime
            tick = runtime.tick

            def timed(now_ns: int) -> list[tuple[str, bytes]]:
                count[0] += 1
                t0 = clock()
                out = tick(now_ns)
                spent[0] += clock() - t0
                return out

            runtime.tick = timed  # type: ignore[method-assign]
        callback = node._tick_timer.callback

        def timed_callback() -> None:
            t0 = clock()
            callback()
            whole[0] += clock() - t0

        node._tick_timer.callback = timed_callback
        executor = make_executor(executor_kind)
        gc.collect()
        gc.freeze()
        executor.add_node(node)
        end = time.monotonic() + warmup
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.1)
        n0, s0, w0, cpu0 = count[0], spent[0], whole[0], time.process_time()
        end = time.monotonic() + seconds
        while time.monotonic() < end:
            executor.spin_once(timeout_sec=0.1)
        n, cpu = count[0] - n0, time.process_time() - cpu0
        out = {"cpu": cpu / n * 1e6, "tick": (spent[0] - s0) / n / 1e3,
               "callback": (whole[0] - w0) / n / 1e3, "ticks": float(n)}
        executor.shutdown(timeout_sec=1.0)
        node.destroy_node()
        return out
    finally:
        rclpy.try_shutdown()


def in_situ(opts: argparse.Namespace) -> None:
    """Rounds of child processes (see the module docstring), then the summary lines."""
    from .node_floor import variants

    env = {**os.environ, "ROS_AUTOMATIC_DISCOVERY_RANGE": "LOCALHOST",
           "ROS_DOMAIN_ID": os.environ.get("LINKAGE_ROS_DOMAIN_ID", str(150 + os.getpid() % 50))}
    children: dict[str, tuple[list[str], dict[str, str]]] = {}
    base = [sys.executable, "-m", "bench.node_tick", "--child", "--scene", opts.scene, "--rate", str(opts.rate),
            "--seconds", str(opts.seconds), "--warmup", str(opts.warmup), "--executor", opts.executor]
    children["node"] = (base, env)
    for label, where in variants(opts.also):
        path = os.pathsep.join(filter(None, (where, env.get("PYTHONPATH"))))
        children[f"node_{label}"] = (base, {**env, "PYTHONPATH": path})
    children["floor"] = ([*base, "--floor"], env)
    order = list(children)
    results: dict[str, list[dict[str, float]]] = {name: [] for name in order}
    root = Path(__file__).resolve().parents[1]
    print(f"{opts.scene} at {opts.rate:g} Hz, in situ: {opts.rounds} round(s) of {', '.join(order)}; "
          f"{opts.seconds:g} s after {opts.warmup:g} s each, executor {opts.executor}, no subscriber", flush=True)
    for k in range(opts.rounds):
        for name in order if k % 2 == 0 else order[::-1]:
            argv, child_env = children[name]
            done = subprocess.run(argv, cwd=root, env=child_env, capture_output=True, text=True, timeout=600)
            if done.returncode != 0:
                sys.exit(f"{name}: {done.stderr.strip()[-2000:]}")
            row = json.loads(done.stdout.strip().splitlines()[-1])
            results[name].append(row)
            tick = f"   Runtime.tick {row['tick']:5.1f} µs" if name != "floor" else ""
            tick = f"   timer callback {row['callback']:5.1f} µs" + tick
            print(f"  round {k + 1}  {name:12s}  CPU {row['cpu']:6.1f} µs per tick{tick}   "
                  f"({int(row['ticks'])} ticks)", flush=True)
    floor = [r["cpu"] for r in results["floor"]]

    def spread(values: Sequence[float]) -> str:
        return f"{statistics.median(values):6.1f} [{min(values):.1f}–{max(values):.1f}]"

    for name in order:
        cpu = [r["cpu"] for r in results[name]]
        line = (f"{name:12s} CPU per tick {spread(cpu)} µs, timer callback "
                f"{spread([r['callback'] for r in results[name]])} µs")
        if name != "floor":
            line += (f", beyond the floor {spread([c - f for c, f in zip(cpu, floor)])} µs, "
                     f"Runtime.tick {spread([r['tick'] for r in results[name]])} µs")
        print(line)


def main(argv: Sequence[str] | None = None) -> None:
    parser = argparse.ArgumentParser(prog="python -m bench.node_tick", description=__doc__.split("\n")[0])
    parser.add_argument("names", nargs="*", help="scenes of the in-process timing (default: four_bar harvester_finger)")
    parser.add_argument("--in-situ", action="store_true", help="time the tick inside running nodes (see above)")
    parser.add_argument("--scene", default="four_bar", help="--in-situ: the scene")
    parser.add_argument("--rate", type=float, default=1000.0, help="--in-situ: rate_hz")
    parser.add_argument("--seconds", type=float, default=10.0, help="--in-situ: measured seconds per child")
    parser.add_argument("--warmup", type=float, default=2.0, help="--in-situ: seconds before measuring")
    parser.add_argument("--rounds", type=int, default=3, help="--in-situ: rounds")
    parser.add_argument("--executor", choices=("events", "single"), default="events", help="--in-situ: executor")
    parser.add_argument("--also", action="append", metavar="LABEL=DIR",
                        help="--in-situ: also the node from DIR/linkage_ros (paired A/B)")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    parser.add_argument("--floor", action="store_true", help=argparse.SUPPRESS)
    opts = parser.parse_args(argv)
    if opts.child:
        print(json.dumps(in_situ_child(opts.scene, opts.rate, opts.seconds, opts.warmup, opts.floor, opts.executor)))
        return
    if opts.in_situ:
        in_situ(opts)
        return
    for name in opts.names or ["four_bar", "harvester_finger"]:
        for path, row in (("node", bench_node(name)), ("builder", bench_builder(name))):
            print(f"{name:20s} {path:8s} " + "  ".join(f"{k} {v:6.1f} µs" for k, v in row.items()))


if __name__ == "__main__":
    main()
