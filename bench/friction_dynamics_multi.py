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

import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a file: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from bench.friction_dynamics import TWO_INPUTS, main

if __name__ == "__main__":
    sys.exit(main(case=TWO_INPUTS))
