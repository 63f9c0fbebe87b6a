"""Vector-loop form against group form of the same mechanism: vectorised solve time (issue 3).

``python -m bench.vectors_speed [--count N] [--repeat R]`` solves each pair of scenes on N crank
angles (default 10⁶, with ω and ε so that the real-motion path runs too), alternating the two
forms in each repeat so that a noisy, shared machine slows both alike, and prints the median
time of each and their ratio (vector / group; issue 3 asks for at most 1.5).
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import time
from collections.abc import Sequence

import numpy as np

import solver

__all__ = ["PAIRS", "measure", "main"]

PAIRS = (
    ("four_bar", "four_bar_vectors"),
    ("harvester_finger", "harvester_finger_vectors"),
    ("slider_crank", "vectors/pl3_slider_crank"),
)
LIMIT = 1.5


def _time(scene: solver.Scene, phi: np.ndarray) -> float:
    t = time.perf_counter()
    k = scene.solve(phi, omega=2.0, epsilon=0.5)
    for p in scene.output_points:
        k.point(p)
    for j in scene.output_joints:
        k.joint(j)
    return time.perf_counter() - t


def measure(groups: str, vectors: str, *, count: int, repeat: int) -> tuple[float, float]:
    """Median seconds of the group form and of the vector form on ``count`` angles."""
    a, b = solver.load_scene(groups), solver.load_scene(vectors)
    phi = np.linspace(0.0, 2 * math.pi, count, endpoint=False)
    _time(a, phi[:1000]), _time(b, phi[:1000])  # warm up
    ta, tb = [], []
    for _ in range(repeat):
        ta.append(_time(a, phi))
        tb.append(_time(b, phi))
    return statistics.median(ta), statistics.median(tb)


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m bench.vectors_speed", description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=10**6, help="crank angles per solve (default 10⁶)")
    p.add_argument("--repeat", type=int, default=7, help="timed solves per form (default 7)")
    args = p.parse_args(argv)
    print(
        f"{platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}; "
        f"{args.count} angles, median of {args.repeat}"
    )
    print(f"{'group form':<18} {'vector form':<26} {'group s':>9} {'vector s':>9} {'ratio':>6}")
    worst = 0.0
    for groups, vectors in PAIRS:
        ta, tb = measure(groups, vectors, count=args.count, repeat=args.repeat)
        worst = max(worst, tb / ta)
        print(f"{groups:<18} {vectors:<26} {ta:9.4f} {tb:9.4f} {tb / ta:6.2f}")
    print(f"worst ratio {worst:.2f} (limit {LIMIT})")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
