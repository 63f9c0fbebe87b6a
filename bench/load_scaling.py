"""Loading a scene grows linearly with its number of groups (issue 13).

``python -m bench.load_scaling [--sizes 1000,2000,4000,8000]`` writes a chain of N groups (a crank,
then each point attached to the previous link), loads it and times the three stages: reading the
YAML (solver._yaml, bounded), validating it into groups (solver._loader) and building the scene
and its plan (dependency order, pruning). Before issue 13 the ordering rescanned every pending
group per round: 4,000 chained groups took 7 s, 8,000 took 45 s. It prints the time per group of
each stage, which stays flat when the growth is linear.
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

import solver
from solver._loader import parse_scene, read_yaml

__all__ = ["chain_scene", "measure", "main"]


def chain_scene(n: int) -> str:
    """A crank and n − 1 attached groups, each on the link of the previous two points."""
    lines = ["scene: chain", "units: {length: m, angle: deg}", "fixed: {O: [0.0, 0.0]}", "groups:",
             "  - {type: crank, name: crank, center: O, point: P0, length: 0.1}"]
    prev = "O"
    for i in range(1, n):
        lines.append(f"  - {{type: attached, name: g{i}, point: P{i}, base: P{i - 1}, along: [{prev}, P{i - 1}], "
                     "distance: 0.1, angle: 10}")
        prev = f"P{i - 1}"
    lines.append(f"outputs: {{points: [P{n - 1}]}}")
    return "\n".join(lines) + "\n"


def measure(n: int, folder: Path) -> tuple[float, float, float]:
    """Seconds to read, validate and plan a chain of n groups."""
    path = folder / f"chain{n}.yaml"
    path.write_text(chain_scene(n), encoding="utf-8")
    t0 = time.perf_counter()
    data = read_yaml(path)
    t1 = time.perf_counter()
    scene_data = parse_scene(data, file=str(path))
    t2 = time.perf_counter()
    solver.Scene(scene_data)
    t3 = time.perf_counter()
    return t1 - t0, t2 - t1, t3 - t2


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", default="1000,2000,4000,8000", help="comma-separated group counts")
    args = p.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",") if s.strip()]
    print(f"# {platform.processor() or platform.machine()}, Python {platform.python_version()}")
    print(f"{'groups':>7} {'read s':>8} {'validate s':>11} {'plan s':>8} {'total s':>8} {'µs/group':>9}")
    with tempfile.TemporaryDirectory() as tmp:
        for n in sizes:
            r, v, pl = measure(n, Path(tmp))
            total = r + v + pl
            print(f"{n:7d} {r:8.3f} {v:11.3f} {pl:8.3f} {total:8.3f} {1e6 * total / n:9.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
