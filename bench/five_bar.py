"""The five-bar (two inputs) over N samples of (q1, q2): ours with J and H against bare numpy (issue 14).

``python -m bench.five_bar [--count N] [--repeat R] [--ticks T]`` times, on the same N random
samples of (q1, q2) in [40°, 140°]² (default N = 10⁶), alternating within each repeat so that a
shared machine slows all alike, and prints the median of each:

* **bare numpy, positions only**: P from the closed form written out by hand for this one
  mechanism (circle intersection), no derivatives — the floor any general solver is held to;
* **ours, real motion**: ``scene.solve(q, omega=ω, epsilon=ε)`` — P, v = J·ω, a = J·ε + ωᵀHω and
  the joints, one pass;
* **ours, with J and H**: the same, then every output's ``.jacobian`` and ``.hessian`` (three
  more passes: e₁, e₂ and e₁ + e₂);

then the per-tick cost (one instant, plain Python floats): ``solve((q1, q2), omega, epsilon)``
and ``floats("P")``, and the same with P's jacobian and hessian, median over T ticks.
"""

from __future__ import annotations

import argparse
import math
import platform
import statistics
import time
from collections.abc import Callable, Sequence

import numpy as np

import solver

__all__ = ["bare_positions", "main", "measure"]

CRANK, DISTAL, BASE = 0.15, 0.25, 0.2
OMEGA = (2.0, -1.5)
EPSILON = (0.7, 3.0)


def bare_positions(q: np.ndarray) -> np.ndarray:
    """P of the shipped five-bar, (N, 2) from (N, 2) inputs: positions only, bare numpy."""
    a1 = CRANK * np.exp(1j * q[:, 0])
    a2 = BASE + CRANK * np.exp(1j * q[:, 1])
    d = a2 - a1
    dd = d.real * d.real + d.imag * d.imag
    h = np.sqrt(DISTAL * DISTAL / dd - 0.25)
    p = 0.5 * (a1 + a2) + 1j * h * d  # on the left of A1 → A2 (M = −1)
    return np.stack([p.real, p.imag], axis=-1)


def _ours(scene: solver.Scene, q: np.ndarray, derivatives: bool) -> float:
    t = time.perf_counter()
    k = scene.solve(q, omega=OMEGA, epsilon=EPSILON)
    for p in scene.output_points:
        m = k.point(p)
        if derivatives:
            m.jacobian, m.hessian  # noqa: B018  (evaluated on first access)
    for j in scene.output_joints:
        m = k.joint(j)
        if derivatives:
            m.jacobian, m.hessian  # noqa: B018
    return time.perf_counter() - t


def _bare(q: np.ndarray) -> float:
    t = time.perf_counter()
    bare_positions(q)
    return time.perf_counter() - t


def measure(count: int, repeat: int, ticks: int, seed: int = 14) -> dict[str, float]:
    """Median seconds of each vectorised variant over ``count`` samples, and µs per tick."""
    scene = solver.load_scene("five_bar")
    rng = np.random.default_rng(seed)
    q = np.radians(rng.uniform(40.0, 140.0, (count, 2)))
    err = np.abs(scene.solve(q).point("P").position - bare_positions(q)).max()
    runs: dict[str, list[float]] = {"bare": [], "motion": [], "jh": []}
    for _ in range(repeat):
        runs["bare"].append(_bare(q))
        runs["motion"].append(_ours(scene, q, False))
        runs["jh"].append(_ours(scene, q, True))
    out = {name: statistics.median(v) for name, v in runs.items()}
    out["agreement_m"] = float(err)
    samples = [(float(a), float(b)) for a, b in q[: max(ticks, 1)]]
    out["tick_us"] = _per_tick(scene, samples, lambda k: k.floats("P"))
    out["tick_jh_us"] = _per_tick(scene, samples, lambda k: (k.point("P").jacobian, k.point("P").hessian))
    return out


def _per_tick(
    scene: solver.Scene, samples: Sequence[tuple[float, float]], read: Callable[[solver.Kinematics], object]
) -> float:
    times = []
    for s in samples:
        t = time.perf_counter()
        read(scene.solve(s, omega=OMEGA, epsilon=EPSILON))
        times.append(time.perf_counter() - t)
    return statistics.median(times) * 1e6


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=1_000_000, help="samples of (q1, q2) (default 10⁶)")
    parser.add_argument("--repeat", type=int, default=5, help="repeats, median reported (default 5)")
    parser.add_argument("--ticks", type=int, default=2000, help="per-tick solves timed (default 2000)")
    args = parser.parse_args(argv)
    r = measure(args.count, args.repeat, args.ticks)
    n = args.count
    print(f"five_bar, N = {n} samples of (q1, q2) in [40°, 140°]², median of {args.repeat}; "
          f"{platform.processor() or platform.machine()}, Python {platform.python_version()}, numpy {np.__version__}")
    print(f"  bare numpy, P positions only     {r['bare'] * 1e3:10.1f} ms  {r['bare'] / n * 1e9:7.1f} ns/sample")
    print(f"  ours, P + joints, v and a        {r['motion'] * 1e3:10.1f} ms  {r['motion'] / n * 1e9:7.1f} ns/sample"
          f"  ×{r['motion'] / r['bare']:.1f}")
    print(f"  ours, + J and H of every output  {r['jh'] * 1e3:10.1f} ms  {r['jh'] / n * 1e9:7.1f} ns/sample"
          f"  ×{r['jh'] / r['bare']:.1f}")
    print(f"  positions agree to {r['agreement_m']:.1e} m")
    print(f"  per tick (one instant, floats): {r['tick_us']:.1f} µs; with P's J and H: {r['tick_jh_us']:.1f} µs"
          f" (median of {args.ticks})")
    return 0 if math.isfinite(r["jh"]) else 1


if __name__ == "__main__":
    raise SystemExit(main())
