"""Render a measured :class:`bench.speed_vs_error.Report` as markdown tables and a log–log plot."""

from __future__ import annotations

import datetime
import math
from pathlib import Path
from typing import Any

from bench._common import QUANTITIES, SCENES
from bench.plot import FLOOR, plot

__all__ = ["write"]

TARGET_VECTORISED_S = 0.15e-6
TARGET_TICK_US = 100.0


def _e(x: float) -> str:
    if x == 0.0:
        return "0"
    if not math.isfinite(x):
        return "∞"
    return f"{x:.1e}"


def _us(seconds: float) -> str:
    us = seconds * 1e6
    return f"{us:.3g}" if us < 1000 else f"{us:,.0f}"


def _find(report: Any, scene: str, method: str) -> Any:
    return next((r for r in report.results if r.scene == scene and r.method.startswith(method)), None)


def _targets(report: Any) -> list[str]:
    ours = _find(report, "four_bar", "ours, vectorised")
    rows = ["| target | measured | met |", "|---|---|---|"]

    def row(target: str, measured: str, ok: bool | None) -> None:
        rows.append(f"| {target} | {measured} | {'—' if ok is None else ('yes' if ok else '**no**')} |")

    row(
        "four-bar full kinematics vectorised ≤ 0.15 µs/position",
        f"{_us(ours.seconds)} µs",
        ours.seconds <= TARGET_VECTORISED_S,
    )
    peer = {r.method.rsplit(", ", 1)[-1]: r for r in report.results if r.family == "peer"}
    for mode, need in (("numba", 4), ("pure Python", 150)):
        info = report.peers.get(mode)
        if isinstance(info, dict):
            ratio = info["per_position_s"] / info["ours_per_position_s"]
            row(
                f"≥ {need}× faster than pylinkage{' + numba' if mode == 'numba' else ', pure Python'}",
                f"{ratio:.1f}× (paired runs: theirs {_us(info['per_position_s'])} µs, "
                f"ours {_us(info['ours_per_position_s'])} µs)",
                ratio >= need,
            )
    for mode, r in peer.items():
        ratios = [r.errors[q] / max(ours.errors[q], FLOOR) for q in QUANTITIES]
        text = ", ".join(f"{q[:3]} {x:.1f}×" for q, x in zip(QUANTITIES, ratios, strict=True))
        row(f"errors ≥ 100× smaller than pylinkage ({mode})", text, min(ratios) >= 100)
    drift = report.peers.get("drift")
    if drift:
        ratio = drift["position"] / max(ours.errors["position"], FLOOR)
        row(
            f"… pylinkage positions after a {drift['steps']:,}-step turn (crank angle re-read each step)",
            f"{_e(drift['position'])} × scale, {ratio:.0f}× ours",
            ratio >= 100,
        )
    worst_pos = max(_find(report, s, "ours, vectorised").errors["position"] for s in SCENES)
    worst_ana = max(max(_find(report, s, "ours, vectorised").errors[q] for q in QUANTITIES[1:]) for s in SCENES)
    row("positions ≤ 1e-15 × scale (all scenes)", f"{_e(worst_pos)} × scale", worst_pos <= 1e-15)
    row("analogs ≤ 1e-12 relative (all scenes)", f"{_e(worst_ana)}", worst_ana <= 1e-12)
    node = report.node or {}
    if "tick" in node:
        row(
            "node engine ≤ 100 µs per tick (harvester finger)", f"{node['tick']:.0f} µs", node["tick"] <= TARGET_TICK_US
        )
    else:
        row("node engine ≤ 100 µs per tick", f"not measured: {node.get('missing', 'engine missing')}", None)
    return rows


def _words(report: Any) -> list[str]:
    """What the plot shows, with this run's figures."""
    fb = [r for r in report.results if r.scene == "four_bar"]
    ours, scalar = _find(report, "four_bar", "ours, vectorised"), _find(report, "four_bar", "ours, scalar")
    cs = _find(report, "four_bar", "complex step")
    fds = [r for r in fb if r.family == "finite differences"]
    best_v = min(fds, key=lambda r: r.errors["velocity"])
    best_a = min(fds, key=lambda r: r.errors["acceleration"])
    nrs = [r for r in fb if r.family == "Newton"]
    text = [
        f"* **Ours, vectorised** sits alone in the bottom-left corner: {_us(ours.seconds)} µs per position for "
        "all points and joints with both analogs, at the rounding floor (positions "
        f"{_e(ours.errors['position'])} × scale, "
        f"velocity {_e(ours.errors['velocity'])}, acceleration {_e(ours.errors['acceleration'])} "
        "relative). The analogs "
        "are propagated exactly through the closed form, so they cost a few more array operations than the positions "
        "and are as accurate as the positions themselves.",
        f"* **Ours, scalar** (one φ per call, the node's path) has the same errors but costs {_us(scalar.seconds)} µs: "
        "the formulas are the same, the time is Python's per-call overhead, not arithmetic.",
        f"* **Central finite differences** trade truncation against cancellation: the velocity error is best at "
        f"h = {best_v.method.split('=')[1]} ({_e(best_v.errors['velocity'])}) and the acceleration error at "
        f"h = {best_a.method.split('=')[1]} ({_e(best_a.errors['acceleration'])}); smaller steps make the "
        "acceleration worse (ε/h² grows to order 1 at h = 1e-8). No step reaches the exact analogs, and each costs "
        "three position evaluations.",
        f"* **Complex step** gives the velocity analog at the rounding floor ({_e(cs.errors['velocity'])}) — no "
        "subtraction, so no cancellation — but the second derivative still needs a difference "
        f"(here of complex-step first derivatives): {_e(cs.errors['acceleration'])}. Complex arithmetic makes it "
        f"{cs.seconds / ours.seconds:.1f}× the cost of ours.",
        "* **Newton–Raphson** (generic loop closure, warm-started along the sweep) converges quadratically, so even "
        f"a loose tolerance gives small errors (tol 1e-6: positions {_e(nrs[0].errors['position'])}); tighter "
        f"tolerances reach the rounding floor at {nrs[-1].note}. Its analogs from the constraint Jacobian are exact "
        f"once the positions are; the cost is the iterations and a linear solve per angle: {_us(nrs[-1].seconds)} µs "
        "per position in Python, one angle at a time (a compiled multibody code would be faster per iteration, but "
        "it cannot skip the iterations that a closed form does not need).",
    ]
    peer = [r for r in fb if r.family == "peer"]
    for r in peer:
        info = report.peers.get(r.method.rsplit(", ", 1)[-1], {})
        paired = info["per_position_s"] / info["ours_per_position_s"] if info else r.seconds / ours.seconds
        text.append(
            f"* **{r.method}**: {_us(r.seconds)} µs per position ({paired:.1f}× ours in paired runs), errors "
            f"{_e(r.errors['position'])} / {_e(r.errors['velocity'])} / {_e(r.errors['acceleration'])} "
            "(position / velocity / acceleration): also closed-form circle intersection and analytic derivatives, "
            "so close to the floor over one turn; it steps the crank by re-reading the angle from the last position, "
            "so its angle drifts with the number of steps."
        )
    node = report.node or {}
    if "tick" in node:
        text.append(
            f"* **The node's tick** costs {node['tick']:.0f} µs: {node['frame']:.0f} µs to solve one φ "
            "with every joint "
            f"and point (the scalar path above, with more outputs) and {node['build']:.0f} µs to fill "
            f"{node['messages']} messages. The profile below is flat — no single hot spot; the time is the Python "
            "interpreter's per-call cost over some hundred small calls (solver groups, jets, dataclass and message "
            f"constructors). Even so one core sustains {node['max_rate_hz']:,.0f} Hz."
        )
    if report.integration:
        by = {(r["method"], r["rate"]): r for r in report.integration}
        top = max(r["rate"] for r in report.integration)
        exact = by.get(("exact piecewise (Motion)", top))
        euler, rk4 = by[("Euler", top)], by[("RK4", top)]
        line = (
            f"* **Time integration** (right panel), after {report.config.duration:g} s simulated at {top} Hz: "
            f"Euler is off by {_e(euler['phi_error'])} rad (first order: its error grows with the step and the "
            f"duration), RK4 by {_e(rk4['phi_error'])} rad — for a piecewise-constant ε RK4 is exact per step, and "
            "what remains is rounding accumulated over every tick, which grows with the rate."
        )
        plain = by.get(("closed form, plain float", top))
        phi_end = 2.0 * math.pi * report.config.duration
        spacing = math.ulp(phi_end)
        if exact and plain:
            line += (
                f" The closed form in plain floats is as good here ({_e(plain['phi_error'])} rad): at the end φ is "
                f"about {phi_end:.0f} rad, whose own spacing of doubles ({_e(spacing)} rad) is the floor for every "
                "method; Motion's error-free sums matter only for longer runs or larger ω."
            )
        if exact:
            line += (
                f" The exact piecewise law stays at {_e(exact['phi_error'])} rad at every rate for "
                f"{exact['tick_s'] * 1e6:.2g} µs per tick: the rounding of one evaluation, because "
                "nothing is accumulated."
            )
        text.append(line)
    return text


def _scene_table(report: Any, scene: str) -> list[str]:
    rows = [
        "| method | µs / position | positions (× scale) | velocity (rel.) | acceleration (rel.) | note |",
        "|---|---:|---:|---:|---:|---|",
    ]
    for r in report.results:
        if r.scene != scene:
            continue
        errs = [_e(r.errors.get(q, math.nan)) for q in QUANTITIES]
        rows.append(f"| {r.method} | {_us(r.seconds)} | {' | '.join(errs)} | {r.note} |")
    return rows


def _integration_table(report: Any) -> list[str]:
    rows = [
        "| method | rate (Hz) | ticks | max φ error (rad) | max ω error (rad/s) | µs / tick |",
        "|---|---:|---:|---:|---:|---:|",
    ]
    for r in sorted(report.integration, key=lambda r: (r["method"], r["rate"])):
        rows.append(
            f"| {r['method']} | {r['rate']:g} | {r['ticks']:,} | {_e(r['phi_error'])} | {_e(r['omega_error'])} | "
            f"{r['tick_s'] * 1e6:.3g} |"
        )
    return rows


def _node_lines(report: Any) -> list[str]:
    node = report.node or {}
    if "tick" not in node:
        return [f"Not measured: {node.get('missing', 'the node engine is not importable')}."]
    return [
        "| per tick (harvester finger, every joint and point) | µs |",
        "|---|---:|",
        f"| `Engine.frame(t)`: motion law + scalar solve | {node['frame']:.1f} |",
        f"| `MessageBuilder.build`: all {node['messages']} messages (rosbags Jazzy types) | {node['build']:.1f} |",
        f"| **tick = frame + build** | **{node['tick']:.1f}** |",
        f"| CDR serialisation of those messages (recording only; rclpy does it in C) | {node['serialize']:.1f} |",
        "",
        f"Highest publish rate one core sustains: **{node['max_rate_hz']:,.0f} Hz** (1 / tick); at 1 kHz the node "
        f"uses {node['core_at_1khz'] * 100:.0f} % of a core (before rclpy's own publishing cost).",
    ]


def write(report: Any, out: Path) -> tuple[Path, Path]:
    """Write ``speed-vs-error.md`` and ``speed-vs-error.png`` into ``out``."""
    md, png = out / "speed-vs-error.md", out / "speed-vs-error.png"
    plot(report, png)
    m, cfg = report.machine, report.config
    lines = [
        "# Speed against error",
        "",
        "Regenerate (tables and plot, about " + f"{max(report.wall_s / 60, 1):.0f} min" + "):",
        "",
        "```sh",
        ".venv/bin/pip install -e '.[bench]'   # matplotlib, pylinkage==1.3.0, numba",
        ".venv/bin/python -m bench.speed_vs_error          # --quick: a smoke run in seconds, written to "
        "bench/.cache/quick/",
        "```",
        "",
        "Measured "
        f"{datetime.date.today().isoformat()}{' (QUICK RUN: small sizes, not for citing)' if cfg.quick else ''} "
        f"on **{m['cpu']}, {m['cores']} cores** ({m['system']}, load average {m['load']} at the end), "
        f"Python {m['python']}, "
        f"numpy {m['numpy']}, mpmath {m['mpmath']}, pylinkage {m['pylinkage']}, numba {m['numba']}. "
        f"Times are medians of {cfg.repeat} runs in one process; the whole run took {report.wall_s:.0f} s. "
        "On a 2-core machine shared with other work, times move by 2–3× with the load; errors do not.",
        "",
        "## Targets",
        "",
        *_targets(report),
        "",
        "## What the plot shows",
        "",
        "![speed against error](speed-vs-error.png)",
        "",
        "Left: the four-bar, one marker per method and quantity (circle positions, square velocity analog, "
        "triangle acceleration analog; errors below 1e-17 drawn at 1e-17). Right: integrating φ(t).",
        "",
        *_words(report),
        "",
        "## How it was measured",
        "",
        f"* **Error**: maximum over {cfg.n_reference} angles evenly over one turn against an mpmath reference at 50 "
        "digits (tests/reference/mp_reference.py: closed-form positions in mpmath, analogs by `mp.diff`; cached in "
        "bench/.cache/). Positions: max |error| / the scene's largest link length (angle joints in rad); velocity and "
        "acceleration analogs (ω = 1, ε = 0): max |error| / max |reference| of the same output; the "
        "worst output is listed.",
        f"* **Time** per position: ours vectorised on {cfg.n_time:,} angles, the finite-difference and "
        f"complex-step variants on {cfg.n_time // 5:,} angles; ours scalar over {cfg.n_scalar:,} calls of "
        f"`scene.solve(float)`; Newton over the {cfg.n_reference}-angle error sweep; every output with velocity "
        "and acceleration fetched.",
        "* **Finite differences and complex step** differentiate the bench's own real-arithmetic copy of each scene's "
        "closed-form positions (bench/alternatives.py; tests/bench/ checks it equals the solver's positions), so "
        "their cost is that of positions only.",
        "* **Newton–Raphson** (bench/newton.py): natural coordinates (the moving points), scalar constraints "
        "(crank driver, distances, point on a line, collinearity, seed 001's groove), iterate until the update is "
        "≤ tol × scale, warm-started from the previous angle; velocity and acceleration analogs from Φ_q q' = −Φ_φ, "
        "Φ_q q'' = −γ.",
        "* **pylinkage** (bench/peers.py): the same four-bar built from `Ground`, `Crank`, `RRRDyad`, `Linkage`; "
        "`step_fast_with_kinematics` with ω = 1, timed with numba and, in a child process where numba cannot be "
        "imported, in pure Python. Its joint angles are not available, so only points A and B are compared.",
        "",
    ]
    for scene in SCENES:
        lines += [f"## {scene}", "", *_scene_table(report, scene), ""]
    lines += ["## pylinkage", ""]
    if "missing" in report.peers:
        lines += [report.peers["missing"], ""]
    else:
        for mode in ("numba", "pure Python"):
            info = report.peers.get(mode)
            if isinstance(info, dict):
                what = "JIT compilation, or loading numba's on-disk cache" if mode == "numba" else "no JIT"
                lines.append(
                    f"* {mode}: first build and run ({what}) {info['warmup_s']:.2f} s, not included in the "
                    "time per position."
                )
        if "cold_jit_s" in report.peers:
            lines.append(
                f"* numba, first use (fresh process, empty numba cache): import, JIT compilation and first run "
                f"{report.peers['cold_jit_s']:.1f} s."
            )
        drift = report.peers.get("drift")
        if drift:
            lines.append(
                f"* Over a run of {drift['steps']:,} steps (one turn), point B drifts to "
                f"{_e(drift['position'])} × scale "
                "from the closed form at the nominal angles: its crank angle is re-read from the previous position at "
                "every step, so rounding accumulates. Ours evaluates every angle independently."
            )
        lines.append("")
    lines += [
        "## Time integration of φ(t)",
        "",
        f"φ(0) = 0, ω(0) = 2π rad/s, ε switching every {integration_segment()} s through "
        f"{', '.join(f'{e:g}' for e in integration_epsilons())} rad/s², over {cfg.duration:g} s. Errors at the exact "
        f"rational tick times n/rate, sampled at every {cfg.sample_every:g} s and ⅓ s later, against mpmath. Cost: one "
        "scalar Python evaluation or step per tick. Euler and RK4 accumulate tick after tick (computed with a "
        "sequential cumulative sum, the same additions a loop makes).",
        "",
        *_integration_table(report),
        "",
        "## Node engine and memory",
        "",
        *_node_lines(report),
        "",
        f"Memory of a vectorised solve (four-bar, every output with both analogs), per 10⁶ positions: output arrays "
        f"{report.memory.get('outputs_mib', math.nan):.0f} MiB, peak traced allocation during the solve "
        f"{report.memory.get('peak_mib', math.nan):.0f} MiB (`tracemalloc`).",
        "",
    ]
    lines += ["## Where the time goes", ""]
    if report.breakdown:
        lines += ["Four-bar, vectorised, per position:", "", "| stage | µs / position |", "|---|---:|"]
        lines += [f"| {k} | {_us(v)} |" for k, v in report.breakdown.items()]
        lines.append("")
        bare = report.breakdown.get("bare numpy positions only (bench copy)")
        full = report.breakdown.get("solve() and every output fetched")
        if bare and full:
            lines += [
                f"Positions alone, as bare numpy expressions, take {_us(bare)} µs per position; the full solve with "
                f"both exact analogs of every point and joint takes {full / bare:.1f}× that. The difference is the "
                "analog propagation (each jet carries two derivatives along with its value) and "
                "numpy's temporaries (each array operation writes a fresh array of 8–16 bytes per angle).",
                "",
            ]
    if report.profiles:
        lines += [
            "cProfile, sorted by own time (numpy's array operations are counted in the Python function that "
            "calls them):",
            "",
        ]
        for title, text in report.profiles.items():
            lines += [f"### {title}", "", "```", text, "```", ""]
    md.write_text("\n".join(lines).rstrip() + "\n")
    return md, png


def integration_segment() -> str:
    from bench.integration import SEGMENT_S

    return f"{SEGMENT_S:g}"


def integration_epsilons() -> tuple[float, ...]:
    from bench.integration import EPSILONS

    return EPSILONS
