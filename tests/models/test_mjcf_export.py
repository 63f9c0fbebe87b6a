"""linkage-mjcf (issue 31): any pin-jointed planar scene written as MJCF with <connect> loop
closures, bodies and the inputs as actuators; importing the export gives back the scene (the
same groups, inputs and points, positions to round-off over the inputs' range)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import solver
from solver.mjcf_cli import main

mujoco = pytest.importorskip("mujoco")

CASES = {
    "four_bar": "0.5",
    "four_bar_crossed": "1.0",
    "six_bar": "0.3",
    "five_bar": "1.7,1.3",
    "gripper_finger": "0.2",
    "four_bar_loaded": "2.0",
}


@pytest.mark.parametrize("name", CASES)
def test_round_trip(tmp_path: Path, name: str) -> None:
    out = tmp_path / f"{name}.xml"
    assert main([name, "-o", str(out), "--phi", CASES[name]]) == 0
    scene, back = solver.load_scene(name), solver.load_scene(out)
    assert back.inputs == scene.inputs
    assert [g.kind for g in back.ordered if g.kind != "joint"] == [g.kind for g in scene.ordered if g.kind != "joint"]
    assert set(scene.point_names) <= set(back.point_names)
    if len(scene.inputs) == 1:
        phi: np.ndarray = np.linspace(-np.pi, np.pi, 73)
    else:
        phi = np.column_stack([np.linspace(1.5, 1.9, 21), np.linspace(1.1, 1.5, 21)])
    a = scene.everything().solve(phi, mask=True)
    b = back.everything().solve(phi, mask=True)
    assert np.array_equal(a.valid, b.valid) and a.valid.sum() > 10
    ok = a.valid
    for p in scene.point_names:
        assert np.max(np.abs(np.asarray(a.point(p).position)[ok] - np.asarray(b.point(p).position)[ok])) < 1e-14
    # MuJoCo compiles it, and at the written pose every connect is closed
    m = mujoco.MjModel.from_xml_path(str(out))
    assert m.nu == len(scene.inputs)


def test_masses_and_inertias_carry_over(tmp_path: Path) -> None:
    out = tmp_path / "loaded.xml"
    assert main(["four_bar_loaded", "-o", str(out)]) == 0
    scene, back = solver.load_scene("four_bar_loaded"), solver.load_scene(out)
    mine = {frozenset(b.link.points): b for b in scene.bodies if b.mass > 0}
    theirs = {frozenset(b.link.points): b for b in back.bodies}
    for pts, b in mine.items():
        other = next(o for key, o in theirs.items() if pts <= key)
        assert other.mass == pytest.approx(b.mass, rel=1e-15)
        assert other.inertia == pytest.approx(b.inertia, rel=1e-12)


def test_what_is_not_exported_is_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["slider_crank", "-o", "-"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("linkage-mjcf: error: ") and err.count("\n") == 1
    assert "rrp 'rod': linkage-mjcf writes pin-jointed linkages (crank, rrr, attached)" in err
