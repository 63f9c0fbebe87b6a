"""Synthesis figures (issue 23) for docs/synthesis.md: not timed tests, a report.

    python -m bench.synthesis [five] [seven] [six] [ten] [population] [--cases=A-B] [--workers=N] [--write]

* **five** — path generation without timing, 5 targets on a crank-rocker's coupler curve, every
  dimension of config/templates/four_bar_path.yaml free: ``solver.synthesize``'s time and largest
  miss (checked by solving the returned scene) against pylinkage 1.3's ``path_generation`` on the
  same targets, whose returned four-bars are solved here by this project's solver (the largest
  miss of the best of them: each target's distance to its coupler curve, 20,000 samples a turn).
* **seven** — issue 32's benchmark: 20 path instances with an exact solution, 7 coupler points
  (sorted input angles) of random crank-rockers (fixed RNG), the default seed: wall and CPU time
  (the machine is shared: the load average after each case is printed beside it; CPU counts the
  pool's processes with ``--workers=N``), starts, the largest miss solving the returned scene.
* **six** — 6 coupler points of 4 random crank-rockers, seeds 0–4: the time by seed.
* **ten** — 10 targets on the coupler curves of 3 random crank-rockers, 150 s each: the largest
  miss over the curve's size and whether it reached 1e-9 m.
* **population** — one population of 400 four-bars × 360 positions in one pass of the plan
  against the kinematics of one candidate over 144,000 positions (``Scene.solve``).

``--write`` replaces the "## Figures" section of docs/synthesis.md.
"""

from __future__ import annotations

import math
import os
import resource
import sys
import time
from pathlib import Path

import numpy as np

import solver
from solver._loader import parse_scene
from solver.synthesis import load_template
from solver.synthesis.population import run

from ._common import machine, median_time, write_section

ROOT = Path(__file__).resolve().parents[1]
TEMPLATE = ROOT / "config" / "templates" / "four_bar_path.yaml"
DOC = ROOT / "docs" / "synthesis.md"
#: the crank-rocker of tests/synthesis (ground 0.403, crank 0.1, coupler 0.35, rocker 0.3; P on AB)
CRANK_ROCKER = np.array([0.0, 0.0, 0.4, 0.05, 0.1, 0.35, 0.3, 0.2, 30.0])


def _targets(template, x: np.ndarray, phi: np.ndarray) -> np.ndarray:  # type: ignore[no-untyped-def]
    return template.scene(x).with_outputs(points=["P"], joints=[]).solve(phi).point("P").position


def _curve_miss(scene: solver.Scene, name: str, targets: np.ndarray, samples: int = 20_000) -> float:
    """Largest distance from a target to the scene's traced curve (a polyline of ``samples``)."""
    phi = np.linspace(0.0, 2 * math.pi, samples + 1)
    k = scene.with_outputs(points=[name], joints=[], forces=False).solve(phi, mask=True)
    xy = k.point(name).position
    z = np.where(k.valid, xy[:, 0] + 1j * xy[:, 1], np.nan)
    p, q = z[:-1], z[1:]
    seg = q - p
    worst = 0.0
    for t in targets:
        w = complex(t[0], t[1]) - p
        with np.errstate(all="ignore"):
            s = np.clip((w.real * seg.real + w.imag * seg.imag) / np.abs(seg) ** 2, 0.0, 1.0)
        d = np.abs(w - np.nan_to_num(s) * seg)
        worst = max(worst, float(np.nanmin(d)))
    return worst


def _pylinkage_scene(sol) -> solver.Scene | None:  # type: ignore[no-untyped-def]
    """A pylinkage FourBarSolution as a scene of this project (crank A→B, coupler B→C, rocker D→C,
    coupler point P on BC), in the assembly its initial pose shows."""
    a, d, b, c = (complex(*p) for p in (sol.ground_pivot_a, sol.ground_pivot_d, sol.crank_pivot_b,
                                         sol.coupler_pivot_c))
    if sol.coupler_point is None:
        return None
    p = complex(*sol.coupler_point)
    mode = 1 if ((c - b).conjugate() * (d - b)).imag > 0 else -1
    rel = (p - b) / (c - b)
    data = {
        "scene": "pylinkage_solution", "units": {"length": "m", "angle": "rad"},
        "fixed": {"A0": [a.real, a.imag], "D0": [d.real, d.imag]},
        "groups": [
            {"type": "crank", "name": "crank", "center": "A0", "point": "B", "length": abs(b - a)},
            {"type": "rrr", "name": "dyad", "ends": ["B", "D0"], "point": "C", "lengths": [abs(c - b), abs(c - d)],
             "M": mode},
            {"type": "attached", "name": "cp", "point": "P", "base": "B", "along": ["B", "C"],
             "distance": abs(p - b), "angle": math.atan2(rel.imag, rel.real)},
        ],
        "outputs": {"points": ["P"]},
    }
    try:
        return solver.Scene(parse_scene(data, file=None))
    except solver.SolverError:
        return None


def five() -> str:
    import warnings

    from pylinkage.synthesis import path_generation

    t = load_template(TEMPLATE)
    rows = []
    for case in range(3):
        phi = np.sort(np.random.default_rng(case).uniform(0.0, 2 * math.pi, 5))
        targets = _targets(t, CRANK_ROCKER, phi)
        t0 = time.perf_counter()
        res = solver.synthesize(t, point="P", through=targets, seed=case)
        ours = time.perf_counter() - t0
        got = res.scene.with_outputs(points=["P"], joints=[]).solve(res.phases).point("P").position
        ours_miss = float(np.abs(np.hypot(*(got - targets).T)).max())
        t0 = time.perf_counter()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            pl = path_generation([tuple(map(float, p)) for p in targets])
        theirs = time.perf_counter() - t0
        misses = [_curve_miss(s, "P", targets) for s in map(_pylinkage_scene, pl.raw_solutions) if s is not None]
        best = min(misses, default=math.inf)
        rows.append(f"| {case} | {ours:.2f} s | {ours_miss:.1e} m | {len(res.solutions)} | {theirs:.2f} s | "
                    f"{best:.1e} m | {len(pl.raw_solutions)} |")
    head = ("| case | synthesize | largest miss | designs | pylinkage 1.3 path_generation | best largest miss | "
            "returned |\n|---|---|---|---|---|---|---|")
    return "### Five targets, all nine dimensions free\n\n" + head + "\n" + "\n".join(rows) + "\n"


def _random_crank_rocker(rng: np.random.Generator, t) -> np.ndarray:  # type: ignore[no-untyped-def]
    """A random crank-rocker of the template's ranges whose transmission angle stays ≥ 40°."""
    while True:
        x = rng.uniform(t.lo, t.hi)
        x[4] = rng.uniform(0.05, 0.2)
        scene = t.scene(x).with_outputs(points=["B"], joints=[])
        k = scene.solve(np.linspace(0, 2 * math.pi, 720, endpoint=False), mask=True)
        if k.valid.all() and k.conditioning["dyad"].min() >= math.sin(math.radians(40)):
            return x


def ten() -> str:
    t = load_template(TEMPLATE)
    rows = []
    rng = np.random.default_rng(10)
    hits = exact = 0
    for case in range(3):
        x = _random_crank_rocker(rng, t)
        phi = np.sort(rng.uniform(0.0, 2 * math.pi, 10))
        targets = _targets(t, x, phi)
        size = float(np.ptp(targets[:, 0]) + np.ptp(targets[:, 1]))
        t0 = time.perf_counter()
        try:
            res = solver.synthesize(t, point="P", through=targets, seed=case, time_limit=150.0, starts=1000)
            got = res.scene.with_outputs(points=["P"], joints=[]).solve(res.phases).point("P").position
            miss = float(np.hypot(*(got - targets).T).max())
            starts, expired = res.starts, res.expired
        except solver.SynthesisError:
            miss, starts, expired = math.inf, 0, True
        took = time.perf_counter() - t0
        hits += miss <= 1e-4 * size
        exact += miss <= 1e-9
        rows.append(f"| {case} | {took:.1f} s | {starts} | {miss:.1e} m | {miss / size:.1e} | "
                    f"{'yes' if miss <= 1e-9 else 'no'} | {'yes' if expired else 'no'} |")
    head = ("| case | time | starts | largest miss | over the curve's size | ≤ 1e-9 m | time limit hit |\n"
            "|---|---|---|---|---|---|---|")
    return (f"### Ten targets, three random crank-rockers, 150 s each\n\n{head}\n" + "\n".join(rows)
            + f"\n\nWithin 1e-4 of the curve's size: {hits} of 3; exact to 1e-9 m: {exact} of 3.\n")


def instances(count: int, targets: int, seed: int) -> list[tuple[np.ndarray, np.ndarray]]:
    """``count`` path instances with an exact solution: ``targets`` coupler points (sorted input
    angles) of random crank-rockers of the template (:func:`_random_crank_rocker`), fixed RNG."""
    t = load_template(TEMPLATE)
    rng = np.random.default_rng(seed)
    out = []
    for _ in range(count):
        x = _random_crank_rocker(rng, t)
        phi = np.sort(rng.uniform(0.0, 2 * math.pi, targets))
        out.append((x, _targets(t, x, phi)))
    return out


def _cpu() -> float:
    """CPU seconds of this process and of its ended children (the pool of ``workers=N``)."""
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime + kids.ru_utime + kids.ru_stime


def _solve_case(targets: np.ndarray, seed: int, workers: int | None = None) -> tuple[float, float, float, int]:
    """(wall s, CPU s — with the pool's processes —, largest miss m — inf when it raised —,
    starts read) of one synthesize call."""
    t = load_template(TEMPLATE)
    w0, c0 = time.perf_counter(), _cpu()
    try:
        res = solver.synthesize(t, point="P", through=targets, seed=seed, workers=workers)
        got = res.scene.with_outputs(points=["P"], joints=[]).solve(res.phases).point("P").position
        miss, starts = float(np.hypot(*(got - targets).T).max()), res.starts
    except solver.SynthesisError:
        miss, starts = math.inf, 0
    return time.perf_counter() - w0, _cpu() - c0, miss, starts


def _load() -> str:
    return " ".join(f"{v:.2f}" for v in os.getloadavg())


def seven(count: int = 20, cases: range | None = None, workers: int | None = None) -> str:
    """Issue 32's benchmark: 20 random 7-point instances, the default seed (``cases``: a part;
    ``workers``: local processes, synthesize's keyword)."""
    rows, walls, cpus, exact = [], [], [], 0
    chosen = cases or range(count)
    for case, (_, targets) in enumerate(instances(count, 7, 32)):
        if case not in chosen:
            continue
        wall, cpu, miss, starts = _solve_case(targets, 0, workers)
        walls.append(wall)
        cpus.append(cpu)
        exact += miss <= 1e-9
        size = float(np.max(np.abs(targets[:, None] - targets[None]).sum(axis=2)))
        rows.append(f"| {case} | {size:.3f} m | {wall:.1f} s | {cpu:.1f} s | {starts} | {miss:.1e} m | "
                    f"{'yes' if miss <= 1e-9 else 'no'} | {_load()} |")
        print(rows[-1], file=sys.stderr, flush=True)
    head = ("| case | targets' size | wall | CPU | starts | largest miss | ≤ 1e-9 m | load after |\n"
            "|---|---|---|---|---|---|---|---|")
    return (f"### Seven targets, {count} random crank-rockers, seed 0\n\n{head}\n" + "\n".join(rows)
            + f"\n\nExact (≤ 1e-9 m, solving the returned scene): {exact} of {count}; median wall "
            f"{float(np.median(walls)):.1f} s, median CPU {float(np.median(cpus)):.1f} s (max {max(cpus):.1f} s).\n"
            ).replace(f"{exact} of {count}", f"{exact} of {len(rows)}")


def six(count: int = 4, seeds: int = 5, workers: int | None = None) -> str:
    """Six targets, seeds 0–4: the time by seed."""
    rows, worst = [], 0.0
    for case, (_, targets) in enumerate(instances(count, 6, 6)):
        cells = []
        for seed in range(seeds):
            wall, cpu, miss, _ = _solve_case(targets, seed, workers)
            worst = max(worst, cpu)
            cells.append(f"{wall:.1f} / {cpu:.1f} s{'' if miss <= 1e-9 else f' ({miss:.0e} m)'}")
        rows.append(f"| {case} | " + " | ".join(cells) + f" | {_load()} |")
        print(rows[-1], file=sys.stderr, flush=True)
    head = ("| case | " + " | ".join(f"seed {s} (wall / CPU)" for s in range(seeds)) + " | load after |\n|"
            + "---|" * (seeds + 2))
    return (f"### Six targets, {count} random crank-rockers, seeds 0–{seeds - 1}\n\n{head}\n" + "\n".join(rows)
            + f"\n\nSlowest: {worst:.1f} s CPU (a miss in brackets where a run did not end exact).\n")


def population() -> str:
    t = load_template(TEMPLATE)
    rng = np.random.default_rng(0)
    xs = np.array([_random_crank_rocker(rng, t) for _ in range(400)])
    phi = np.linspace(0.0, 2 * math.pi, 360, endpoint=False)
    pop = median_time(lambda: run(t, xs, phi, ("P",)), repeat=7)
    scene = t.scene(xs[0]).with_outputs(points=["P"], joints=[])
    one = median_time(lambda: scene.solve(np.linspace(0.0, 2 * math.pi, 144_000)), repeat=7)
    return ("### Population against one candidate\n\n| 400 four-bars × 360 positions, one pass | one four-bar × "
            f"144,000 positions (Scene.solve) | ratio |\n|---|---|---|\n| {pop * 1e3:.1f} ms | {one * 1e3:.1f} ms | "
            f"{pop / one:.2f} |\n")


def main(argv: list[str]) -> int:
    write = "--write" in argv
    chosen = [a for a in argv if not a.startswith("--")] or ["five", "seven", "six", "ten", "population"]
    part = next((a.split("=", 1)[1] for a in argv if a.startswith("--cases=")), None)  # e.g. --cases=10-19
    cases = None if part is None else range(int(part.split("-")[0]), int(part.split("-")[1]) + 1)
    count = next((a.split("=", 1)[1] for a in argv if a.startswith("--workers=")), None)  # local processes
    workers = None if count is None else int(count)
    parts = [seven(cases=cases, workers=workers) if c == "seven" else six(workers=workers) if c == "six" else
             {"five": five, "ten": ten, "population": population}[c]() for c in chosen]
    m = machine()
    text = (f"## Figures\n\nMeasured with `python -m bench.synthesis --write` on {m['cpu']} ({m['cores']} cores, "
            f"shared with other work: load {m['load']}), Python {m['python']}, numpy {m['numpy']}, pylinkage "
            f"{m['pylinkage']}.\n\n" + "\n".join(parts))
    print(text)
    if write:
        write_section(DOC, "## Figures", text)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
