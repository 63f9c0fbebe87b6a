"""Friction in the dynamics: the cost of ``simulate`` with Coulomb friction over the same run without (issue 29).

Run from the repository root::

    .venv/bin/python -m bench.friction_dynamics            # 5 interleaved pairs
    .venv/bin/python -m bench.friction_dynamics --quick    # 1 pair
    .venv/bin/python -m bench.friction_dynamics --pairs 15 # more pairs: a steadier median on a loaded machine

The scene is tests/dynamics/scenes/friction_four_bar_pendulum.yaml (a friction circle at each of its
four pins) against the same scene without its ``friction:`` key, both released from rest at
φ = 0.3 rad and run for 1.4 s (the friction's run sticks at 1.449 s: both move all along), DOP853
at the same tolerance (rtol = atol = 1e-10). Timed by the thread's CPU time (a shared machine's
load out of the ratio), median of interleaved pairs in one process, each scene's compiled instant
built before; the machine's load average is printed beside it. Also printed: the evaluations of
each run and the ratio of the time per evaluation (issue 29's target: the whole run ≤ 3×).
"""

from __future__ import annotations

import argparse
import copy
import os
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import yaml

if __package__ in (None, ""):  # run as a file: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import solver
from solver._loader import parse_scene

ROOT = Path(__file__).resolve().parent.parent
T_END = 1.4
TOL = 1e-10


@dataclass(frozen=True)
class Case:
    """One timed pair: a scene with ``friction:`` against itself without it."""

    scene: Path
    start: float | tuple[float, ...]
    what: str  # the friction, as printed
    pairs: int  # the default count of interleaved pairs


ONE_INPUT = Case(ROOT / "tests/dynamics/scenes/friction_four_bar_pendulum.yaml", 0.3, "4 pins", 5)
#: bench.friction_dynamics_multi's case: two inputs, released from rest at (q1, q2) = (−1.0, −1.9) rad;
#: the friction's run has both cranks moving until 1.45 s.
TWO_INPUTS = Case(ROOT / "tests/dynamics/scenes/friction_five_bar_pendulum.yaml", (-1.0, -1.9),
                  "5 pins, 2 inputs", 3)


def _scenes(case: Case) -> tuple[solver.Scene, solver.Scene]:
    data = yaml.safe_load(case.scene.read_text(encoding="utf-8"))
    plain = copy.deepcopy(data)
    del plain["friction"]
    return solver.Scene(parse_scene(data, file=None)), solver.Scene(parse_scene(plain, file=None))


def main(argv: list[str] | None = None, *, case: Case = ONE_INPUT) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--pairs", type=int, default=None,
                   help=f"interleaved pairs (default {case.pairs}; 1 with --quick)")
    args = p.parse_args(argv)
    pairs = args.pairs or (1 if args.quick else case.pairs)
    with_f, without = _scenes(case)
    runs: dict[str, object] = {}

    def run(scene: solver.Scene, key: str) -> float:
        t = time.thread_time()
        runs[key] = scene.simulate(T_END, phi0=case.start, omega0=0.0, rtol=TOL, atol=TOL)
        return time.thread_time() - t

    run(with_f, "with"), run(without, "without")  # (compiled instants built, caches warm)
    a, b = [], []
    for _ in range(pairs):
        b.append(run(without, "without"))
        a.append(run(with_f, "with"))
    ta, tb = float(np.median(a)), float(np.median(b))
    na, nb = runs["with"].evaluations, runs["without"].evaluations  # type: ignore[attr-defined]
    load = os.getloadavg()
    print(f"{T_END} s from rest at rtol = atol = {TOL:g}: without friction {tb:.3f} s ({nb} evaluations), "
          f"with friction ({case.what}) {ta:.3f} s ({na} evaluations, "
          f"{len(runs['with'].switches)} stick/slip events); "  # type: ignore[attr-defined]
          f"ratio {ta / tb:.2f}, per evaluation {(ta / na) / (tb / nb):.2f} (median of {pairs} pairs, thread CPU "
          f"time; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
