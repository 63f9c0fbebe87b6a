"""Forward dynamics: cost of (M, h) and work–precision against MuJoCo and EXUDYN (docs/dynamics.md).

* per instant: one evaluation of (M, h) (``ReducedModel.instant``: two compiled force passes)
  against one compiled instant with efforts (``scene.instant``), same process, interleaved;
* vectorised: M and h over 10⁵ states against the kinetostatics (``scene.solve`` with efforts);
* work–precision on the four-bar pendulum (four_bar_pendulum, released from rest at φ = 0.3 rad,
  10 s) and on a slider-crank pendulum (engine's geometry and masses, gravity only, released at
  φ = 2 rad, 5 s; not yet measured): the error of φ at the end against wall time, and the loop's largest opening,
  for ``scene.simulate`` at rtol = atol = 1e-4 … 1e-12, for MuJoCo (the same bodies, hinges
  and a ``connect`` equality closing the loop; RK4 and implicit-fast at several steps) and for
  EXUDYN (planar rigid bodies and revolute joints, the loop closed by a joint; generalized-α on
  the index-3 equations, the index-2 trapezoidal rule, DOPRI5 with penalty pins: see
  bench/dynamics_exudyn.py). The
  reference is ``scene.simulate`` at rtol = atol = 1e-13 (itself checked against the 50-digit
  reference of tests/reference/dynamics_mp.py and against energy conservation).

Run ``python -m bench.dynamics`` (MuJoCo and EXUDYN from PyPI: ``pip install mujoco exudyn``; a
missing one is a "not installed" row); it prints Markdown and writes the section "## Measured" of
docs/dynamics.md (``--no-write``: print only).
"""

from __future__ import annotations

import math
import sys
import time
from pathlib import Path
from typing import Any

import numpy as np

import solver

from ._common import assembled_points, machine, median_times, write_section
from .dynamics_exudyn import _exudyn_rows

DOC = Path(__file__).resolve().parents[1] / "docs" / "dynamics.md"


def _loop(f: Any, n: int) -> Any:
    def run() -> None:
        for _ in range(n):
            f()
    return run


def _cost_row(name: str, q: Any, w: Any) -> str:
    scene = solver.load_scene(name)
    model = scene.reduced()
    n_calls, n = 2000, 100_000
    rng = np.random.default_rng(1)
    if len(scene.inputs) == 1:
        qq, ww = (float(q),), (float(w),)
        args = (float(q), float(w), 0.5)
        qs = np.linspace(0, 2 * math.pi, n)
        ws = 2.0 + rng.random(n)
        eps: Any = 0.3
    else:
        qq, ww = tuple(q), tuple(w)
        args = (qq, ww, (0.1, 0.2))
        qs = np.radians(np.column_stack([60 + 60 * rng.random(n), 60 + 60 * rng.random(n)]))
        ws = rng.random((n, 2))
        eps = (0.1, 0.2)
    first = scene.inputs[0]
    scene.instant(*args)
    model.instant(qq, ww)
    t = median_times({"mh": _loop(lambda: model.instant(qq, ww), n_calls),
                      "inst": _loop(lambda: scene.instant(*args), n_calls)}, repeat=15)
    tv = median_times({"mh": lambda: model.mass_bias(qs, ws),
                       "kin": lambda: scene.solve(qs, omega=ws, epsilon=eps).effort(first)}, repeat=5)
    return (f"| {name} | {t['mh'] / n_calls * 1e6:.1f} µs | {t['inst'] / n_calls * 1e6:.1f} µs | "
            f"{t['mh'] / t['inst']:.2f} | {tv['mh'] * 1e3:.0f} ms | {tv['kin'] * 1e3:.0f} ms | "
            f"{tv['mh'] / tv['kin']:.2f} |")


def _cost_rows() -> list[str]:
    return [_cost_row("four_bar_loaded", 0.7, 2.0), _cost_row("engine", 0.7, 200.0),
            _cost_row("five_bar", (1.0, 2.0), (0.5, -0.3))]


# --- MuJoCo: the same mechanism from bodies, hinges and a connect equality ---


def _four_bar_mjcf(scene: Any, phi0: float) -> tuple[str, dict[str, float]]:
    spec = scene.reduced().spec
    body = {b.name: b for b in spec.bodies}
    pts = assembled_points(scene, phi0)
    o, c, a, b = (pts[p] for p in "OCAB")
    crank, coupler, rocker = (body[n] for n in ("crank", "coupler", "rocker"))
    la, lab, lcb = abs(a - o), abs(b - a), abs(b - c)
    th_c = math.atan2((b - a).imag, (b - a).real)
    th_r = math.atan2((b - c).imag, (b - c).real)

    def inertial(bd: Any) -> str:
        i = max(bd.inertia, 1e-9)
        return (f'<inertial pos="{bd.center.real} {bd.center.imag} 0" mass="{bd.mass}" '
                f'diaginertia="{i} {i} {i}"/>')

    xml = f"""
<mujoco>
  <compiler angle="radian"/>
  <option gravity="0 -9.81 0" timestep="0.001" integrator="RK4"/>
  <worldbody>
    <body name="crank" pos="{o.real} {o.imag} 0" euler="0 0 {phi0}">
      <joint name="phi" type="hinge" axis="0 0 1"/>
      {inertial(crank)}
      <body name="coupler" pos="{la} 0 0" euler="0 0 {th_c - phi0}">
        <joint name="knee" type="hinge" axis="0 0 1"/>
        {inertial(coupler)}
        <site name="b1" pos="{lab} 0 0"/>
      </body>
    </body>
    <body name="rocker" pos="{c.real} {c.imag} 0" euler="0 0 {th_r}">
      <joint name="rock" type="hinge" axis="0 0 1"/>
      {inertial(rocker)}
      <site name="b2" pos="{lcb} 0 0"/>
    </body>
  </worldbody>
  <equality>
    <connect body1="coupler" body2="rocker" anchor="{lab} 0 0"/>
  </equality>
</mujoco>"""
    # MuJoCo places the connect's second anchor from the model's reference pose (qpos = 0): the
    # bodies are built in the assembled pose at φ₀, so φ = φ₀ + qpos of the crank's hinge
    return xml, {"phi0": phi0}


def _mujoco_run(xml: str, init: dict[str, float], t_end: float, dt: float, integrator: str,
                stiff: bool, *, torque: float = 0.0) -> tuple[float, float, float]:
    """MuJoCo's run of ``xml`` (hinge ``phi``, connect sites ``b1``/``b2``) for ``t_end`` at step
    ``dt`` (``stiff``: the connect's ``solref`` at 2·dt), ``torque`` applied at the hinge: the
    input angle at the end (``init["phi0"]`` added), the stepping's wall time and the largest
    gap of the connect (every tenth step)."""
    import mujoco

    model = mujoco.MjModel.from_xml_string(xml)
    model.opt.timestep = dt
    model.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator}")
    if stiff:
        model.eq_solref[:] = [2 * dt, 1.0]
    data = mujoco.MjData(model)
    if torque:
        data.qfrc_applied[model.joint("phi").dofadr[0]] = torque
    mujoco.mj_forward(model, data)
    steps = int(round(t_end / dt))
    gap = 0.0
    b1, b2 = data.site("b1"), data.site("b2")
    start = time.perf_counter()
    for i in range(steps):
        mujoco.mj_step(model, data)
        if i % 10 == 0:
            gap = max(gap, float(np.linalg.norm(b1.xpos - b2.xpos)))
    wall = time.perf_counter() - start
    return init.get("phi0", 0.0) + float(data.joint("phi").qpos[0]), wall, gap


def _closure_gap(scene: Any, traj: Any) -> float:
    k = traj.solve()
    a, b = k.point("A").position, k.point("B").position
    c = np.asarray(scene._data.fixed["C"])
    lab = float(np.hypot(*(b - a)[0]))
    lcb = float(np.hypot(*(b[0] - np.array([c.real, c.imag]))))
    e1 = np.abs(np.hypot(*(b - a).T) - lab).max()
    e2 = np.abs(np.hypot(*(b - np.array([c.real, c.imag])).T) - lcb).max()
    return float(max(e1, e2))


def _work_precision(name: str, phi0: float, t_end: float) -> list[str]:
    scene = solver.load_scene(name)
    ref = scene.simulate(t_end, phi0=phi0, rtol=1e-13, atol=1e-13)
    want = float(ref.phi[-1])
    rows = []
    for tol in (1e-2, 1e-3, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12):
        scene.simulate(0.01, phi0=phi0, rtol=tol, atol=tol)  # warm
        start = time.perf_counter()
        traj = scene.simulate(t_end, phi0=phi0, rtol=tol, atol=tol)
        wall = time.perf_counter() - start
        rows.append(f"| linkage_ros DOP853 rtol=atol={tol:g} | {abs(float(traj.phi[-1]) - want):.1e} | "
                    f"{wall:.3f} s | {_closure_gap(scene, traj):.0e} m |")
    rows += _mujoco_rows(scene, phi0=phi0, t_end=t_end, want=want)
    rows += _exudyn_rows(scene, phi0=phi0, t_end=t_end, want=want)
    return rows


def _mujoco_rows(scene: Any, *, phi0: float, t_end: float, want: float) -> list[str]:
    try:
        import mujoco  # noqa: F401
    except ImportError:
        return ["| MuJoCo | not installed | | |"]
    rows = []
    xml, init = _four_bar_mjcf(scene, phi0)
    for integrator, dt, stiff in (("EULER", 1e-3, False), ("RK4", 1e-3, False), ("RK4", 1e-4, False),
                                  ("RK4", 1e-4, True), ("IMPLICITFAST", 1e-4, True), ("RK4", 1e-5, True)):
        got, wall, gap = _mujoco_run(xml, init, t_end, dt, integrator, stiff)
        label = f"MuJoCo {mujoco_version()} {integrator} dt={dt:g}{' stiff solref' if stiff else ''}"
        rows.append(f"| {label} | {abs(got - want):.1e} | {wall:.3f} s | {gap:.1e} m |")
    return rows


def _accuracy_rows() -> list[str]:
    """rtol = atol = 1e-12 on conservative scenes against their references: DOP853 at 1e-13 and an
    implicit method of another family (Radau at 1e-12); the energy balance against the kinetic
    energy's swing."""
    rows = []
    for name, phi0, t_end in (("four_bar_pendulum", 0.3, 10.0), ("four_bar_pendulum", 2.5, 10.0)):
        scene = solver.load_scene(name)
        ref = scene.simulate(t_end, phi0=phi0, rtol=1e-13, atol=1e-13)
        radau = scene.simulate(t_end, phi0=phi0, rtol=1e-12, atol=1e-12, method="Radau")
        run = scene.simulate(t_end, phi0=phi0, rtol=1e-12, atol=1e-12)
        e = run.energy()
        swing = float(np.ptp(e["kinetic"]))
        for label, other in (("DOP853 1e-13", ref), ("Radau 1e-12", radau)):
            dphi = abs(float(run.phi[-1] - other.phi[-1])) / max(abs(float(other.phi[-1])), 1.0)
            dw = abs(float(run.omega[-1] - other.omega[-1])) / float(np.abs(other.omega).max())
            rows.append(f"| {name}, φ₀ = {phi0} rad, {t_end:g} s | {label} | {dphi:.1e} | {dw:.1e} | "
                        f"{float(np.abs(e['balance']).max()) / swing:.1e} |")
    return rows


def mujoco_version() -> str:
    import mujoco

    return str(mujoco.__version__)


def main() -> None:
    info = machine()
    lines = ["## Measured", "",
             f"Measured on {info['cpu']} ({info['cores']} cores, load {info['load']}), Python {info['python']}, "
             f"numpy {info['numpy']}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, by "
             "`python -m bench.dynamics`.", "",
             "### (M, h) per instant and vectorised", "",
             "| scene | (M, h) one state | one compiled instant with efforts | ratio | (M, h) 10⁵ states | "
             "kinetostatics 10⁵ states | ratio |", "|---|---|---|---|---|---|---|"]
    lines += _cost_rows()
    lines += ["", "### Work–precision: four_bar_pendulum from rest at φ = 0.3 rad, 10 s", "",
              "Error of φ(10 s) against linkage_ros at rtol = atol = 1e-13; wall time of the whole run; the "
              "loop's largest opening (|AB| and |CB| against their lengths; MuJoCo and EXUDYN: the distance "
              "between the coupler's and the rocker's B). EXUDYN's h is its fixed step; the explicit "
              "DOPRI5 takes no joints, so there every pin is a penalty spring of stiffness k.", "",
              "| method | error of φ(10 s) (rad) | wall time | loop opening |", "|---|---|---|---|"]
    lines += _work_precision("four_bar_pendulum", 0.3, 10.0)
    lines += ["", "### Accuracy at rtol = atol = 1e-12 (conservative scenes)", "",
              "φ and ω at the end relative to |φ| (at least 1 rad) and to ω's largest size, against DOP853 at "
              "1e-13 and against Radau (implicit, another family) at 1e-12; the energy balance's largest "
              "error relative to the kinetic energy's swing.", "",
              "| run | against | φ | ω | energy balance |", "|---|---|---|---|---|"]
    lines += _accuracy_rows()
    text = "\n".join(lines) + "\n"
    print(text)
    if "--no-write" not in sys.argv:
        write_section(DOC, "## Measured", text)


if __name__ == "__main__":
    main()
