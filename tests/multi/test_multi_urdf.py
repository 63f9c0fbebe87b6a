"""The five-bar (two inputs) in the engine and the URDF export: per-input motion laws, frames that
agree with a sweep, and a URDF (read by yourdfpy) whose cut frames coincide over a run."""

from __future__ import annotations

import io
import math

import numpy as np
import pytest

import solver
from linkage_ros.engine import Engine
from linkage_ros.frame import STATUS_UNASSEMBLABLE
from linkage_ros.motion import Motion, Motions
from linkage_ros.urdf import build_model, frame_tree_joint_states, generate_urdf, kinematics_tree_joint_states

EPS = float(np.finfo(float).eps)
TOL_CLOSURE = 1e-9
TOL_SAME = 64 * EPS
LAWS = {"phi0": (math.pi / 2, math.pi / 2), "omega": (2.0, -1.5), "epsilon": (0.7, 3.0)}


def test_per_input_laws_drive_each_input_exactly() -> None:
    motion = Motions.of(2, **LAWS)
    engine = Engine("five_bar", motion)
    t = 0.37
    frame = engine.frame(t)
    for i, name in enumerate(("q1", "q2")):
        one = Motion(phi0=LAWS["phi0"][i], omega=LAWS["omega"][i], epsilon=LAWS["epsilon"][i])
        assert frame.phi[i] == one.state(t)[0] and frame.omega[i] == one.state(t)[1]
        assert frame.joints[name].position == frame.phi[i]
        assert frame.joints[name].velocity == frame.omega[i]
    assert frame.status == "ok"


def test_frames_of_a_run_equal_single_frames() -> None:
    engine = Engine("five_bar", Motions.of(2, **LAWS))
    times = np.linspace(0.0, 1.5, 40)
    run = list(engine.frames(times))
    again = Engine("five_bar", Motions.of(2, **LAWS))
    for f in run[::7]:
        g = again.frame(f.t)
        assert f.phi == g.phi
        np.testing.assert_allclose(f.points["P"].position, g.points["P"].position, rtol=0, atol=1e-15)
        np.testing.assert_allclose(f.points["P"].acceleration, g.points["P"].acceleration, rtol=1e-13, atol=1e-13)
    assert engine.paths["P"].shape[1] == 2 and len(engine.paths["P"]) > 100


def test_a_single_law_for_two_inputs_is_refused() -> None:
    with pytest.raises(ValueError, match=r"scene 'five_bar' has 2 input\(s\) \(q1, q2\): give Motions of 2 laws"):
        Engine("five_bar", Motion())
    with pytest.raises(ValueError, match=r"omega needs 2 values \(one per input\), got 3"):
        Motions.of(2, omega=(1.0, 2.0, 3.0))


def test_the_engine_stops_where_the_five_bar_cannot_close() -> None:
    """Distal links of 0.2 m: the run from (90°, 90°) spreading the cranks apart reaches |A1A2| > 0.4."""
    from multi_builders import five_bar

    scene = five_bar(distal=0.2)
    engine = Engine(scene, Motions.of(2, phi0=(math.pi / 2, math.pi / 2), omega=(1.0, -1.0)))
    frames = [engine.frame(t) for t in np.linspace(0.0, 2.0, 81)]
    held = [f for f in frames if f.status == STATUS_UNASSEMBLABLE]
    assert held, "the run should reach the unassemblable region"
    assert "group 'distal' cannot be assembled" in held[0].message and "stopped at φ = (" in held[0].message
    assert all(math.isfinite(x) for f in frames for x in f.points["P"].position)


def test_urdf_cut_frames_coincide_over_a_two_input_sweep_and_an_engine_run() -> None:
    yourdfpy = pytest.importorskip("yourdfpy", reason="yourdfpy is the independent URDF parser of this check")
    scene = solver.load_scene("five_bar")
    model = build_model(scene)
    assert model.joint_names[:2] == ("left_crank_joint", "right_crank_joint")
    urdf = yourdfpy.URDF.load(io.StringIO(generate_urdf(scene)), load_meshes=False, build_scene_graph=True)
    grid = np.radians(np.arange(20.0, 170.0, 25.0))
    q = np.stack(np.meshgrid(grid, grid, indexing="ij"), axis=-1).reshape(-1, 2)
    k = scene.everything().solve(q, omega=(2.0, -1.5), mask=True)
    states = kinematics_tree_joint_states(model, k)
    assert states.position.shape == (len(q), len(model.joint_names))

    def gap(names: tuple[str, ...], values: object) -> float:
        urdf.update_cfg(dict(zip(names, (float(x) for x in values))))
        worst = 0.0
        for cut in model.cuts:
            a = np.asarray(urdf.get_transform(f"{cut.name}_a", "world"))[:3, 3]
            b = np.asarray(urdf.get_transform(f"{cut.name}_b", "world"))[:3, 3]
            worst = max(worst, float(np.abs(a - b).max()))
        return worst

    ok = np.flatnonzero(k.valid)
    assert max(gap(states.names, states.position[i]) for i in ok) <= TOL_CLOSURE
    engine = Engine(scene, Motions.of(2, **LAWS))
    frames = list(engine.frames(np.linspace(0.0, 1.0, 30)))
    tree = [frame_tree_joint_states(model, f) for f in frames]
    assert max(gap(s.names, s.position) for s in tree) <= TOL_CLOSURE
    one = frame_tree_joint_states(model, frames[5])
    row = kinematics_tree_joint_states(
        model, scene.everything().solve(np.array([frames[5].phi]), omega=frames[5].omega, epsilon=frames[5].epsilon)
    )
    assert np.allclose(one.position, row.position[0], rtol=0, atol=TOL_SAME * 10)
    assert np.allclose(one.velocity, row.velocity[0], rtol=TOL_SAME, atol=TOL_SAME * 10)


def test_reverse_policy_turns_every_input_back_at_the_last_valid_tick() -> None:
    from multi_builders import five_bar

    def run() -> Engine:
        return Engine(five_bar(distal=0.2), Motions.of(2, phi0=(math.pi / 2, math.pi / 2), omega=(1.0, -1.0)),
                      on_unassemblable="reverse")

    engine = run()
    frames = [engine.frame(t) for t in np.linspace(0.0, 3.0, 121)]
    events = [f for f in frames if f.status == STATUS_UNASSEMBLABLE]
    assert len(events) == 1 and "; reversed at t = " in events[0].message
    assert frames[-1].omega == (-1.0, 1.0)
    whole = list(run().frames(np.linspace(0.0, 3.0, 121)))
    assert [f.phi for f in whole] == [f.phi for f in frames]
