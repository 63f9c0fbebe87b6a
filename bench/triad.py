"""The triads' cost (the RRR triad's, the slider triad's and its swinging-block variant's) against
an RRR dyad's (issue 28 targets: one vectorised sample ≤ 5×, one compiled instant ≤ 4×), measured
in one process:
``python -m bench.triad``.

Prints the load average beside the figures (the machine is shared; only the ratios are meaningful),
and each figure twice: wall-clock (``perf_counter``) and this process's CPU time (``process_time``,
which other processes' load inflates less). The scenes are timed in turn, repeat by repeat,
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
SCENES = ("triad_press", "slider_triad_press", "swinging_block_triad", "four_bar")
BASE = "four_bar"  # the ratios' unit: an RRR dyad (issue 28: a triad sample ≤ 5×, an instant ≤ 4×)


def _best(fns: dict[str, Callable[[], object]], clock: Callable[[], float] = time.perf_counter) -> dict[str, float]:
    """The best of ``REPEATS`` of each function, timed in turn (a burst of load falls on all alike)."""
    out: dict[str, list[float]] = {name: [] for name in fns}
    for _ in range(REPEATS):
        for name, fn in fns.items():
            t0 = clock()
            fn()
            out[name].append(clock() - t0)
    return {name: min(times) for name, times in out.items()}


def main() -> None:
    scenes = {name: solver.load_scene(name) for name in SCENES}
    phi = np.linspace(0.0, 2.0 * np.pi, SAMPLES)
    ticks = [0.1 + 1e-3 * i for i in range(TICKS)]
    for s in scenes.values():
        s.solve(phi)
        s.solve(ticks[0])
    print(f"load average {os.getloadavg()[0]:.2f}")
    for label, clock in (("wall", time.perf_counter), ("cpu", time.process_time)):
        vec = _best({n: (lambda s=s: s.solve(phi)) for n, s in scenes.items()}, clock)
        one = _best({n: (lambda s=s: [s.solve(p) for p in ticks]) for n, s in scenes.items()}, clock)
        for what, times, count in (("vectorised sample", vec, SAMPLES), ("one instant", one, TICKS)):
            base = times[BASE] / count
            print(f"[{label}] {what + ':':18} " + ", ".join(
                f"{n} {t / count * 1e6:.2f} µs ({t / count / base:.1f}×)" for n, t in times.items()))


if __name__ == "__main__":
    main()
