"""``linkage-import`` both ways and ``linkage-solve --structure``: files written, read back, one
line and status 2 for a fault."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from solver import load_scene
from solver._loader import parse_scene
from solver.cli import main as solve_main
from solver.scene import Scene
from solver.structure import scene_dict_from_drawing
from solver.structure_cli import drawing_of_scene, import_main

MIXED = """\
scene: mixed
units: {length: m, angle: deg}
fixed: {O: [0, 0], A: [-1.4, -0.55], Q: [1.0, 0.0]}
groups:
  - {type: actuator, name: lift, base: A, point: C, pivot: O, length: 0.8, M: -1, joint: stroke, stroke: [0.74, 1.30]}
  - {type: crank, name: wheel, center: Q, point: W, length: 0.2}
  - {type: rrr, name: tie, ends: [C, W], point: T, lengths: [1.0, 1.0], M: 1}
outputs: {points: [T], joints: [stroke, wheel]}
"""


def test_import_writes_the_group_form_and_it_solves_bit_identically(tmp_path: Path) -> None:
    out = tmp_path / "groups.yaml"
    assert import_main(["crank_rocker_drawn", "-o", str(out)]) == 0
    text = out.read_text(encoding="utf-8")
    assert "\ndrawing:" not in text and "type: rrr" in text
    a, b = load_scene("crank_rocker_drawn").everything(), load_scene(out).everything()
    phi = np.linspace(0.0, 2 * np.pi, 97)
    ka, kb = a.solve(phi), b.solve(phi)
    for p in a.point_names:
        assert np.array_equal(ka.point(p).position, kb.point(p).position)
    assert np.array_equal(ka.effort("crank"), kb.effort("crank"))
    assert a.solve(0.4).point("P").position == b.solve(0.4).point("P").position  # the compiled instant too


def test_import_drawing_at_an_input_value_and_back(tmp_path: Path) -> None:
    out = tmp_path / "drawn.yaml"
    assert import_main(["six_bar", "--drawing", "--phi", "30", "--deg", "-o", str(out)]) == 0
    drawn = load_scene(out)
    six = load_scene("six_bar")
    k1, k2 = drawn.solve(np.radians([30.0, 100.0])), six.solve(np.radians([30.0, 100.0]))
    for p in six.output_points:
        assert np.allclose(k1.point(p).position, k2.point(p).position, rtol=0, atol=1e-15)


def test_a_mixed_scene_keeps_its_input_order(tmp_path: Path) -> None:
    path = tmp_path / "mixed.yaml"
    path.write_text(MIXED, encoding="utf-8")
    drawn = drawing_of_scene(path, [1.0, 0.5])
    assert drawn["drawing"]["inputs"] == ["lift", "wheel"]  # the actuator listed first, in its place
    again = Scene(parse_scene(scene_dict_from_drawing(drawn), file=None))
    assert again.inputs == load_scene(path).inputs == ("stroke", "wheel")


def test_import_faults_are_one_line_and_status_2(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert import_main(["six_bar", "-o", str(tmp_path / "x.yaml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "has no drawing: section" in err
    assert import_main(["hard/parallelogram", "--drawing", "-o", str(tmp_path / "x.yaml")]) == 2
    assert "through_change_points: continuous" in capsys.readouterr().err
    assert import_main(["five_bar", "--drawing", "--phi", "1", "-o", str(tmp_path / "x.yaml")]) == 2
    assert "has 2 input(s) (q1, q2): give 2 value(s), got 1" in capsys.readouterr().err
    assert import_main(["crank_rocker_drawn", "--phi", "1", "-o", str(tmp_path / "x.yaml")]) == 2
    assert "--phi and --deg go with --drawing" in capsys.readouterr().err


def test_solve_structure_prints_the_decomposition(capsys: pytest.CaptureFixture[str]) -> None:
    assert solve_main(["crank_rocker_drawn", "--structure"]) == 0
    out = capsys.readouterr().out
    assert "mobility F = 3(n − 1) − 2j₁ − j₂ = 3·3 − 2·4 − 0 = 1, inputs 1 (crank)" in out
    assert "as drawn: crank = 53.1301°" in out
    assert "rrr 'coupler_rocker': B from ends [A, C], lengths [0.152643 m, 0.126491 m], M = -1" in out
    assert solve_main(["excavator", "--structure"]) == 0
    assert "= 3, inputs 3 (boom_stroke, arm_stroke, bucket_stroke)" in capsys.readouterr().out
    assert solve_main(["spherical_converter", "--structure"]) == 0
    assert "no planar link structure" in capsys.readouterr().out
    assert solve_main(["nonexistent_scene", "--structure"]) == 2
    assert capsys.readouterr().err.count("\n") == 1
