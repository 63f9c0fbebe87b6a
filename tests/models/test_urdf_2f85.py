"""The 2F-85 as URDF (issue 31): an onshape-to-robot-style file (``closing_*_1``/``closing_*_2``
frame pairs) and a URDF+ file (``<constraint type="loop">``), both written from the MJCF by
tests/data/models/make_2f85_urdfs.py, import to the same scene as the MJCF; ``<mimic>`` is the
coupled input; faults are one SceneError line."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import solver

pytest.importorskip("yourdfpy")
pytest.importorskip("mujoco")

DATA = Path(__file__).resolve().parents[1] / "data" / "models"
INPUTS = ("right_driver_joint", "right_spring_link_joint", "left_spring_link_joint")


@pytest.fixture(scope="module")
def mjcf() -> solver.Scene:
    return solver.load_scene(DATA / "robotiq_2f85.xml")


@pytest.mark.parametrize("form", ["onshape", "urdfplus"])
def test_the_urdf_forms_import_to_the_mjcf_scene(mjcf: solver.Scene, form: str) -> None:
    scene = solver.load_scene(DATA / f"robotiq_2f85_{form}.urdf")
    assert scene.inputs == INPUTS  # the transmission's joint, completed by the spring links
    assert scene.model.kind == "URDF"
    assert [g.kind for g in scene.ordered] == [g.kind for g in mjcf.ordered]
    assert set(scene.output_joints) == set(mjcf.output_joints)
    d = np.linspace(0.0, 0.8, 17)
    q = np.column_stack([d, d - 0.05, d + 0.02])
    k, km = scene.solve(q, omega=0.3, epsilon=0.1), mjcf.solve(q, omega=0.3, epsilon=0.1)
    for j in mjcf.output_joints:
        for attr in ("position", "velocity", "acceleration"):
            np.testing.assert_allclose(getattr(k.joint(j), attr), getattr(km.joint(j), attr), rtol=0, atol=1e-12)
    for j in INPUTS:  # the same bodies: masses, centres, inertias about the plane's normal
        np.testing.assert_allclose(k.effort(j), km.effort(j), rtol=1e-9, atol=1e-15)


def test_mimic_is_the_coupled_input(tmp_path: Path) -> None:
    text = (DATA / "robotiq_2f85_onshape.urdf").read_text()
    text = text.replace('<mimic joint="right_driver_joint" multiplier="1" offset="0"/>',
                        '<mimic joint="right_driver_joint" multiplier="0.5" offset="0"/>')
    path = tmp_path / "half.urdf"
    path.write_text(text)
    scene = solver.load_scene(path)
    k = scene.solve((0.4, 0.35, 0.2))
    assert float(k.joint("left_driver_joint").position) == pytest.approx(0.2, abs=1e-15)


def test_faults(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    text = (DATA / "robotiq_2f85_urdfplus.urdf").read_text()
    bad = tmp_path / "bad.urdf"
    bad.write_text(text.replace('name="right_coupler_joint" type="revolute"', 'name="right_coupler_joint" '
                                'type="floating"'))
    with pytest.raises(solver.SceneError, match=r"bad.urdf: joint right_coupler_joint: joint 'right_coupler_joint' "
                                                r"is floating: a spatial mechanism"):
        solver.load_scene(bad)
    bad.write_text(text.replace('type="loop"', 'type="coupling"', 1))
    with pytest.raises(solver.SceneError, match=r"constraint right_loop: constraint 'right_loop' of type 'coupling'"):
        solver.load_scene(bad)
    with pytest.raises(solver.SceneError, match=r"keyframe: a URDF has no keyframes"):
        solver.load_scene(DATA / "robotiq_2f85_onshape.urdf", keyframe="open")
    monkeypatch.setitem(sys.modules, "yourdfpy", None)
    with pytest.raises(solver.SceneError, match=r"reading URDF needs the yourdfpy package: pip install yourdfpy"):
        solver.load_scene(DATA / "robotiq_2f85_onshape.urdf")
