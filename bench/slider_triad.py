"""The slider triad's cost against the RRR triad's and an RRR dyad's, measured in one process:
``python -m bench.slider_triad`` (docs/stability.md#the-slider-triad). Both triads follow their
mode without an eigenvalue problem per sample (anchors' shortcut) or per tick (Newton follow).

Prints the load average beside the figures (the machine is shared; only the ratios are meaningful),
and each figure as this process's CPU time (``process_time``) and wall-clock (``perf_counter``).
"""

from __future__ import annotations

import os
import time
from collections.abc import Callable

import numpy as np

import solver

SAMPLES = 3600
TICKS = 300
REPEATS = 5


def _best(fn: Callable[[], object], clock: Callable[[], float]) -> float:
    out = []
    for _ in range(REPEATS):
        t0 = clock()
        fn()
        out.append(clock() - t0)
    return min(out)


def main() -> None:
    scenes = {n: solver.load_scene(n) for n in ("slider_triad_press", "triad_press", "four_bar")}
    phi = np.linspace(0.0, 2.0 * np.pi, SAMPLES)
    ticks = [1e-3 * i for i in range(TICKS)]
    for s in scenes.values():
        s.solve(phi)
        s.solve(ticks[0])
    print(f"load average {os.getloadavg()[0]:.2f}")
    for label, clock in (("cpu", time.process_time), ("wall", time.perf_counter)):
        vec = {n: _best(lambda s=s: s.solve(phi), clock) / SAMPLES for n, s in scenes.items()}
        one = {n: _best(lambda s=s: [s.solve(p) for p in ticks], clock) / TICKS for n, s in scenes.items()}
        base_v, base_i = vec["four_bar"], one["four_bar"]
        print(f"[{label}] vectorised sample: " + ", ".join(f"{n} {t * 1e6:.2f} µs ({t / base_v:.1f}×)"
                                                          for n, t in vec.items()))
        print(f"[{label}] one instant:       " + ", ".join(f"{n} {t * 1e6:.1f} µs ({t / base_i:.1f}×)"
                                                          for n, t in one.items()))


if __name__ == "__main__":
    main()
