"""Imported models (issue 31): the 2F-85's import time, the relay's cost per message on it against
the five-bar's, and MuJoCo's own loop gap beside ours.

    .venv/bin/python -m bench.models            # the measurement (~1 min)
    .venv/bin/python -m bench.models --quick    # a smoke run

* **import**: ``solver.load_scene("robotiq_2f85.xml")`` in a fresh Python process (mujoco and
  the structure finder imported on the way; the figure the issue's ≤ 1 s is about), wall-clock
  and CPU time (on a shared machine the wall-clock time includes other processes' turns), and
  again in the same process (the file alone).
* **relay**: mechanism_node's runtime in topic mode (``Runtime.answer``, rosbags' Jazzy classes,
  no rclpy; as bench/relay.py), one incoming JointState → every topic's CDR bytes, for the
  five-bar (2 inputs, efforts and pin loads) and the 2F-85 (3 inputs, 8 joints, bodies and
  gravity: efforts and ten pin loads; or its kinematics alone), the same number of messages,
  alternated passes, best of ``--repeat``; timed in the process's CPU time (``process_time``),
  which leaves out the time the shared machine gives to other processes.
* **loop gap**: MuJoCo closes the 2F-85's ``<connect>`` loops with soft constraints (solref
  0.005 1, solimp 0.95 0.99 0.001, as the model says): ``mj_step`` with the gripper's actuator
  driven 0 → 255 over 1 s, then held; the largest |anchor₁ − anchor₂| over the run. Ours: the
  imported scene solved at the inputs MuJoCo reached, its joint values put in MuJoCo's qpos,
  ``mj_kinematics``, the same gap.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
MODEL = ROOT / "tests" / "data" / "models" / "robotiq_2f85.xml"
NS = 1_000_000_000
PASSIVE = ("right_coupler_joint", "right_follower_joint", "left_driver_joint", "left_coupler_joint",
           "left_follower_joint")
INPUTS = ("right_driver_joint", "right_spring_link_joint", "left_spring_link_joint")


def import_seconds() -> tuple[float, float, float]:
    """(fresh process wall, fresh process CPU, same process CPU) seconds for load_scene of the 2F-85."""
    code = (f"import time, solver; t, c = time.perf_counter(), time.process_time(); "
            f"solver.load_scene({str(MODEL)!r}); print(time.perf_counter() - t, time.process_time() - c)")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    wall, cpu = map(float, subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                                          check=True).stdout.split())
    import solver

    solver.load_scene(MODEL)
    t = time.process_time()
    solver.load_scene(MODEL)
    return wall, cpu, time.process_time() - t


def _runtime(scene: str, names: Sequence[str], q0: Sequence[float], **settings: object) -> object:
    from rosbags.typesys import Stores, get_typestore

    from linkage_ros.runtime import Runtime

    store = get_typestore(Stores.ROS2_JAZZY)
    runtime = Runtime({"scene": scene, "input_source": "topic", **settings}, store.types,
                      serialize=store.serialize_cdr)
    for k in range(8):
        runtime.answer(list(names), list(q0), [0.0] * len(names), NS - (8 - k) * 1_000_000)
    return runtime


def _kinematic_copy(folder: Path) -> str:
    """The imported 2F-85 without its bodies and gravity, as a scene file (the kinematics alone)."""
    import yaml

    from solver.models import model_scene_data

    data, _ = model_scene_data(MODEL)
    data = {k: v for k, v in data.items() if k not in ("bodies", "gravity")}
    path = folder / "robotiq_2f85_kinematics.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False))
    return str(path)


def relay_us(n: int, repeat: int, folder: Path) -> dict[str, float]:
    """Mean µs per incoming JointState, best of ``repeat`` alternated passes, per case."""
    t = np.linspace(0.0, 1.0, n)
    q5 = np.column_stack([1.6 + 0.2 * t, 1.4 - 0.2 * t])
    q3 = np.column_stack([0.1 + 0.6 * t, 0.1 + 0.55 * t, 0.12 + 0.6 * t])
    pad = {"points": ["right_pad"]}
    cases = {
        "five_bar (P)": ("five_bar", ("q1", "q2"), q5, {}),
        "2F-85, every point, efforts and pin loads": (str(MODEL), INPUTS, q3, {}),
        "2F-85 (right_pad), efforts and pin loads": (str(MODEL), INPUTS, q3, pad),
        "2F-85 (right_pad), kinematics only": (_kinematic_copy(folder), INPUTS, q3, pad),
    }
    runtimes = {name: _runtime(sc, names, qs[0], **more) for name, (sc, names, qs, more) in cases.items()}
    best = {name: float("inf") for name in cases}
    for rep in range(repeat + 1):  # the first pass traces the compiled instant's branches: untimed
        for name, (_, names, qs, _) in cases.items():
            rt = runtimes[name]
            vel = [0.5] * len(names)
            clock = time.process_time  # CPU time of this process: the shared machine's waits left out
            t0 = clock()
            for k, row in enumerate(qs):
                out = rt.answer(list(names), row.tolist(), vel, (rep + 2) * NS + k * 1_000_000)  # type: ignore[attr-defined]
                assert out, name
            if rep:
                best[name] = min(best[name], (clock() - t0) / len(qs) * 1e6)
    return best


def loop_gaps(seconds: float = 2.0) -> tuple[float, float, float]:
    """(MuJoCo's largest connect gap over the run, m; ours at MuJoCo's inputs, m; the largest
    difference of a passive joint, MuJoCo's against ours, rad)."""
    import mujoco

    import solver

    m = mujoco.MjModel.from_xml_path(str(MODEL))
    d = mujoco.MjData(m)
    scene = solver.load_scene(MODEL)
    adr = {m.joint(j).name: int(m.joint(j).qposadr[0]) for j in range(m.njnt)}
    connects = [e for e in range(m.neq) if int(m.eq_type[e]) == int(mujoco.mjtEq.mjEQ_CONNECT)]

    def gap() -> float:
        worst = 0.0
        for e in connects:
            b1, b2 = int(m.eq_obj1id[e]), int(m.eq_obj2id[e])
            p1 = d.xpos[b1] + d.xmat[b1].reshape(3, 3) @ m.eq_data[e][0:3]
            p2 = d.xpos[b2] + d.xmat[b2].reshape(3, 3) @ m.eq_data[e][3:6]
            worst = max(worst, float(np.linalg.norm(p1 - p2)))
        return worst

    theirs, ours, joints = 0.0, 0.0, 0.0
    steps = int(seconds / m.opt.timestep)
    for i in range(steps):
        d.ctrl[0] = 255.0 * min(1.0, i * m.opt.timestep)
        mujoco.mj_step(m, d)
        theirs = max(theirs, gap())
        if i % 50 == 0:
            q = tuple(float(d.qpos[adr[n]]) for n in INPUTS)
            k = scene.solve(q, mask=True)
            if not bool(k.valid):
                continue
            saved = d.qpos.copy()
            joints = max(joints, max(abs(float(k.joint(n).position) - float(saved[adr[n]])) for n in PASSIVE))
            for n in PASSIVE:
                d.qpos[adr[n]] = float(k.joint(n).position)
            mujoco.mj_kinematics(m, d)
            ours = max(ours, gap())
            d.qpos[:] = saved
            mujoco.mj_kinematics(m, d)
    return theirs, ours, joints


def main(argv: Sequence[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="bench.models", description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--repeat", type=int, default=None)
    args = p.parse_args(argv)
    n = 200 if args.quick else 2000
    repeat = args.repeat or (1 if args.quick else 5)
    load = os.getloadavg()
    wall, cpu, warm = import_seconds()
    print(f"load average {load[0]:.2f} {load[1]:.2f} {load[2]:.2f}")
    print(f"import of the 2F-85 in a fresh process: {wall:.3f} s wall-clock, {cpu:.3f} s CPU; "
          f"{warm * 1e3:.1f} ms CPU again in the same process")
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        us = relay_us(n, repeat, Path(folder))
    base = us["five_bar (P)"]
    print("relay per incoming JointState (best of passes, same process):")
    for name, value in us.items():
        print(f"  {name}: {value:.1f} µs ({value / base:.2f}× the five-bar)")
    theirs, ours, joints = loop_gaps(1.0 if args.quick else 2.0)
    print(f"loop gap over the closing run: MuJoCo (soft connect) {theirs:.3g} m; ours {ours:.3g} m; "
          f"passive joints MuJoCo − ours up to {joints:.3g} rad")
    return 0


if __name__ == "__main__":
    sys.exit(main())
