"""Every number of docs/dynamics.md's "Machine dynamics" and its steady-state sweep, measured.

``python -m bench.machine_numbers`` prints, with the wall time of each: the engine's gas work per
720° cycle, its steady speed, the bare engine (its flywheel taken off) — no steady motion, and
where it stalls — the flywheel for δ = 1/80 on the bare engine (exact and classical), the shipped
engine's δ and what ``flywheel_for(engine, 1/80)`` adds to it, the harvester's steady motion and
run-up, and the sweep: ``steady_state`` on every shipped one-input machine with extra flywheels
1e-4 … 10 kg·m² (``--quick``: the first and last three values), with the share that converged.
``tests/dynamics/test_dynamics_machine.py`` checks the docs' figures against :func:`numbers`.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np
import yaml

import solver
from solver.dynamics import flywheel_for, run_up, steady_state

#: One-input shipped scenes with a steady motion: a drive (motor) or a load doing net work
#: over a cycle (the engine's gas force), and something to take it (a brake, the crop).
MACHINES = ("engine", "harvester_finger")
#: The sweep's extra flywheels (kg·m²).
SWEEP = tuple(float(v) for v in np.geomspace(1e-4, 10.0, 11))


def bare_engine(folder: Path) -> Any:
    """The shipped engine without its ``flywheel:`` (the crank's own inertia only)."""
    data = yaml.safe_load(solver.find_scene("engine").read_text(encoding="utf-8"))
    data.pop("flywheel")
    path = folder / "engine_bare.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return solver.load_scene(path)


def _timed(f: Callable[[], Any]) -> tuple[Any, float]:
    began = time.perf_counter()
    out = f()
    return out, time.perf_counter() - began


def numbers(folder: Path) -> dict[str, Any]:
    """The figures of the docs, each with the seconds it took (``*_s``)."""
    out: dict[str, Any] = {}
    engine = solver.load_scene("engine")
    model = engine.reduced()
    phi = np.linspace(0.0, 4 * math.pi, 14401)
    gas = model.generalized_forces(phi, 200.0)["loads[0]"]  # the gas table's generalised force (N·m)
    out["gas_work_J"] = float(np.trapezoid(gas, phi))
    steady, out["steady_s"] = _timed(lambda: steady_state(engine))
    out["omega_mean"], out["rpm"] = steady.omega_mean, steady.omega_mean * 60 / (2 * math.pi)
    out["inv_delta"] = 1 / steady.delta
    bare = bare_engine(folder)
    try:
        steady_state(bare)
        out["bare"] = "steady"
    except solver.DynamicsError as error:
        out["bare"] = error.reason
    (jf, state, estimate), out["flywheel_bare_s"] = _timed(lambda: flywheel_for(bare, 1 / 80))
    out["flywheel_bare"], out["flywheel_bare_estimate"], out["flywheel_bare_inv_delta"] = jf, estimate, 1 / state.delta
    (extra, state, _), out["flywheel_engine_s"] = _timed(lambda: flywheel_for(engine, 1 / 80))
    out["flywheel_engine"], out["flywheel_engine_inv_delta"] = extra, 1 / state.delta
    harvester = solver.load_scene("harvester_finger")
    up = run_up(harvester)
    out["harvester_run_up"], out["harvester_mean"], out["harvester_delta"] = (
        up.time, up.steady.omega_mean, up.steady.delta)
    return out


def sweep(values: tuple[float, ...] = SWEEP) -> list[tuple[str, float, str, float]]:
    """(scene, extra flywheel, "1/δ = …" or the failure, seconds) of steady_state over ``values``."""
    rows = []
    for name in MACHINES:
        scene = solver.load_scene(name)
        for jf in values:
            began = time.perf_counter()
            try:
                s = steady_state(scene, flywheel=jf)
                text = f"ω_m = {s.omega_mean:.6g} rad/s, 1/δ = {1 / s.delta:.5g}"
            except solver.DynamicsError as error:
                text = f"FAILED: {error}"
            rows.append((name, jf, text, time.perf_counter() - began))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="sweep the first and last three flywheels only")
    args = parser.parse_args()
    import tempfile

    print(f"load average {os.getloadavg()}")
    with tempfile.TemporaryDirectory() as folder:
        for key, value in numbers(Path(folder)).items():
            print(f"{key}: {value:.6g}" if isinstance(value, float) else f"{key}: {value}")
    values = SWEEP[:3] + SWEEP[-3:] if args.quick else SWEEP
    rows = sweep(values)
    for name, jf, text, seconds in rows:
        print(f"| {name} | {jf:.3g} | {text} | {seconds:.1f} s |")
    ok = sum("FAILED" not in text for _, _, text, _ in rows)
    print(f"steady states converged: {ok} of {len(rows)} ({100 * ok / len(rows):.0f} %)")
    print(f"load average {os.getloadavg()}")


if __name__ == "__main__":
    main()
