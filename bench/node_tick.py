"""Cost of one node tick (solve + every message) and of its parts; not a test.

    .venv/bin/python -m bench.node_tick [scene ...]

Prints the best of 7 repeats (µs per tick) for: the whole tick (Engine.frame + MessageBuilder.build
with rosbags' Jazzy classes, paths sent once per second of run time at 1 kHz), the frame alone,
the scalar solve of every point and joint alone, and the messages alone.
"""

from __future__ import annotations

import sys
import timeit

from rosbags.typesys import Stores, get_typestore

import solver
from linkage_ros.engine import Engine
from linkage_ros.messages import MessageBuilder
from linkage_ros.motion import Motion

TICKS = 2000
REPEATS = 7
RATE_HZ = 1000


def bench(name: str) -> dict[str, float]:
    types = get_typestore(Stores.ROS2_JAZZY).types
    engine = Engine(name, Motion(phi0=0.3, omega=2.0, epsilon=0.1))
    builder = MessageBuilder(engine, types)
    full = solver.load_scene(name).everything()
    frame = engine.frame(1.0)
    clock = [0]

    def tick() -> None:
        clock[0] += 1
        t = clock[0] / RATE_HZ
        builder.build(engine.frame(t), clock[0] * (1_000_000_000 // RATE_HZ))

    def best(fn: object) -> float:
        return min(timeit.repeat(fn, number=TICKS, repeat=REPEATS)) / TICKS * 1e6  # type: ignore[arg-type]

    return {
        "tick": best(tick),
        "frame": best(lambda: engine.frame(1.0)),
        "solve": best(lambda: full.solve(1.3, omega=2.0, epsilon=0.1)),
        "messages": best(lambda: builder.build(frame, 5, include_paths=False)),
    }


def main(names: list[str]) -> None:
    for name in names or ["harvester_finger"]:
        row = bench(name)
        print(f"{name:22s} " + "  ".join(f"{k} {v:6.1f} µs" for k, v in row.items()))


if __name__ == "__main__":
    main(sys.argv[1:])
