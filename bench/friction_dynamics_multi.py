"""Friction in the dynamics of several inputs: the cost of ``simulate`` with Coulomb friction over
the same run without (issue 29).

Run from the repository root::

    .venv/bin/python -m bench.friction_dynamics_multi            # 3 interleaved pairs
    .venv/bin/python -m bench.friction_dynamics_multi --quick    # 1 pair

The scene is tests/dynamics/scenes/friction_five_bar_pendulum.yaml (two inputs, a friction circle
at each of its five pins) against the same scene without its ``friction:`` key, both released from
rest at (q1, q2) = (−1.0, −1.9) rad and run for 1.4 s (the friction's run has both cranks moving
until 1.45 s), DOP853 at the same tolerance (rtol = atol = 1e-10). Timed by the thread's CPU time,
median of interleaved pairs in one process, each scene's compiled passes built before; the
machine's load average is printed beside it (issue 29's target: the whole run ≤ 3×).
"""

from __future__ import annotations

import argparse
import copy
import os
import sys
import time
from pathlib import Path

import numpy as np
import yaml

if __package__ in (None, ""):  # run as a file: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import solver
from solver._loader import parse_scene

ROOT = Path(__file__).resolve().parent.parent
SCENE = ROOT / "tests/dynamics/scenes/friction_five_bar_pendulum.yaml"
T_END = 1.4
TOL = 1e-10
START = (-1.0, -1.9)


def _scenes() -> tuple[solver.Scene, solver.Scene]:
    data = yaml.safe_load(SCENE.read_text(encoding="utf-8"))
    plain = copy.deepcopy(data)
    del plain["friction"]
    return solver.Scene(parse_scene(data, file=None)), solver.Scene(parse_scene(plain, file=None))


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    args = p.parse_args(argv)
    pairs = 1 if args.quick else 3
    with_f, without = _scenes()
    runs: dict[str, object] = {}

    def run(scene: solver.Scene, key: str) -> float:
        t = time.thread_time()
        runs[key] = scene.simulate(T_END, phi0=START, omega0=0.0, rtol=TOL, atol=TOL)
        return time.thread_time() - t

    run(with_f, "with"), run(without, "without")  # (compiled passes built, caches warm)
    a, b = [], []
    for _ in range(pairs):
        b.append(run(without, "without"))
        a.append(run(with_f, "with"))
    ta, tb = float(np.median(a)), float(np.median(b))
    na, nb = runs["with"].evaluations, runs["without"].evaluations  # type: ignore[attr-defined]
    load = os.getloadavg()
    print(f"{T_END} s from rest at rtol = atol = {TOL:g}: without friction {tb:.3f} s ({nb} evaluations), "
          f"with friction (5 pins, 2 inputs) {ta:.3f} s ({na} evaluations, "
          f"{len(runs['with'].switches)} stick/slip events); "  # type: ignore[attr-defined]
          f"ratio {ta / tb:.2f}, per evaluation {(ta / na) / (tb / nb):.2f} (median of {pairs} pairs, thread CPU "
          f"time; load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
