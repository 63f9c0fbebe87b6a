"""The node's work per tick, and the memory of a vectorised solve.

Per tick (harvester finger scene, every joint and point solved, as the node does): ``Engine.frame(t)``
(motion law + scalar solve) and ``MessageBuilder.build`` with rosbags' Jazzy typestore classes
(every topic: joint states, joint kinematics, point position/velocity/acceleration, markers,
diagnostics; the path markers sent once a second, the builder's default). CDR serialisation of all
messages, which the MCAP recorder adds but rclpy does in C, is timed on its own.

Memory: ``tracemalloc`` peak of a full solve of 10⁶ angles of the four-bar with every output's
position, velocity and acceleration fetched, and the bytes of those output arrays.
"""

from __future__ import annotations

import gc
import math
import statistics
import time
import tracemalloc
from typing import Any

import numpy as np

import solver

__all__ = ["memory_per_million", "run_ticks", "setup", "tick_cost"]


def setup(rate_hz: float = 1000.0) -> tuple[Any, Any, Any] | str:
    """(engine, builder, typestore) for the harvester finger; a reason string when not importable."""
    try:
        from rosbags.typesys import Stores, get_typestore

        from linkage_ros.engine import Engine
        from linkage_ros.messages import MessageBuilder
        from linkage_ros.motion import Motion
    except ImportError as error:
        return str(error)
    store = get_typestore(Stores.ROS2_JAZZY)
    engine = Engine("harvester_finger", Motion(phi0=0.0, omega=2.0 * math.pi, epsilon=0.1))
    return engine, MessageBuilder(engine, store.types, frame_id="world"), store


def run_ticks(engine: Any, builder: Any, times: list[float], *, keep: int = 0) -> tuple[float, float, list[Any]]:
    """Seconds spent in frame(t) and in build() over ``times``, tick after tick as a node runs
    (nothing kept, so the garbage collector sees a node's load), and the first ``keep`` ticks'
    messages."""
    clock = time.perf_counter
    frame_s = build_s = 0.0
    kept: list[Any] = []
    for i, t in enumerate(times):
        start = clock()
        frame = engine.frame(t)
        mid = clock()
        messages = builder.build(frame, int(round(t * 1e9)))
        end = clock()
        frame_s += mid - start
        build_s += end - mid
        if i < keep:
            kept.append(messages)
    return frame_s, build_s, kept


def tick_cost(*, ticks: int, rate_hz: float = 1000.0, repeat: int = 5) -> dict[str, Any]:
    """Median µs per tick of frame(t), build(), both, and serialisation; {'missing': why} without
    the engine."""
    parts = setup(rate_hz)
    if isinstance(parts, str):
        return {"missing": parts}
    engine, builder, store = parts
    dt = 1.0 / rate_hz
    # as mechanism_node does before it spins: the long-lived objects leave the collector's passes
    gc.collect()
    gc.freeze()
    runs: dict[str, list[float]] = {"frame": [], "build": [], "tick": [], "serialize": []}
    n_messages = 0
    for r in range(repeat + 1):
        times = [(r * ticks + i) * dt for i in range(ticks)]
        frame_s, build_s, sample = run_ticks(engine, builder, times, keep=max(ticks // 10, 1))
        n_messages = len(sample[0])
        start = time.perf_counter()
        for messages in sample:
            for _, msg in messages:
                store.serialize_cdr(msg, msg.__msgtype__)
        serialize_s = time.perf_counter() - start
        if r == 0:
            continue  # warm-up
        runs["frame"].append(frame_s / ticks)
        runs["build"].append(build_s / ticks)
        runs["tick"].append((frame_s + build_s) / ticks)
        runs["serialize"].append(serialize_s / len(sample))
    gc.unfreeze()
    out: dict[str, Any] = {k: statistics.median(v) * 1e6 for k, v in runs.items()}
    out["messages"] = n_messages
    out["max_rate_hz"] = 1e6 / out["tick"]
    out["core_at_1khz"] = out["tick"] * 1e3 / 1e6
    return out


def memory_per_million(count: int = 1_000_000) -> dict[str, float]:
    """Peak traced bytes and output bytes of a full four-bar solve, per 10⁶ positions (MiB)."""
    scene = solver.load_scene("four_bar")
    phi = np.linspace(0.0, 2.0 * math.pi, count, endpoint=False)
    tracemalloc.start()
    tracemalloc.reset_peak()
    k = scene.solve(phi, omega=1.0, epsilon=0.0)
    arrays = [getattr(k.point(p), q) for p in scene.output_points for q in ("position", "velocity", "acceleration")]
    arrays += [getattr(k.joint(j), q) for j in scene.output_joints for q in ("position", "velocity", "acceleration")]
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    scale = 1e6 / count / 2**20
    return {"peak_mib": peak * scale, "outputs_mib": sum(a.nbytes for a in arrays) * scale}
