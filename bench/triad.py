"""The triad's cost against an RRR dyad's (issue 28 targets: one vectorised sample ≤ 5×, one
compiled instant ≤ 4×), measured in one process: ``python -m bench.triad``.

Prints the load average beside the figures (the machine is shared; only the ratios are meaningful).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable

import numpy as np

import solver

SAMPLES = 3600
TICKS = 200
REPEATS = 5


def _best(fn: Callable[[], object]) -> float:
    out = []
    for _ in range(REPEATS):
        t0 = time.perf_counter()
        fn()
        out.append(time.perf_counter() - t0)
    return min(out)


def main() -> None:
    triad, dyad = solver.load_scene("triad_press"), solver.load_scene("four_bar")
    phi = np.linspace(0.0, 2.0 * np.pi, SAMPLES)
    tv, dv = (_best(lambda s=s: s.solve(phi)) / SAMPLES for s in (triad, dyad))
    ticks = [0.1 + 1e-3 * i for i in range(TICKS)]
    for s in (triad, dyad):
        s.solve(ticks[0])
    ti, di = (_best(lambda s=s: [s.solve(p) for p in ticks]) / TICKS for s in (triad, dyad))
    print(f"load average {os.getloadavg()[0]:.2f}")
    print(f"vectorised sample: triad_press {tv * 1e6:.2f} µs, four_bar {dv * 1e6:.2f} µs, ratio {tv / dv:.0f}")
    print(f"one instant:       triad_press {ti * 1e6:.1f} µs, four_bar {di * 1e6:.1f} µs, ratio {ti / di:.0f}")


if __name__ == "__main__":
    main()
