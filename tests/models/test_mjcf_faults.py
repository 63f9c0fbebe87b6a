"""MJCF import: a planar four-bar closed by a connect, and every fault as one SceneError line (issue 31)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

import solver

pytest.importorskip("mujoco")

FOUR_BAR = """
<mujoco model="four_bar">
  <compiler angle="degree"/>
  <worldbody>
    <body name="crank" pos="0 0 0">
      <joint name="crank_joint" type="hinge" axis="0 0 1" {crank_extra}/>
      <inertial mass="0.1" pos="0.05 0 0" diaginertia="1e-5 1e-4 1e-4"/>
      <body name="coupler" pos="0.1 0 0" euler="0 0 60">
        <joint name="coupler_joint" type="{coupler_type}" axis="{coupler_axis}"/>
        <inertial mass="0.2" pos="0.2 0 0" diaginertia="1e-5 1e-3 1e-3"/>
        <body name="tip" pos="0.4 0 0"/>
      </body>
    </body>
    <body name="rocker" pos="0.4 0 0">
      <joint name="rocker_joint" type="hinge" axis="0 0 -1"/>
      <inertial mass="0.15" pos="0 0.1 0" diaginertia="1e-5 1e-4 1e-4"/>
    </body>
  </worldbody>
  <equality>
    <connect name="loop" body1="coupler" body2="rocker" anchor="0.4 0 0"/>
    {equality}
  </equality>
  <actuator><motor joint="crank_joint"/></actuator>
</mujoco>
"""


def _write(tmp_path: Path, name: str = "four_bar.xml", **fmt: str) -> Path:
    values = {"crank_extra": "", "coupler_type": "hinge", "coupler_axis": "0 0 1", "equality": ""} | fmt
    path = tmp_path / name
    path.write_text(FOUR_BAR.format(**values))
    return path


def test_a_four_bar_with_a_connect(tmp_path: Path) -> None:
    scene = solver.load_scene(_write(tmp_path))  # the input: the actuated joint
    assert scene.inputs == ("crank_joint",)
    kinds = [g.kind for g in scene.ordered if g.kind != "joint"]
    assert kinds[:2] == ["crank", "rrr"]
    k = scene.solve(0.0)
    for j in scene.output_joints:
        assert abs(k.joint(j).position) < 1e-14
    # the rocker's axis is −z: its qpos is clockwise positive
    k1 = scene.solve(0.1)
    assert k1.joint("rocker_joint").position < 0.0 or k1.joint("rocker_joint").position > 0.0
    assert np.isfinite(k1.effort("crank_joint"))


def test_non_parallel_hinge_axes_are_a_spatial_loop(tmp_path: Path) -> None:
    path = _write(tmp_path, coupler_axis="0 1 1")
    with pytest.raises(solver.SceneError, match=(
            r"four_bar.xml: joint coupler_joint: spatial loop 'loop': hinge 'coupler_joint' axis "
            r"\(-0.612372, 0.353553, 0.707107\) is not parallel to hinge 'crank_joint' axis \(0, 0, 1\), 45° off")):
        solver.load_scene(path)


def test_a_ball_joint_is_spatial(tmp_path: Path) -> None:
    path = _write(tmp_path, coupler_type="ball")
    with pytest.raises(solver.SceneError, match=r"joint coupler_joint: joint 'coupler_joint' of body 'coupler' is a "
                                                r"ball joint: a spatial mechanism"):
        solver.load_scene(path)


def test_a_nonlinear_joint_equality_is_refused(tmp_path: Path) -> None:
    eq = '<joint name="tie" joint1="rocker_joint" joint2="crank_joint" polycoef="0 1 0.5 0 0"/>'
    with pytest.raises(solver.SceneError, match=r"equality tie: tie: joint 'rocker_joint' = polynomial of "
                                                r"'crank_joint' with polycoef 0 1 0.5 0 0: only a linear one"):
        solver.load_scene(_write(tmp_path, equality=eq))


def test_missing_mujoco_is_one_line(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setitem(sys.modules, "mujoco", None)
    with pytest.raises(solver.SceneError,
                       match=r"four_bar.xml: reading MJCF needs the mujoco package .*pip install mujoco"):
        solver.load_scene(_write(tmp_path))


def test_a_file_mujoco_cannot_compile(tmp_path: Path) -> None:
    path = tmp_path / "broken.xml"
    path.write_text("<mujoco><worldbody><body><joint type='nope'/></body></worldbody></mujoco>")
    with pytest.raises(solver.SceneError, match=r"broken.xml: MuJoCo cannot compile it: "):
        solver.load_scene(path)


def test_an_unknown_input_and_a_moving_input(tmp_path: Path) -> None:
    path = _write(tmp_path)
    with pytest.raises(solver.SceneError, match=r"inputs: input 'nope' is not a joint of the model; joints: "
                                                r"crank_joint, coupler_joint, rocker_joint"):
        solver.load_scene(path, inputs=["nope"])
    with pytest.raises(solver.SceneError, match=r"input 'coupler_joint' turns 'coupler' on 'crank', a moving body"):
        solver.load_scene(path, inputs=["coupler_joint"])


def test_keyframe_pose(tmp_path: Path) -> None:
    path = _write(tmp_path)
    with pytest.raises(solver.SceneError, match=r"keyframe: no keyframe 'open'; keyframes: none"):
        solver.load_scene(path, keyframe="open")


def test_a_slide_joint_is_a_slider_block() -> None:
    """A slider-crank: the slide's body is the block, pinned to the rod by a connect; the slide
    is published as a prismatic read-out in the model's convention (qpos from the pose)."""
    path = Path(__file__).resolve().parents[1] / "data" / "models" / "slider_crank.xml"
    scene = solver.load_scene(path)
    assert [g.kind for g in scene.ordered if g.kind != "joint"] == ["crank", "rrp"]
    phi = np.linspace(-np.pi, np.pi, 37)
    k = scene.solve(phi)
    a, e, rod = 0.1, 0.02, float(np.hypot(0.28, 0.02))
    x = a * np.cos(phi) + np.sqrt(rod**2 - (a * np.sin(phi) - e) ** 2)
    np.testing.assert_allclose(np.asarray(k.point("B").position)[:, 0], x, rtol=0, atol=1e-15)
    np.testing.assert_allclose(k.joint("slide").position, x - 0.38, rtol=0, atol=1e-15)
    assert np.all(np.isfinite(k.effort("crank_joint")))
