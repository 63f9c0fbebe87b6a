"""A drawn scene loads as fast as its group form (issue 31: ≤ 1.2×).

``python -m bench.drawn_load [--repeat 200]`` writes, for each scene measured, its drawing and
its equivalent group scene to files (linkage-import's writer), then loads each file with
``solver.load_scene`` in alternation, ``--repeat`` times, and prints the median load time of each
and their ratio (measured in the same process as CPU time, interleaved, so that the machine's
load affects both alike). The drawn form pays for its structure finder (graph, mobility, decomposition); the
group form for nothing more than it always did. ``--chain 1000,2000,4000`` also times the
structure finder on a chain of N RRR dyads (2N links, N + 1 ground points): it grows linearly.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

import solver
from solver.structure import scene_dict_from_drawing
from solver.structure_cli import drawing_of_scene, dump_scene

__all__ = ["measure", "main"]

#: The scenes measured: the shipped drawn example, and group scenes drawn at an input value.
SCENES = ("crank_rocker_drawn", "six_bar", "harvester_finger", "engine", "excavator")


def _files(name: str, folder: Path) -> tuple[Path, Path]:
    path = solver.find_scene(name)
    scene = solver.load_scene(path)
    values = [0.7 if r is None else 0.5 * (r[0] + r[1]) for r in scene.input_ranges]
    drawn = drawing_of_scene(path, values)
    drawn_file = folder / f"{name.replace('/', '_')}_drawn.yaml"
    group_file = folder / f"{name.replace('/', '_')}_groups.yaml"
    drawn_file.write_text(dump_scene(drawn), encoding="utf-8")
    group_file.write_text(dump_scene(scene_dict_from_drawing(drawn, source=name)), encoding="utf-8")
    return drawn_file, group_file


def measure(name: str, folder: Path, repeat: int) -> tuple[float, float, float, float]:
    """Seconds to load the drawn file and its group file: medians, then minima (the least
    disturbed load of each: on a busy machine the steadier ratio)."""
    drawn_file, group_file = _files(name, folder)
    times: dict[Path, list[float]] = {drawn_file: [], group_file: []}
    for _ in range(repeat):
        for f in (drawn_file, group_file):
            t0 = time.process_time()  # this process's CPU time: other processes' load barely moves it
            solver.load_scene(f)
            times[f].append(time.process_time() - t0)
    a, b = times[drawn_file], times[group_file]
    return statistics.median(a), statistics.median(b), min(a), min(b)


def chain(n: int) -> dict[str, object]:
    """A drawn crank driving n RRR dyads in series, each to a ground point of its own."""
    pts: dict[str, list[float]] = {"O": [0.0, 0.0], "P0": [0.1, 0.05]}
    ground, links, prev = ["O"], {"crank": ["O", "P0"]}, "P0"
    for i in range(1, n + 1):
        pts[f"G{i}"] = [0.3 * i + 0.1, -0.2]
        pts[f"P{i}"] = [0.3 * i, 0.1 + 0.05 * (i % 2)]
        ground.append(f"G{i}")
        links[f"a{i}"], links[f"b{i}"] = [prev, f"P{i}"], [f"G{i}", f"P{i}"]
        prev = f"P{i}"
    return {"scene": "chain", "units": {"length": "m", "angle": "rad"},
            "drawing": {"points": pts, "ground": ground, "links": links, "inputs": ["crank"]},
            "outputs": {"points": [prev]}}


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=(__doc__ or "").splitlines()[0])
    p.add_argument("--repeat", type=int, default=200)
    p.add_argument("--chain", default="", help="comma-separated dyad counts for the scaling table")
    args = p.parse_args(argv)
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else float("nan")
    print(f"# {platform.processor() or platform.machine()}, Python {platform.python_version()}, "
          f"load average {load:.2f}")
    print(f"{'scene':<20} {'drawn ms':>9} {'groups ms':>10} {'ratio':>6} {'min ratio':>10}   (medians; minima)")
    with tempfile.TemporaryDirectory() as tmp:
        for name in SCENES:
            drawn, groups, lo_d, lo_g = measure(name, Path(tmp), args.repeat)
            print(f"{name:<20} {drawn * 1e3:>9.3f} {groups * 1e3:>10.3f} {drawn / groups:>6.2f} {lo_d / lo_g:>10.2f}")
    sizes = [int(x) for x in args.chain.split(",") if x.strip()]
    if sizes:
        print(f"{'dyads':>7} {'structure s':>12} {'µs/link':>8}")
    for n in sizes:
        data = chain(n)
        t0 = time.perf_counter()
        scene_dict_from_drawing(data)
        t = time.perf_counter() - t0
        print(f"{n:>7} {t:>12.3f} {t / (2 * n) * 1e6:>8.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
