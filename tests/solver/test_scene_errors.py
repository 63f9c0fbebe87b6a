"""A malformed scene is a SceneError naming the file, the entry and what is wrong."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest
import yaml

import solver

BASE: dict[str, Any] = yaml.safe_load(
    """
scene: test
units: {length: m, angle: deg}
fixed: {O: [0, 0], C: [0.4, 0]}
groups:
  - {type: crank, name: crank, center: O, point: A, length: 0.1}
  - {type: rrr, name: dyad, ends: [A, C], point: B, lengths: [0.4, 0.3], M: +1}
joints:
  rocker: {angle: [C, B]}
outputs: {points: [B], joints: [rocker]}
"""
)


def _load(tmp_path: Path, edit: Any) -> solver.Scene:
    data = copy.deepcopy(BASE)
    edit(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return solver.load_scene(path)


def _set(path: str, value: Any):  # type: ignore[no-untyped-def]
    def edit(data: Any) -> None:
        *head, last = path.split("/")
        node = data
        for key in head:
            node = node[int(key)] if key.isdigit() else node[key]
        if value is KeyError:
            del node[int(last) if last.isdigit() else last]
        else:
            node[int(last) if last.isdigit() else last] = value

    return edit


@pytest.mark.parametrize(
    ("edit", "message"),
    [
        (_set("groups/1/ends", ["A", "Z"]), r"bad\.yaml: rrr 'dyad': unknown point or joint 'Z'"),
        (_set("groups/1/lengths", [0.4, -0.3]), r"groups\[1\]\.lengths\.CB: length must be positive, got -0\.3"),
        (_set("groups/0/length", 0), r"groups\[0\]\.length: length must be positive, got 0"),
        (_set("groups/1/M", 2), r"groups\[1\]\.M: assembly mode must be \+1 or -1, got 2"),
        (_set("groups/1/M", KeyError), r"groups\[1\]\.M: missing required field"),
        (
            _set("groups/1/type", "rrrr"),
            r"groups\[1\]\.type: unknown group type 'rrrr' \(did you mean 'rrr'\?\); known types: .*rrr",
        ),
        (_set("units/length", "inch"), r"units\.length: unknown length unit 'inch'"),
        (_set("units", KeyError), r"bad\.yaml: units: missing required field"),
        (_set("outputs/points", ["Q"]), r"outputs\.points: unknown point 'Q'"),
        (_set("outputs/joints", ["B"]), r"outputs\.joints: unknown joint 'B'"),
        (_set("groups/1/colour", "red"), r"groups\[1\]: unknown field\(s\): colour"),
        (_set("fixed/C", [0.4]), r"fixed\.C: must be \[x, y\] or \[x, y, z\]"),
        (_set("groups/0/center", "A"), r"groups\[0\]\.center: the crank turns about a fixed point; 'A' is not one of"),
        (_set("joints/rocker", {"spin": ["C", "B"]}), r"joints\.rocker: must be one of \{angle: …"),
        (_set("groups/1/point", "A"), r"'A' is defined twice"),
    ],
)
def test_malformed_scene_names_file_entry_and_fault(tmp_path: Path, edit: Any, message: str) -> None:
    with pytest.raises(solver.SceneError, match=message):
        _load(tmp_path, edit)


def test_scene_without_an_input_is_rejected(tmp_path: Path) -> None:
    def edit(data: Any) -> None:
        data["groups"] = data["groups"][1:]
        data["fixed"]["A"] = [0.1, 0.0]

    with pytest.raises(solver.SceneError, match=r"a scene needs exactly one input \(a crank\), found 0"):
        _load(tmp_path, edit)


def test_missing_file_lists_the_shipped_scenes() -> None:
    with pytest.raises(solver.SceneError, match=r"nope\.yaml: no such scene file.*four_bar"):
        solver.load_scene("nope.yaml")


def test_invalid_yaml_is_a_scene_error(tmp_path: Path) -> None:
    path = tmp_path / "broken.yaml"
    path.write_text("groups: [unclosed\n", encoding="utf-8")
    with pytest.raises(solver.SceneError, match=r"broken\.yaml:\d+: not valid YAML"):
        solver.load_scene(path)


def test_lengths_in_millimetres_are_converted_to_metres(tmp_path: Path) -> None:
    def edit(data: Any) -> None:
        data["units"]["length"] = "mm"
        data["fixed"]["C"] = [400, 0]
        data["groups"][0]["length"] = 100
        data["groups"][1]["lengths"] = [400, 300]

    mm = _load(tmp_path, edit).solve(0.7).point("B").position
    m = solver.load_scene("four_bar").solve(0.7).point("B").position
    assert mm == pytest.approx(m, rel=1e-15)


def test_unassemblable_position_is_an_assembly_error_never_nan() -> None:
    data = copy.deepcopy(BASE)
    data["groups"][1]["lengths"] = [0.25, 0.2]
    scene = solver.Scene(solver._loader.parse_scene(data, file="double_rocker"))
    with pytest.raises(solver.AssemblyError, match=r"group 'dyad' cannot be assembled.*requested φ = 180\.0000°"):
        scene.solve([0.0, 3.141592653589793])
    with pytest.raises(solver.AssemblyError, match=r"group 'dyad' cannot be assembled"):
        scene.solve(3.141592653589793)
