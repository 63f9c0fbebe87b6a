"""Peers: pylinkage 1.3.0 on the four-bar, with numba (in this process) and pure Python (a child
process in which numba cannot be imported, so pylinkage falls back to its plain-Python solvers).

pylinkage steps a crank by a fixed angle per iteration (the angle recovered from the previous
position by atan2, plus the increment); its RRR dyad keeps the intersection nearest the previous
position, so the assembly is set by the initial position hint (our M = +1 here). It reports
points only: A (crank) and B (dyad), each with velocity and acceleration for ω = 1, ε = 0, which
are then the analogs. ``step_fast_with_kinematics`` is the path measured in both modes.
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["available", "cold_jit_seconds", "four_bar_run", "measure", "measure_pure"]

_CHILD = """
import sys, json
sys.modules['numba'] = None  # pylinkage then uses its no-op njit: pure Python
sys.path.insert(0, {root!r})
from bench.peers import measure
print(json.dumps(measure({n_time}, {n_error}, {repeat}, numba=False, n_ours={n_ours})))
"""


def available() -> str | None:
    """pylinkage's version, or None when it is not installed."""
    try:
        from importlib.metadata import version

        return version("pylinkage")
    except Exception:
        return None


def four_bar_run(count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, Any]:
    """Build the four-bar in pylinkage and run one turn of ``count`` steps: (pos, vel, acc) of A, B
    as arrays (count, 2, 2), at the angles 2πk/count, and the linkage (for re-running)."""
    from pylinkage.actuators import Crank
    from pylinkage.components import Ground
    from pylinkage.dyads import RRRDyad
    from pylinkage.simulation import Linkage

    from .alternatives import four_bar

    step = 2.0 * math.pi / count
    origin, pivot = Ground(0.0, 0.0, name="O"), Ground(0.4, 0.0, name="C")
    crank = Crank(anchor=origin, radius=0.1, angular_velocity=step, initial_angle=-step, name="crank")
    hint = four_bar(np.array([-step]))[0]["B"][0]
    dyad = RRRDyad(crank.output, pivot, distance1=0.4, distance2=0.3, x=float(hint[0]), y=float(hint[1]), name="B")
    linkage = Linkage([origin, pivot, crank, dyad], name="four-bar")
    linkage.set_input_velocity(crank, omega=1.0, alpha=0.0)
    pos, vel, acc = linkage.step_fast_with_kinematics(iterations=count)
    index = [linkage.components.index(c) for c in (crank, dyad)]
    return pos[:, index], vel[:, index], acc[:, index], linkage


def _ours(count: int) -> Callable[[], object]:
    """Our vectorised four-bar over ``count`` angles, every output with both analogs."""
    import solver

    scene = solver.load_scene("four_bar")
    phi = 2.0 * math.pi * np.arange(count) / count

    def run() -> None:
        k = scene.solve(phi, omega=1.0, epsilon=0.0)
        fetched = [k.point(p).acceleration for p in scene.output_points]
        fetched += [k.joint(j).acceleration for j in scene.output_joints]
        del fetched

    return run


def measure(n_time: int, n_error: int, repeat: int, *, numba: bool = True, n_ours: int = 1_000_000) -> dict[str, Any]:
    """Seconds per position (median of ``repeat`` runs of ``n_time`` steps), the one-off warm-up
    (first build and run, JIT compilation included), and the outputs of an ``n_error``-step turn.

    Each repetition also times our vectorised four-bar (``n_ours`` angles) right after pylinkage's
    run, so that the ratio of the two is measured under the same machine load.
    """
    start = time.perf_counter()
    four_bar_run(8)
    warmup = time.perf_counter() - start
    ours = _ours(n_ours)
    ours()
    times, ours_times = [], []
    for _ in range(repeat):
        start = time.perf_counter()
        four_bar_run(n_time)
        mid = time.perf_counter()
        ours()
        times.append(mid - start)
        ours_times.append(time.perf_counter() - mid)
    pos, vel, acc, _ = four_bar_run(n_error)
    return {
        "mode": "numba" if numba else "pure Python",
        "warmup_s": warmup,
        "per_position_s": float(np.median(times)) / n_time,
        "ours_per_position_s": float(np.median(ours_times)) / n_ours,
        "n_time": n_time,
        "outputs": {"A": [x[:, 0].tolist() for x in (pos, vel, acc)], "B": [x[:, 1].tolist() for x in (pos, vel, acc)]},
    }


_COLD = """
import sys, time
start = time.perf_counter()
sys.path.insert(0, {root!r})
from bench.peers import four_bar_run
four_bar_run(8)
print(time.perf_counter() - start)
"""


def cold_jit_seconds(root: str) -> float:
    """Import and first run with numba in a fresh process and an empty numba cache: the JIT warm-up
    a first-time user pays (later processes load the compiled code from numba's on-disk cache)."""
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        done = subprocess.run(
            [sys.executable, "-c", _COLD.format(root=root)], capture_output=True, text=True, check=True, env=env
        )
    return float(done.stdout.strip().splitlines()[-1])


def measure_pure(n_time: int, n_error: int, repeat: int, root: str, *, n_ours: int = 1_000_000) -> dict[str, Any]:
    """:func:`measure` in a child process without numba."""
    code = _CHILD.format(root=root, n_time=n_time, n_error=n_error, repeat=repeat, n_ours=n_ours)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    return json.loads(done.stdout.strip().splitlines()[-1])
