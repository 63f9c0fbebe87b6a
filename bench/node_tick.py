"""Cost of one node tick and of its parts, in-process; not a test.

    .venv/bin/python -m bench.node_tick [scene ...]        # default: four_bar harvester_finger

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
"""

from __future__ import annotations

import gc
import sys
import timeit
from collections.abc import Callable

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


def main(names: list[str]) -> None:
    for name in names or ["four_bar", "harvester_finger"]:
        for path, row in (("node", bench_node(name)), ("builder", bench_builder(name))):
            print(f"{name:20s} {path:8s} " + "  ".join(f"{k} {v:6.1f} µs" for k, v in row.items()))


if __name__ == "__main__":
    main(sys.argv[1:])
