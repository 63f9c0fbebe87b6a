"""Friction: the cost of the kinetostatics with Coulomb friction over the same without (issue 29).

Run from the repository root::

    .venv/bin/python -m bench.friction            # 10⁵ samples, 9 interleaved pairs
    .venv/bin/python -m bench.friction --quick    # 10⁴ samples, 3 pairs
    .venv/bin/python -m bench.friction --pairs 25 # more pairs: a steadier median on a loaded machine

The scene is tests/forces/scenes/friction_slider_crank.yaml (friction circles at three pins and
friction in the guide: four elements) against the same scene without its ``friction:`` key; both
solved vectorised at ω = 15 rad/s, ε = 3 rad/s², efforts and every reaction read. Timed by the
thread's CPU time (a shared machine's load out of the ratio), median of interleaved pairs in one
process; the machine's load average is printed beside it (issue 29's target: ≤ 3×).
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
SCENE = ROOT / "tests/forces/scenes/friction_slider_crank.yaml"


def _scenes() -> tuple[solver.Scene, solver.Scene]:
    data = yaml.safe_load(SCENE.read_text(encoding="utf-8"))
    plain = copy.deepcopy(data)
    del plain["friction"]
    return solver.Scene(parse_scene(data, file=None)), solver.Scene(parse_scene(plain, file=None))


def _cpu(fn) -> float:  # type: ignore[no-untyped-def]
    t = time.thread_time()
    fn()
    return time.thread_time() - t


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--pairs", type=int, default=None, help="interleaved pairs (default 9; 1–3 with --quick)")
    args = p.parse_args(argv)
    n, pairs = (10_000, 3) if args.quick else (100_000, 9)
    pairs = args.pairs or pairs
    with_f, without = _scenes()
    phi = np.linspace(0.0, 2 * np.pi, n, endpoint=False)

    def run(scene: solver.Scene) -> None:
        k = scene.solve(phi, omega=15.0, epsilon=3.0)
        k.effort("crank")
        for pin in scene.pins:
            k.reaction(pin.point, on=pin.body, by=pin.other)
        k.slide_reaction("piston")

    run(with_f), run(without)
    a, b = [], []
    for _ in range(pairs):
        b.append(_cpu(lambda: run(without)))
        a.append(_cpu(lambda: run(with_f)))
    ta, tb = float(np.median(a)), float(np.median(b))
    load = os.getloadavg()[0]
    print(f"{n} samples: without friction {tb * 1e3:.1f} ms, with friction (4 elements) {ta * 1e3:.1f} ms, "
          f"ratio {ta / tb:.2f} (median of {pairs} pairs, thread CPU time; load average {load:.2f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
