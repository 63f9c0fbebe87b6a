"""The triad's cost against an RRR dyad's (issue 28 targets: one vectorised sample ≤ 5×, one
compiled instant ≤ 4×), measured in one process: ``python -m bench.triad``.

Prints the load average beside the figures (the machine is shared; only the ratios are meaningful),
and each figure twice: wall-clock (``perf_counter``) and this process's CPU time (``process_time``,
which other processes' load inflates less). The two scenes are timed in turn, repeat by repeat,
and each keeps its best (least disturbed) repeat, so that a burst of load falls on both alike. On a
loaded machine the scheduler's time slices cut the triad's longer sweep more often than the
four-bar's short one, so the wall-clock ratio there is the scheduler's; ``chrt -f 1 python -m
bench.triad`` (no time slicing by ordinary processes) makes the two clocks agree.
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable

import numpy as np

import solver

SAMPLES = 3600
TICKS = 1000
REPEATS = 25


def _best_pair(fns: tuple[Callable[[], object], Callable[[], object]],
               clock: Callable[[], float] = time.perf_counter) -> tuple[float, float]:
    """The best of ``REPEATS`` of each function, timed in turn."""
    out: tuple[list[float], list[float]] = ([], [])
    for _ in range(REPEATS):
        for fn, times in zip(fns, out):
            t0 = clock()
            fn()
            times.append(clock() - t0)
    return min(out[0]), min(out[1])


def main() -> None:
    triad, dyad = solver.load_scene("triad_press"), solver.load_scene("four_bar")
    phi = np.linspace(0.0, 2.0 * np.pi, SAMPLES)
    ticks = [0.1 + 1e-3 * i for i in range(TICKS)]
    for s in (triad, dyad):
        s.solve(phi)
        s.solve(ticks[0])
    print(f"load average {os.getloadavg()[0]:.2f}")
    for label, clock in (("wall", time.perf_counter), ("cpu", time.process_time)):
        tv, dv = (x / SAMPLES for x in _best_pair((lambda: triad.solve(phi), lambda: dyad.solve(phi)), clock))
        ti, di = (x / TICKS for x in _best_pair((lambda: [triad.solve(p) for p in ticks],
                                                 lambda: [dyad.solve(p) for p in ticks]), clock))
        print(f"[{label}] vectorised sample: triad_press {tv * 1e6:.2f} µs, four_bar {dv * 1e6:.2f} µs, "
              f"ratio {tv / dv:.1f}")
        print(f"[{label}] one instant:       triad_press {ti * 1e6:.1f} µs, four_bar {di * 1e6:.1f} µs, "
              f"ratio {ti / di:.1f}")


if __name__ == "__main__":
    main()
