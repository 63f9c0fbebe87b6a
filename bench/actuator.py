"""Linear actuators: the actuator group against the RRR dyad, and the excavator's relay against the five-bar's.

``python -m bench.actuator [--quick] [--repeat R]`` prints two tables (a benchmark, not a test):

1. **One group** (issue 25's target: an actuator costs no more than an ``rrr`` group, the same
   circle intersection): ``group.solve(ctx)`` alone, its inputs' jets prepared once —
   the actuator of ``tipper`` (fixed base and pivot, the stroke s with s' = 1) against an RRR dyad
   with the same circle (one end moving like a crank's pin, the other fixed, as in a four-bar);
   per instant (plain Python floats, µs per call) and vectorised (numpy, ns per sample over
   N = 8192 samples); and the compiled per-tick function of ``tipper`` against ``four_bar``'s
   (``scene.instant``: the whole scene, positions, velocities, accelerations and forces; both
   scenes have bodies and loads).
2. **Relay per message** (target: the excavator ≤ 1.5× the five-bar): mechanism_node's topic
   mode without rclpy (``Runtime.answer``: the relay reads the JointState, solves it, packs and
   serialises every topic), three cylinder strokes in for the excavator (every joint, the
   bucket tip's position and velocity and the three cylinder forces out), two angles for the
   five-bar; mean µs per message over a sequence of inputs, best of the passes.

Round-robin timing (bench._common.median_times) so that the machine's load falls on all alike.
"""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a file: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import numpy as np

import solver
from bench._common import machine, median_times
from solver._backend import NUMPY, SCALAR
from solver.groups import RRR, Actuator, Context
from solver.jet import Jet, constant

__all__ = ["group_times", "relay_times", "main"]

NS = 1_000_000_000
STAMP_STEP_NS = 10_000_000
N_VECTOR = 8192


def _pair() -> tuple[Actuator, RRR, complex, complex]:
    """The tipper's actuator, and an RRR dyad closing the same circle: ends A (a crank's pin
    moving about the fixed base) and O, lengths (s, l)."""
    scene = solver.load_scene("tipper")
    act = next(g for g in scene.ordered if isinstance(g, Actuator))
    base, pivot = complex(scene.plan.fixed[act.base]), complex(scene.plan.fixed[act.pivot])
    rrr = RRR(name="dyad", ends=("A", "O"), point="C", lengths=(1.0, act.length), mode=act.mode)
    return act, rrr, base, pivot


def group_times(repeat: int, calls: int) -> dict[str, float]:
    """µs per call (scalar) and ns per sample (vectorised) of each group's solve."""
    act, rrr, base, pivot = _pair()
    s = 1.0
    arm = complex(0.3, 0.2)  # the crank's pin relative to the base: A = base + arm, A' = j·arm, A'' = −arm

    def act_scalar() -> None:
        for _ in range(calls):
            ctx = Context(phi=s, xp=SCALAR, values={act.base: constant(base), act.pivot: constant(pivot)})
            act.solve(ctx)

    def rrr_scalar() -> None:
        for _ in range(calls):
            ctx = Context(phi=s, xp=SCALAR,
                          values={"A": Jet(base + arm, 1j * arm, -arm), "O": constant(pivot)})
            rrr.solve(ctx)

    strokes = np.linspace(0.8, 1.25, N_VECTOR)
    arms = 0.3 * np.exp(1j * np.linspace(0.0, 1.0, N_VECTOR))
    pins = Jet(base + arms, 1j * arms, -arms)

    def act_vector() -> None:
        ctx = Context(phi=strokes, xp=NUMPY, values={act.base: constant(base), act.pivot: constant(pivot)})
        act.solve(ctx)

    def rrr_vector() -> None:
        ctx = Context(phi=strokes, xp=NUMPY, values={"A": pins, "O": constant(pivot)})
        rrr.solve(ctx)

    # both with bodies, gravity and loads: the compiled instant then includes the force layer
    tipper, four_bar = solver.load_scene("tipper").everything(), solver.load_scene("four_bar_loaded").everything()
    tipper.instant(1.0, 0.1, 0.0)
    four_bar.instant(1.0, 0.1, 0.0)

    def tipper_instant() -> None:
        for i in range(calls):
            tipper.instant(0.8 + 4e-4 * (i % 1000), 0.1, 0.0)

    def four_bar_instant() -> None:
        for i in range(calls):
            four_bar.instant(0.8 + 4e-4 * (i % 1000), 0.1, 0.0)

    with np.errstate(all="ignore"):
        t = median_times({"actuator scalar": act_scalar, "rrr scalar": rrr_scalar,
                          "actuator vector": act_vector, "rrr vector": rrr_vector,
                          "tipper instant": tipper_instant, "four_bar instant": four_bar_instant}, repeat=repeat)
    out = {k: v / calls * 1e6 for k, v in t.items() if "vector" not in k}
    out.update({k: v / N_VECTOR * 1e9 for k, v in t.items() if "vector" in k})
    return out


def _runtime(scene: str, first: Sequence[float]) -> Any:
    from rosbags.typesys import Stores, get_typestore

    from linkage_ros.runtime import Runtime

    store = get_typestore(Stores.ROS2_JAZZY)
    runtime = Runtime({"scene": scene, "input_source": "topic", "input_phi0s": list(first)}, store.types,
                      serialize=store.serialize_cdr)
    assert runtime.relay is not None
    return runtime


def _messages(runtime: Any, rows: Sequence[Sequence[float]], rates: Sequence[float]) -> Callable[[], float]:
    """One pass over ``rows``: mean µs per ``Runtime.answer``."""
    names = list(runtime.relay.input_joints)
    stamp = [NS]

    def run() -> float:
        clock = time.perf_counter
        start = clock()
        for q in rows:
            stamp[0] += STAMP_STEP_NS
            runtime.answer(names, list(q), list(rates), stamp[0])
        return (clock() - start) / len(rows) * 1e6

    return run


def relay_times(repeat: int, count: int) -> dict[str, float]:
    """Mean µs per message, best of ``repeat`` passes, excavator and five-bar alternating."""
    rng = np.random.default_rng(25)
    excavator = solver.load_scene("excavator")
    lo = np.array([r[0] for r in excavator.input_ranges])
    hi = np.array([r[1] for r in excavator.input_ranges])
    strokes = lo + (hi - lo) * rng.uniform(0.05, 0.95, (count, 3))
    angles = np.radians(rng.uniform(40.0, 140.0, (count, 2)))
    passes: dict[str, list[float]] = {"excavator": [], "five_bar": []}
    runs = {
        "excavator": _messages(_runtime("excavator", strokes[0]), strokes.tolist(), (0.05, -0.08, 0.1)),
        "five_bar": _messages(_runtime("five_bar", angles[0]), angles.tolist(), (2.0, -1.5)),
    }
    for run in runs.values():  # warm-up: templates, fast path, every traced branch
        run()
    for _ in range(repeat):
        for name, run in runs.items():
            passes[name].append(run())
    return {name: min(v) for name, v in passes.items()}


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m bench.actuator", description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="fewer calls and messages (seconds)")
    p.add_argument("--repeat", type=int, default=7)
    args = p.parse_args(argv)
    calls, count = (2000, 300) if args.quick else (20000, 2000)
    info = machine()
    print(f"measured on {info.get('cpu', '?')}, {info.get('cores', '?')} cores, Python {info.get('python', '?')}; "
          f"median of {args.repeat} rounds (relay: best of {args.repeat} passes)")
    g = group_times(args.repeat, calls)
    print("\n| one group | actuator (tipper) | rrr (same circle) | ratio |\n|---|---:|---:|---:|")
    print(f"| per instant, µs per solve | {g['actuator scalar']:.2f} | {g['rrr scalar']:.2f} | "
          f"{g['actuator scalar'] / g['rrr scalar']:.2f} |")
    print(f"| vectorised, ns per sample (N = {N_VECTOR}) | {g['actuator vector']:.1f} | {g['rrr vector']:.1f} | "
          f"{g['actuator vector'] / g['rrr vector']:.2f} |")
    print(f"| compiled scene.instant, µs (tipper / four_bar_loaded, everything) | {g['tipper instant']:.2f} | "
          f"{g['four_bar instant']:.2f} | {g['tipper instant'] / g['four_bar instant']:.2f} |")
    r = relay_times(args.repeat, count)
    print("\n| relay per message (Runtime.answer, every topic) | µs |\n|---|---:|")
    print(f"| excavator: 3 strokes in; joints, tip, 3 cylinder forces out | {r['excavator']:.1f} |")
    print(f"| five_bar: 2 angles in | {r['five_bar']:.1f} |")
    print(f"| ratio (target ≤ 1.5) | {r['excavator'] / r['five_bar']:.2f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
