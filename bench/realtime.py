"""Real-time dynamics (issue 32): the adaptive run's speed, the fixed-step path at the node's
rate, and work–precision at every error level against MuJoCo and EXUDYN (docs/dynamics.md).

* ``engine.simulate(2.0)`` at the default tolerance (from rest, and running at 200 rad/s), the
  own DOP853 (breakpoint to breakpoint) against scipy's ``solve_ivp`` DOP853 on the same equation;
* the node's fixed-step path: :class:`solver.dynamics.Stepper` with RK4 at the step
  :func:`solver.dynamics.fixed_step` chooses for 1 kHz from the default tolerance (1e-9), 2 s of
  ticks, against DOP853 at 1e-12: the largest error of φ and ω at a tick, and the wall time a tick;
* work–precision: the four-bar pendulum (from rest at φ = 0.3 rad, 10 s) and the slider-crank
  with a flywheel (bench/scenes/slider_crank_flywheel.yaml: 1.5 N·m against a brake, from rest,
  5 s, about 31 turns): ours (DOP853 at rtol = atol = 1e-3 … 1e-12, RK4 at fixed steps) against
  MuJoCo (bodies, hinges, a slide and a ``connect`` equality; RK4 with a stiff ``solref``,
  implicit-fast) and, on the pendulum, EXUDYN (bench/dynamics_exudyn.py); then per error level
  1e-2 … 1e-10 rad the fastest run of each that reaches it.

``python -m bench.realtime`` prints Markdown and writes the section "## Real time" of
docs/dynamics.md (``--no-write``: print only); ``--engine`` prints the engine's table alone (CPU
time, paired in process against DOP853 on every step, without scipy's slow run), ``--node`` the
node's fixed-step table alone (the tolerance's step and one step a tick). Timings are of a shared
machine: the load average is printed beside them; compare within one run.
"""

from __future__ import annotations

import math
import sys
import time
import timeit
from pathlib import Path
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

import solver
from solver.dynamics import Stepper, _stepping, fixed_step
from solver.dynamics.drive import make_drive
from solver.dynamics.integrate import Equation

from ._common import machine, write_section
from .dynamics import _closure_gap, _mujoco_rows, _mujoco_run
from .dynamics_exudyn import _exudyn_rows

DOC = Path(__file__).resolve().parents[1] / "docs" / "dynamics.md"
SLIDER = Path(__file__).resolve().parent / "scenes" / "slider_crank_flywheel.yaml"
LEVELS = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10)
TOLERANCES = (1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9, 1e-10, 1e-11, 1e-12)
STEPS = (0.05, 0.02, 0.01, 5e-3, 2e-3, 1e-3, 5e-4)


def _best_of(fn: Any, repeat: int = 3) -> tuple[Any, float]:
    best, out = math.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return out, best


# --- engine.simulate(2.0) ------------------------------------------------------------------------


def _cpu_best_of(fn: Any, repeat: int = 3) -> tuple[Any, float, float]:
    """(the result, the best wall time, the best CPU time of the process) over ``repeat`` runs."""
    best_wall = best_cpu = math.inf
    out = None
    for _ in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        out = fn()
        best_cpu = min(best_cpu, time.process_time() - cpu)
        best_wall = min(best_wall, time.perf_counter() - wall)
    return out, best_wall, best_cpu


def _engine_rows(*, scipy_too: bool = True) -> list[str]:
    """engine.simulate(2.0) at the default tolerance: ours (a step cut short by a kink tried with
    the 5(4) pair first), DOP853 on every step (``_stepping.SHORT_STEP = 0``: the loop before that
    change, paired in this process), and scipy's solve_ivp; CPU times, and the µs of one (M, h)
    here (to scale to another machine's figure)."""
    engine = solver.load_scene("engine")
    engine.simulate(0.01)  # compile
    model = engine.reduced()
    fn, _ = make_drive(None, engine.inputs, model.motors, scene=engine.name)
    unit = model._stacked_unit
    unit.function(0.3, 200.0, 0.0)
    f = unit.function
    instant = min(timeit.repeat(lambda: f(0.3, 200.0, 0.0), number=2000, repeat=7)) / 2000
    rows = []
    for omega0 in (0.0, 200.0):
        short = _stepping.SHORT_STEP
        try:
            _stepping.SHORT_STEP = 0.0
            ref = engine.simulate(2.0, omega0=omega0, rtol=1e-12, atol=1e-12)
            plain, _, plain_cpu = _cpu_best_of(lambda w=omega0: engine.simulate(2.0, omega0=w))
        finally:
            _stepping.SHORT_STEP = short
        run, wall, cpu = _cpu_best_of(lambda w=omega0: engine.simulate(2.0, omega0=w))
        row = (f"| from φ = 0, ω = {omega0:g} rad/s | {cpu:.3f} s CPU ({2.0 / cpu:.1f}× real time; wall {wall:.3f} s), "
               f"{run.evaluations} evaluations, {abs(run.phi[-1] - ref.phi[-1]):.1e} rad | {plain_cpu:.3f} s CPU, "
               f"{plain.evaluations} evaluations, {abs(plain.phi[-1] - ref.phi[-1]):.1e} rad | "
               f"{plain_cpu / cpu:.2f} | {cpu / instant:.0f} (M, h) of {instant * 1e6:.1f} µs |")
        if scipy_too:
            start = time.process_time()
            old = solve_ivp(Equation(model, fn), (0.0, 2.0), np.array([0.0, omega0, 0.0, 0.0]), method="DOP853",
                            rtol=1e-9, atol=1e-9)
            row += (f" {time.process_time() - start:.3f} s CPU, {old.nfev} evaluations, "
                    f"{abs(old.y[0, -1] - ref.phi[-1]):.1e} rad |")
        else:
            row += " — |"
        rows.append(row)
    return rows


ENGINE_HEADER = ("| run | ours | DOP853 on every step | its CPU / ours | ours in units of one (M, h) here | "
                 "scipy solve_ivp (DOP853, no breakpoints) |")


# --- the node's fixed step -----------------------------------------------------------------------

_NODE_SCENES: tuple[tuple[str, dict[str, Any]], ...] = (
    ("engine", {"omega0": 200.0}), ("four_bar_loaded", {"phi0": 0.3, "drive": 0.0}),
    ("harvester_finger", {}), ("tipper", {"phi0": 1.0, "drive": 8000.0}),
)


def _node_rows(seconds: float = 2.0, rate: float = 1000.0) -> list[str]:
    rows = []
    for name, kw in _NODE_SCENES:
        scene = solver.load_scene(name)
        start = time.perf_counter()
        step, _ = fixed_step(scene, period=1.0 / rate, tolerance=1e-9, **kw)
        calibration = time.perf_counter() - start
        exact = Stepper(scene, rtol=1e-12, atol=1e-12, works=False, **kw)
        n = int(seconds * rate)
        wanted = []
        for i in range(1, n + 1):
            try:
                wanted.append(exact.advance(i / rate)[:2].copy())
            except solver.DynamicsError:
                break
        cells = []
        wall = 0.0
        for h in (step, 1.0 / rate):  # the tolerance's step, and one step a tick (the node's under its budget)
            fixed = Stepper(scene, method="RK4", step=h, works=False, **kw)
            dphi = dw = 0.0
            wall = 0.0
            for i, want in enumerate(wanted, start=1):
                t0 = time.process_time()
                got = fixed.advance(i / rate)
                fixed.accelerations()
                wall += time.process_time() - t0
                dphi = max(dphi, abs(got[0] - want[0]))
                dw = max(dw, abs(got[1] - want[1]) / max(1.0, abs(want[1])))
            cells.append((dphi, dw, wall / max(len(wanted), 1)))
        (p1, w1, c1), (p2, w2, c2) = cells
        rows.append(f"| {name} {', '.join(f'{k} = {v:g}' for k, v in kw.items())} | {round(1 / (rate * step))} | "
                    f"{p1:.1e} | {w1:.1e} | {c1 * 1e6:.0f} µs | {p2:.1e} | {w2:.1e} | {c2 * 1e6:.0f} µs | "
                    f"{len(wanted) / rate:g} s | {calibration:.2f} s |")
    return rows


NODE_HEADER = ("| scene, start | steps a tick for 1e-9 | φ error | ω error | a tick (CPU) | φ error, one step a tick | "
               "ω error | a tick (CPU) | run | calibration |")


# --- work–precision ------------------------------------------------------------------------------


def _slider_mjcf(scene: Any) -> str:
    """The slider-crank with its flywheel in MuJoCo: crank (hinge, with the flywheel's inertia and
    the brake as joint damping), rod (hinge at A), piston (a slide along x), closed by a
    ``connect`` between the rod's B and the piston; built at φ = 0 (top dead centre)."""
    spec = scene.reduced().spec
    body = {b.name: b for b in spec.bodies}
    crank, rod, piston = body["crank"], body["rod"], body["piston"]
    la, lab = 0.045, 0.155
    damping = next(ld.coefficient for ld in spec.loads if type(ld).__name__ == "Damper")

    def inertial(bd: Any) -> str:
        i = max(bd.inertia, 1e-9)
        return (f'<inertial pos="{bd.center.real} {bd.center.imag} 0" mass="{bd.mass}" '
                f'diaginertia="{i} {i} {i}"/>')

    return f"""
<mujoco>
  <compiler angle="radian"/>
  <option gravity="0 -9.81 0" timestep="0.001" integrator="RK4"/>
  <worldbody>
    <body name="crank" pos="0 0 0">
      <joint name="phi" type="hinge" axis="0 0 1" damping="{damping}"/>
      {inertial(crank)}
      <body name="rod" pos="{la} 0 0">
        <joint name="knee" type="hinge" axis="0 0 1"/>
        {inertial(rod)}
        <site name="b1" pos="{lab} 0 0"/>
      </body>
    </body>
    <body name="piston" pos="{la + lab} 0 0">
      <joint name="x" type="slide" axis="1 0 0"/>
      {inertial(piston)}
      <site name="b2" pos="0 0 0"/>
    </body>
  </worldbody>
  <equality>
    <connect body1="rod" body2="piston" anchor="{lab} 0 0"/>
  </equality>
</mujoco>"""


def _slider_gap(traj: Any) -> float:
    k = traj.solve()
    a, b = k.point("A").position, k.point("B").position
    return float(np.abs(np.hypot(*(b - a).T) - 0.155).max())


Run = tuple[str, str, float, float, float]  # (tool, settings, error, wall, loop opening)


def _ours(scene: Any, t_end: float, want: float, gap: Any, **kw: Any) -> list[Run]:
    out: list[Run] = []
    scene.simulate(0.01, **kw)  # warm
    for tol in TOLERANCES:
        traj, wall = _best_of(lambda tol=tol: scene.simulate(t_end, rtol=tol, atol=tol, **kw))
        out.append(("linkage_ros", f"DOP853 rtol=atol={tol:g}", abs(float(traj.phi[-1]) - want), wall, gap(traj)))
    for h in STEPS:
        try:
            traj, wall = _best_of(lambda h=h: scene.simulate(t_end, method="RK4", step=h, **kw))
        except solver.DynamicsError:
            out.append(("linkage_ros", f"RK4 step {h:g} s", math.nan, math.nan, math.nan))
            continue
        out.append(("linkage_ros", f"RK4 step {h:g} s", abs(float(traj.phi[-1]) - want), wall, gap(traj)))
    return out


def _parse_rows(rows: list[str], tool: str) -> list[Run]:
    """(tool, settings, error, wall, opening) from the Markdown rows of bench.dynamics' helpers."""
    out: list[Run] = []
    for row in rows:
        cells = [c.strip() for c in row.strip("|").split("|")]
        try:
            err, wall = float(cells[1]), float(cells[2].rstrip(" s"))
        except (ValueError, IndexError):
            continue
        opening = float(cells[3].rstrip(" m")) if len(cells) > 3 and cells[3] else math.nan
        out.append((tool, cells[0], err, wall, opening))
    return out


def _pendulum_runs() -> list[Run]:
    scene = solver.load_scene("four_bar_pendulum")
    want = float(scene.simulate(10.0, phi0=0.3, rtol=1e-13, atol=1e-13).phi[-1])
    runs = _ours(scene, 10.0, want, lambda traj: _closure_gap(scene, traj), phi0=0.3)
    runs += _parse_rows(_mujoco_rows(scene, phi0=0.3, t_end=10.0, want=want), "MuJoCo")
    runs += _parse_rows(_exudyn_rows(scene, phi0=0.3, t_end=10.0, want=want), "EXUDYN")
    return runs


def _slider_runs() -> list[Run]:
    scene = solver.load_scene(SLIDER)
    want = float(scene.simulate(5.0, drive=1.5, rtol=1e-13, atol=1e-13).phi[-1])
    runs = _ours(scene, 5.0, want, _slider_gap, drive=1.5)
    try:
        import mujoco
    except ImportError:
        return runs
    xml = _slider_mjcf(scene)
    for integrator, dt, stiff in (("RK4", 1e-3, True), ("RK4", 1e-4, True), ("RK4", 1e-5, True),
                                  ("IMPLICITFAST", 1e-4, True), ("IMPLICITFAST", 1e-3, True), ("RK4", 1e-4, False)):
        got, wall, gap = _mujoco_run(xml, {}, 5.0, dt, integrator, stiff, torque=1.5)
        runs.append((f"MuJoCo {mujoco.__version__}", f"{integrator} dt={dt:g}{' stiff solref' if stiff else ''}",
                     abs(got - want), wall, gap))
    return runs


def _table(runs: list[Run]) -> list[str]:
    rows = ["| tool | settings | error of φ at the end (rad) | wall time | loop opening |", "|---|---|---|---|---|"]
    for tool, settings, err, wall, gap in runs:
        rows.append(f"| {tool} | {settings} | {err:.1e} | {wall:.3f} s | {gap:.0e} m |")
    return rows


def _levels(runs: list[Run]) -> list[str]:
    """Per error level, the fastest run of each tool that reaches it, and ours against the best other."""
    tools = sorted({r[0].split()[0] for r in runs})
    rows = ["| error ≤ | " + " | ".join(tools) + " | ours / best other |", "|---|" + "---|" * (len(tools) + 1)]
    for level in LEVELS:
        best: dict[str, Run] = {}
        for run in runs:
            tool = run[0].split()[0]
            if run[2] <= level and math.isfinite(run[3]) and (tool not in best or run[3] < best[tool][3]):
                best[tool] = run
        cells = [f"{best[t][3]:.3f} s ({best[t][1]})" if t in best else "—" for t in tools]
        others = [best[t][3] for t in best if t != "linkage_ros"]
        ratio = (f"{best['linkage_ros'][3] / min(others):.2f}" if "linkage_ros" in best and others
                 else "only ours" if "linkage_ros" in best else "—")
        rows.append(f"| {level:g} | " + " | ".join(cells) + f" | {ratio} |")
    return rows


def _engine_text(*, scipy_too: bool) -> list[str]:
    return ["The own step loop, breakpoint to breakpoint across the 145 kinks of the 720° gas table (a step cut "
            "short by a kink tried with Dormand and Prince's 5(4) pair first), against the same loop with DOP853 on "
            "every step (in this process) and scipy's `solve_ivp` (DOP853, same equation and tolerance, no "
            "breakpoints; one run); CPU time of the process (the best of three), errors of φ after 2 s against "
            "DOP853 at 1e-12.", "", ENGINE_HEADER, "|---|---|---|---|---|---|", *_engine_rows(scipy_too=scipy_too)]


def _node_text() -> list[str]:
    return ["The step `fixed_step` chooses for ticks of 1 ms at the default `dynamics_tolerance` (1e-9) without a "
            "budget, and one step a tick (what the node's budget gives on a loaded machine, and on every machine for "
            "the engine at 200 rad/s): the largest error at a tick over 2 s against DOP853 at 1e-12 (φ in rad, ω "
            "relative to max(1, |ω|)), the CPU time of a tick (the law's advance and its ε), and the calibration's "
            "time.", "", NODE_HEADER, "|---|---|---|---|---|---|---|---|---|---|", *_node_rows()]


def main() -> None:
    if "--node" in sys.argv:  # the node's rows alone, printed
        info = machine()
        print(f"load {info['load']}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
        print("\n".join(_node_text()))
        return
    if "--engine" in sys.argv:  # the engine's rows alone (no scipy), printed
        info = machine()
        print(f"load {info['load']}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
        print("\n".join(_engine_text(scipy_too=False)))
        return
    info = machine()
    lines = ["## Real time", "",
             f"Measured on {info['cpu']} ({info['cores']} cores, load {info['load']} — a shared machine: other "
             f"sessions ran beside it), Python {info['python']}, numpy {info['numpy']}, "
             f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, by `python -m bench.realtime` (the best "
             "of three runs each).", "",
             "### engine.simulate(2.0), adaptive DOP853 at its default tolerance (rtol = atol = 1e-9)", ""]
    lines += _engine_text(scipy_too=True)
    lines += ["", "### The node's fixed step: RK4 at 1 kHz against the adaptive run", "",
              *_node_text()]
    pendulum, slider = _pendulum_runs(), _slider_runs()
    lines += ["", "### Work–precision at every error level", "",
              "The fastest run of each tool whose error of φ at the end is within the level (its settings in "
              "brackets); ours: DOP853 at rtol = atol = 1e-3 … 1e-12 and RK4 at fixed steps of 50 ms … 0.5 ms, "
              "the loop closed to round-off in every run (tables below).", "",
              "Four-bar pendulum (four_bar_pendulum from rest at φ = 0.3 rad, 10 s):", ""]
    lines += _levels(pendulum)
    lines += ["", "Slider-crank with a flywheel (bench/scenes/slider_crank_flywheel.yaml, 1.5 N·m against the "
              "brake, from rest, 5 s; EXUDYN not built for this one):", ""]
    lines += _levels(slider)
    lines += ["", "All runs, four-bar pendulum:", ""] + _table(pendulum)
    lines += ["", "All runs, slider-crank with a flywheel:", ""] + _table(slider)
    text = "\n".join(lines) + "\n"
    print(text)
    if "--no-write" not in sys.argv:
        write_section(DOC, "## Real time", text)


if __name__ == "__main__":
    main()
