"""Speed against error: measure every method, write docs/speed-vs-error.md and .png.

Run from the repository root::

    .venv/bin/python -m bench.speed_vs_error            # full run (a few minutes), writes docs/
    .venv/bin/python -m bench.speed_vs_error --quick    # seconds; writes bench/.cache/quick/

(``python bench/speed_vs_error.py`` works too.) Needs numpy, mpmath, matplotlib; pylinkage 1.3.0
and numba are measured when installed; the node engine (linkage_ros, rosbags) when importable.
The mpmath reference is cached under bench/.cache/ (ignored by git).
"""

from __future__ import annotations

import argparse
import cProfile
import io
import json
import math
import pstats
import sys
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a file: make the repository root importable
    sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

import numpy as np

import solver
from bench import alternatives, integration, newton, node_cost, peers
from bench._common import (
    CACHE,
    ROOT,
    SCENES,
    errors_against,
    machine,
    median_time,
    median_times,
    reference,
    turn,
)
from bench.forces import carry_section
from bench.instant import carry_section as carry_instant

__all__ = ["Config", "Result", "main", "measure"]


@dataclass(frozen=True)
class Config:
    quick: bool
    n_reference: int  # angles of the error turn
    n_time: int  # angles of a vectorised timing run
    n_scalar: int  # calls of a scalar timing run
    repeat: int
    n_peer_pure: int
    duration: float  # simulated seconds of time integration
    sample_every: float
    ticks: int  # node ticks per timing run

    @staticmethod
    def make(quick: bool) -> Config:
        if quick:
            return Config(True, 48, 100_000, 200, 3, 300, 60.0, 10.0, 100)
        return Config(False, 720, 1_000_000, 3000, 5, 3000, 3600.0, 1.0, 2000)


@dataclass
class Result:
    scene: str
    method: str
    family: str  # ours | finite differences | complex step | Newton | peer
    seconds: float  # per position
    errors: dict[str, float]
    note: str = ""


@dataclass
class Report:
    config: Config
    machine: dict[str, str]
    results: list[Result] = field(default_factory=list)
    peers: dict[str, Any] = field(default_factory=dict)
    integration: list[Any] = field(default_factory=list)
    node: dict[str, Any] | None = None
    memory: dict[str, float] = field(default_factory=dict)
    profiles: dict[str, str] = field(default_factory=dict)
    breakdown: dict[str, float] = field(default_factory=dict)
    wall_s: float = 0.0


def _ours_outputs(scene: solver.Scene, k: solver.Kinematics) -> tuple[dict, dict]:
    quantities = ("position", "velocity", "acceleration")
    pts = {p: tuple(getattr(k.point(p), q) for q in quantities) for p in scene.output_points}
    jts = {j: tuple(getattr(k.joint(j), q) for q in quantities) for j in scene.output_joints}
    return pts, jts


def _vectorised(scene: solver.Scene, phi: np.ndarray) -> tuple[dict, dict]:
    return _ours_outputs(scene, scene.solve(phi, omega=1.0, epsilon=0.0))


def _scalar(scene: solver.Scene, phi: Sequence[float] | np.ndarray) -> tuple[dict, dict]:
    rows = [_ours_outputs(scene, scene.solve(float(f), omega=1.0, epsilon=0.0)) for f in phi]
    pts = {p: tuple(np.array([r[0][p][i] for r in rows]) for i in range(3)) for p in rows[0][0]}
    jts = {j: tuple(np.array([r[1][j][i] for r in rows]) for i in range(3)) for j in rows[0][1]}
    return pts, jts


def _profile(fn: Callable[[], object], lines: int = 12) -> str:
    prof = cProfile.Profile()
    prof.enable()
    fn()
    prof.disable()
    text = io.StringIO()
    pstats.Stats(prof, stream=text).strip_dirs().sort_stats("tottime").print_stats(lines)
    body = text.getvalue().strip().splitlines()
    start = next((i for i, line in enumerate(body) if line.lstrip().startswith("ncalls")), 0)
    calls = [line.strip() for line in body if "function calls" in line][:1]
    return "\n".join(calls + [line.rstrip() for line in body[start:] if line.strip()])


def _kinematics(report: Report, name: str, log: Callable[[str], None]) -> None:
    cfg = report.config
    ref = reference(name, cfg.n_reference)
    scene = solver.load_scene(name)
    phi_time = turn(cfg.n_time)
    add = report.results.append

    t = median_time(lambda: _vectorised(scene, phi_time), repeat=cfg.repeat) / cfg.n_time
    add(Result(name, "ours, vectorised", "ours", t, errors_against(ref, *_vectorised(scene, ref.phi))))
    sweep = turn(cfg.n_scalar)
    t = median_time(lambda: _scalar(scene, sweep), repeat=max(cfg.repeat // 2, 1)) / cfg.n_scalar
    add(Result(name, "ours, scalar (one φ per call)", "ours", t, errors_against(ref, *_scalar(scene, ref.phi))))
    log(f"  {name}: ours done")

    phi_alt = turn(cfg.n_time // 5)  # time per position is flat beyond ~10⁵ angles
    t = median_time(lambda: alternatives.complex_step(name, phi_alt), repeat=cfg.repeat) / len(phi_alt)
    errs = errors_against(ref, *alternatives.complex_step(name, ref.phi))
    add(Result(name, "complex step", "complex step", t, errs, "d² by central difference of complex steps"))
    t = median_time(lambda: alternatives.central_differences(name, phi_alt, 1e-4), repeat=cfg.repeat) / len(phi_alt)
    for h in alternatives.FD_STEPS:
        errs = errors_against(ref, *alternatives.central_differences(name, ref.phi, h))
        add(Result(name, f"central differences h={h:.0e}", "finite differences", t, errs))
    for tol in newton.TOLERANCES:
        box: dict[str, Any] = {}

        def sweep_newton(tol: float = tol, box: dict[str, Any] = box) -> None:
            box["out"] = newton.solve_sweep(name, ref.phi, tol)

        t = median_time(sweep_newton, repeat=max(cfg.repeat // 2, 1)) / len(ref.phi)
        q, v, a, iterations = box["out"]
        errs = errors_against(ref, *newton.outputs(name, q, v, a))
        add(Result(name, f"Newton–Raphson tol={tol:.0e}", "Newton", t, errs, f"{iterations:.2f} iterations per angle"))
    log(f"  {name}: alternatives done")


def _peers(report: Report, log: Callable[[str], None]) -> None:
    cfg = report.config
    version = peers.available()
    if version is None:
        report.peers = {"missing": "pylinkage is not installed (pip install pylinkage==1.3.0 numba)"}
        return
    ref = reference("four_bar", cfg.n_reference)
    report.peers["version"] = version
    runs = []
    try:
        import numba  # noqa: F401

        runs.append(peers.measure(cfg.n_time, cfg.n_reference, cfg.repeat, numba=True, n_ours=cfg.n_time))
        if not cfg.quick:
            report.peers["cold_jit_s"] = peers.cold_jit_seconds(str(ROOT))
    except ImportError:
        report.peers["numba"] = "numba is not installed"
    runs.append(peers.measure_pure(cfg.n_peer_pure, cfg.n_reference, cfg.repeat, str(ROOT), n_ours=cfg.n_time))
    for run in runs:
        outputs = {p: tuple(np.asarray(x) for x in v) for p, v in run["outputs"].items()}
        errs = errors_against(ref, outputs, {})
        note = f"warm-up {run['warmup_s']:.2f} s (cached JIT; cold: see below), apart" if run["mode"] == "numba" else ""
        note += ("; " if note else "") + "points A, B only (no joint angles)"
        report.results.append(
            Result("four_bar", f"pylinkage {version}, {run['mode']}", "peer", run["per_position_s"], errs, note)
        )
        report.peers[run["mode"]] = {
            "warmup_s": run["warmup_s"],
            "n_time": run["n_time"],
            "per_position_s": run["per_position_s"],
            "ours_per_position_s": run["ours_per_position_s"],
        }
    if "numba" not in report.peers or not isinstance(report.peers["numba"], dict):
        return
    # drift over a long run: pylinkage re-derives the crank angle from the last position each step
    count = cfg.n_time
    pos, vel, _, _ = peers.four_bar_run(count)
    exact = alternatives.four_bar(turn(count))[0]
    report.peers["drift"] = {
        "steps": count,
        "position": float(np.max(np.abs(pos[:, 1] - exact["B"]))) / 0.4,
    }
    log("  pylinkage done")


def measure(cfg: Config, log: Callable[[str], None] = print) -> Report:
    start = time.perf_counter()
    report = Report(cfg, machine())
    for name in SCENES:
        _kinematics(report, name, log)
    _peers(report, log)
    report.integration = [
        asdict(r)
        for r in integration.run(
            duration=cfg.duration, sample_every=cfg.sample_every, tick_count=20_000 if not cfg.quick else 2_000
        )
    ]
    log("  time integration done")
    report.node = node_cost.tick_cost(ticks=cfg.ticks, repeat=max(cfg.repeat // 2, 1))
    report.memory = node_cost.memory_per_million(cfg.n_time)
    log("  node engine and memory done")
    ours = next(r for r in report.results if r.scene == "four_bar" and r.method == "ours, vectorised")
    scene = solver.load_scene("four_bar")
    phi = turn(cfg.n_time)
    breakdown = median_times(
        {
            "solve() alone": lambda: scene.solve(phi, omega=1.0, epsilon=0.0),
            "solve() and every output fetched": lambda: _vectorised(scene, phi),
            "bare numpy positions only (bench copy)": lambda: alternatives.four_bar(phi),
        },
        repeat=cfg.repeat,
    )
    report.breakdown = {k: v / cfg.n_time for k, v in breakdown.items()}
    if ours.seconds > 0.15e-6 or cfg.quick:
        report.profiles["four_bar vectorised solve, 10⁶ angles"] = _profile(
            lambda: _vectorised(scene, turn(cfg.n_time))
        )
    if report.node and "tick" in report.node and (report.node["tick"] > 100.0 or cfg.quick):
        parts = node_cost.setup()
        assert not isinstance(parts, str)  # tick_cost above measured it
        engine, builder, _ = parts
        node_cost.run_ticks(engine, builder, [i * 1e-3 for i in range(50)])  # warm
        times = [1.0 + i * 1e-3 for i in range(500)]
        report.profiles["node tick (harvester_finger), 500 ticks"] = _profile(
            lambda: node_cost.run_ticks(engine, builder, times), lines=16
        )
    report.wall_s = time.perf_counter() - start
    return report


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description="Speed against error: writes speed-vs-error.md and .png")
    parser.add_argument("--quick", action="store_true", help="small sizes (seconds), for smoke tests")
    parser.add_argument("--out", type=Path, help="output folder (default: docs/, or bench/.cache/quick/ with --quick)")
    args = parser.parse_args(argv)
    from bench.report import write  # matplotlib only here

    cfg = Config.make(args.quick)
    out = args.out or (CACHE / "quick" if args.quick else ROOT / "docs")
    out.mkdir(parents=True, exist_ok=True)
    report = measure(cfg, lambda s: print(s, file=sys.stderr, flush=True))
    (CACHE / ("results_quick.json" if cfg.quick else "results.json")).write_text(
        json.dumps(asdict(report), indent=1, default=float)
    )
    # bench/forces.py's and bench/instant.py's sections survive the rewrite
    with carry_section(out / "speed-vs-error.md"), carry_instant(out / "speed-vs-error.md"):
        md, png = write(report, out)
    print(f"wrote {md} and {png} in {report.wall_s:.0f} s")
    return 0 if all(math.isfinite(r.seconds) for r in report.results) else 1


if __name__ == "__main__":
    sys.exit(main())
