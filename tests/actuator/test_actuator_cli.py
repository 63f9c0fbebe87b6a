"""linkage-solve on scenes driven by actuators: strokes in m in the grid, the CSV and the summary."""

from __future__ import annotations

import io

import numpy as np
import pytest

import solver
from solver.cli import main


def _out(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    cap = capsys.readouterr()
    return code, cap.out, cap.err


def test_the_default_sweep_is_the_whole_stroke_in_metres(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _out(capsys, "tipper", "--phi-count", "8", "--omega", "0.05", "--csv", "-")
    assert code == 0 and err == ""
    rows = np.loadtxt(io.StringIO(out), delimiter=",", skiprows=1)
    assert out.splitlines()[0].startswith("stroke,C.x,C.y,")
    np.testing.assert_array_equal(rows[:, 0], np.linspace(0.74, 1.30, 8))
    k = solver.load_scene("tipper").solve(np.linspace(0.74, 1.30, 8), omega=0.05)
    np.testing.assert_array_equal(rows[:, 1:3], k.point("C").position)


def test_range_narrows_the_stroke_in_metres(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _out(capsys, "tipper", "--range", "0.8:0.9", "--phi-count", "3", "--csv", "-")
    assert code == 0
    strokes = np.loadtxt(io.StringIO(out), delimiter=",", skiprows=1)[:, 0]
    np.testing.assert_array_equal(strokes, np.linspace(0.8, 0.9, 3))
    code, _, err = _out(capsys, "tipper", "--range", "stroke=0.8:1.4", "--phi-count", "3")
    assert code == 2 and err.startswith("linkage-solve: error: ") and err.endswith("requested s = 1.4 m\n")
    code, _, err = _out(capsys, "tipper", "--range", "lift=0.8:0.9")
    assert code == 2 and err == "linkage-solve: error: --range 'lift=0.8:0.9': give LO:HI (m) or stroke=LO:HI\n"
    code, _, err = _out(capsys, "tipper", "--deg", "--phi", "0.9")
    assert code == 2 and "--deg: the input 'stroke' of tipper is an actuator's stroke, in m" in err


def test_the_summary_speaks_of_strokes_in_metres(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _out(capsys, "tipper", "--phi-count", "12", "--omega", "0.05")
    lines = out.splitlines()
    assert code == 0
    assert lines[0].startswith("scene tipper: 12 positions over its stroke of the input 'stroke'; ṡ = 0.05 m/s, "
                               "s̈ = 0 m/s²")
    assert "  singular positions over the stroke, a group's conditioning 0 (0 of the samples singular):" in lines
    assert any(line.startswith("  effort stroke: peak |Q| = 55708.7 N at s = 0.7400 m") for line in lines)
    assert "°" not in "".join(line for line in lines if "at s =" in line and "floor" not in line)


def test_a_grid_of_strokes_spans_each_cylinder(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, _ = _out(capsys, "excavator", "--count", "2", "--deg", "--range", "arm_stroke=1.4:1.5", "--csv", "-")
    assert code == 0
    rows = np.loadtxt(io.StringIO(out), delimiter=",", skiprows=1)
    assert out.splitlines()[0].startswith("boom_stroke,arm_stroke,bucket_stroke,")
    assert sorted(set(rows[:, 0])) == [1.05, 1.6] and sorted(set(rows[:, 1])) == [1.4, 1.5]


def test_the_urdf_opens_the_cylinder_into_barrel_and_rod_with_the_stroke_as_a_prismatic_joint() -> None:
    from linkage_ros.load_messages import tree_effort_joints
    from linkage_ros.urdf import build_model, generate_urdf, tree_joint_states

    scene = solver.load_scene("excavator").everything()
    model = build_model(scene)
    rods = [j for j in model.joints if j.type == "prismatic"]
    assert [(j.name, j.parent, j.child) for j in rods] == [
        (f"{a}_rod_joint", f"{a}_barrel", f"{a}_rod") for a in ("boom_cylinder", "arm_cylinder", "bucket_cylinder")]
    q = np.array([[1.3, 1.6, 1.2], [1.1, 1.85, 1.4]])
    states = tree_joint_states(model, scene.solve(q, omega=(0.1, -0.2, 0.3)))
    cols = [states.names.index(j.name) for j in rods]
    np.testing.assert_allclose(states.position[:, cols], q, rtol=0, atol=1e-15)
    np.testing.assert_allclose(states.velocity[:, cols], [[0.1, -0.2, 0.3]] * 2, rtol=0, atol=1e-15)
    assert tree_effort_joints(model, scene.inputs) == [(j.name, q_) for j, q_ in zip(rods, scene.inputs)]
    text = generate_urdf(scene)
    assert '<joint name="arm_cylinder_rod_joint" type="prismatic">' in text
    assert '<limit lower="1.3" upper="1.9" effort="1000000" velocity="1000" />' in text  # no motor: defaults
