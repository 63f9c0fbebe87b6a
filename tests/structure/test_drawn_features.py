"""The drawn form's features as a user writes them: slides (``on:`` unquoted), actuators, slotted
links, bodies and loads naming links, read-outs by link with their value at the drawn pose."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from solver import load_scene
from solver.structure import find_structure
from solver.structure_cli import structure_lines

SLIDER = """\
scene: slider
units: {length: mm, angle: deg}
drawing:
  points: {O: [0, 0], A: [30, 40], B: [150, 10], G1: [-50, 10], G2: [250, 10]}
  ground: [O, G1, G2]
  links: {crank: [O, A], rod: [A, B]}
  inputs: [crank]
  slides: {piston: {point: B, on: ground, along: [G1, G2], joint: x}}
outputs: {points: [B], joints: [x]}
bodies: {piston: {mass: 0.3}, rod: {mass: 0.2, center: [50, 0]}}
gravity: [0, -9.81]
loads:
  - {body: crank, point: A, force: [1.0, 0.0]}
"""

TIPPER = """\
scene: tipper_drawn
units: {length: m, angle: deg}
drawing:
  points: {O: [0, 0], A: [-1.4, -0.55], C: [-0.8, 0.05], F: [-2.4, 0.3]}
  ground: [O, A]
  links: {body: [O, C, F]}
  actuators: {lift: {between: [A, C], stroke: [0.5, 1.3], joint: stroke}}
joints:
  floor: {revolute: {parent: ground, child: body, at: 0}}
outputs: {points: [F], joints: [stroke, floor]}
"""

FINGER = """\
scene: finger_drawn
units: {length: m, angle: deg}
drawing:
  points: {O: [0, 0], A: [0.04, -0.03], B: [0.2, 0.0], C: [0.36, 0.03], X: [0.1, 0.05]}
  ground: [O, A]
  links: {drum: [O, B], finger: [A, C, X]}
  inputs: [drum]
  slides: {eyelet: {point: B, on: finger, along: [A, C]}}
outputs: {points: [C, X]}
"""


def _write(tmp_path: Path, text: str) -> Path:
    path = tmp_path / "s.yaml"
    path.write_text(text, encoding="utf-8")
    return path


def test_a_slider_crank_with_bodies_and_loads_named_by_links(tmp_path: Path) -> None:
    path = _write(tmp_path, SLIDER)
    scene = load_scene(path)
    assert [g.kind for g in scene.plan.groups if g.kind != "joint"] == ["crank", "rrp"]
    phi = math.atan2(40, 30)
    k = scene.solve(np.array([phi]))
    assert np.allclose(k.point("B").position[0], [0.15, 0.01], rtol=0, atol=1e-15)
    assert np.isclose(k.joint("x").position[0], 0.2, rtol=0, atol=1e-15)  # from G1 along G1→G2
    assert np.isfinite(k.effort("crank")).all()
    assert scene.forces is not None
    bodies = {b.name: (b.link.points, b.mass) for b in scene.forces.spec.bodies}
    assert bodies["piston"] == (("B",), 0.3) and bodies["rod"] == (("A", "B"), 0.2)
    assert bodies["crank"] == (("O", "A"), 0.0)  # named by a load only: massless


def test_an_actuator_pushes_its_link(tmp_path: Path) -> None:
    path = _write(tmp_path, TIPPER)
    st = find_structure(__import__("yaml").safe_load(TIPPER))
    assert [(s.kind, s.mode) for s in st.ordered] == [("actuator", -1), ("attached", None)]
    scene = load_scene(path)
    s0 = st.inputs_drawn["stroke"]
    assert s0 == pytest.approx(math.hypot(0.6, 0.6))
    k = scene.solve(np.array([s0, 1.0]))
    assert np.allclose(k.point("F").position[0], [-2.4, 0.3], rtol=0, atol=1e-15)
    assert abs(k.joint("floor").position[0]) <= 1e-15  # `at: 0`: zero where it is drawn
    assert k.joint("floor").position[1] < 0.0  # a longer cylinder lifts the front (clockwise here)


def test_a_slotted_link_with_a_point_off_its_slot(tmp_path: Path) -> None:
    path = _write(tmp_path, FINGER)
    scene = load_scene(path)
    assert [g.kind for g in scene.plan.groups] == ["crank", "slotted", "attached"]
    k = scene.solve(np.array([0.0]))
    assert np.allclose(k.point("X").position[0], [0.1, 0.05], rtol=0, atol=1e-15)
    lines = structure_lines(path)
    assert "slotted 'finger': the link turns about A through B" in "\n".join(lines)
