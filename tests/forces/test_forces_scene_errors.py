"""Bad ``bodies``, ``gravity`` and ``loads`` are one SceneError line naming the key and the reason."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest
import yaml

import solver

BASE: dict[str, Any] = yaml.safe_load(
    """
scene: loaded
units: {length: m, angle: deg}
fixed: {O: [0, 0], C: [0.4, 0]}
groups:
  - {type: crank, name: crank, center: O, point: A, length: 0.1}
  - {type: rrr, name: dyad, ends: [A, C], point: B, lengths: [0.4, 0.3], M: +1}
joints:
  rocker: {angle: [C, B]}
outputs: {points: [B], joints: [rocker]}
bodies:
  crank: {points: [O, A], mass: 0.25, center: [0.04, 0.01], inertia: 2.0e-4}
  coupler: {points: [A, B], mass: 0.9, center: [0.18, 0.03], inertia: 1.3e-2}
  rocker: {points: [C, B], mass: 0.6, center: [0.12, -0.02], inertia: 5.0e-3}
gravity: [0.0, -9.81]
loads:
  - {body: rocker, point: B, force: [3.0, -20.0]}
  - {body: rocker, torque: 1.5}
"""
)


def _load(tmp_path: Path, edit: Any) -> solver.Scene:
    data = copy.deepcopy(BASE)
    edit(data)
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return solver.load_scene(path)


def _set(path: str, value: Any):  # type: ignore[no-untyped-def]
    def edit(data: Any) -> None:
        *head, last = path.split("/")
        node = data
        for key in head:
            node = node[int(key)] if isinstance(node, list) else node[key]
        if isinstance(node, list):
            node[int(last)] = value
        else:
            node[last] = value

    return edit


CASES = [
    ("bodies/coupler/mass", -0.9, r"bad\.yaml:\d+: bodies\.coupler\.mass: must not be negative, got -0\.9$"),
    ("bodies/coupler/inertia", float("inf"), r"bodies\.coupler\.inertia: must be finite, got inf$"),
    ("bodies/coupler/mass", float("nan"), r"bodies\.coupler\.mass: must be finite, got nan$"),
    ("bodies/coupler/mass", "0.9 kg", r"bodies\.coupler\.mass: must be a number, got '0\.9 kg'$"),
    ("bodies/coupler/mass", "1e-3", r"bodies\.coupler\.mass: must be a number, got the text '1e-3'.*write 1\.0e-3"),
    (
        "bodies/coupler/points",
        ["O", "B"],
        r"bodies\.coupler\.points: \['O', 'B'\] are not points of one link of "
        r"the scene; links: crank \[O, A\]; dyad\.1 \[A, B\]; dyad\.2 \[C, B\]$",
    ),
    (
        "bodies/coupler/points",
        ["C", "B"],
        r"bodies\.coupler\.points: two bodies for one link \(dyad\.2 \[C, B\]\): "
        r"'coupler' and 'rocker'|two bodies for one link",
    ),
    ("bodies/coupler/points", ["B"], r"a body named by one point is a slider block; 'B' is the pin of none"),
    ("bodies/coupler/center", [0.1], r"bodies\.coupler\.center: must be \[x, y\] \(a planar vector\), got \[0\.1\]$"),
    ("bodies/coupler/mas", 1.0, r"bodies\.coupler: unknown field 'mas' \(did you mean 'mass'\?\)"),
    ("bodies/ground", {"points": ["O", "C"]}, r"bodies\.ground: 'ground' is the frame"),
    ("gravity", [0.0, -9.81, 0.0], r"gravity: must be \[gx, gy\] in m/s² \(planar scenes\), got 3 components$"),
    ("gravity", "down", r"gravity: must be \[gx, gy\] in m/s² \(planar scenes\), got 'down'$"),
    ("gravity", [0.0, ".inf"], r"gravity\.y: must be a number"),
    ("loads/0/body", "rotor", r"loads\[0\]\.body: unknown body 'rotor'; bodies: crank, coupler, rocker$"),
    ("loads/0/body", "rockr",
     r"loads\[0\]\.body: unknown body 'rockr' \(did you mean 'rocker'\?\); bodies: crank, coupler, rocker$"),
    ("loads/0/force", ["zero", 0.0], r"bad\.yaml:\d+: loads\[0\]\.force\.x: must be a number, got 'zero'$"),
    ("loads/0/force", [0.0, "-20 N"], r"loads\[0\]\.force\.y: must be a number, got '-20 N'$"),
    ("bodies/coupler/center", [0.1, "up"], r"bodies\.coupler\.center\.y: must be a number, got 'up'$"),
    ("loads/1", {"spring": [["rockr", "B"], ["ground", "O"]], "stiffness": 10.0},
     r"loads\[1\]\.spring: unknown body 'rockr' \(did you mean 'rocker'\?\); bodies: crank, coupler, rocker, "
     r"ground$"),
    ("loads/0/point", "A", r"loads\[0\]\.point: 'A' is not a point of body 'rocker' \(C, B\)$"),
    ("loads/0/forse", [1.0, 0.0], r"loads\[0\]: unknown field 'forse' \(did you mean 'force'\?\)"),
    ("loads/0/force", [1.0, 2.0, 3.0], r"loads\[0\]\.force: must be \[x, y\] \(a planar vector\)"),
    ("loads/1/body", "ground", r"loads\[1\]\.body: ground is never solved"),
    ("loads/1", {"body": "rocker"}, r"loads\[1\]: a load is one of force, torque, spring or table; got none$"),
    (
        "loads/1",
        {"spring": [["rocker", "B"], ["ground", "A"]], "stiffness": 10.0},
        r"loads\[1\]\.spring: 'A' is not a point of body 'ground'$",
    ),
    (
        "loads/1",
        {"spring": [["rocker", "B"], ["rocker", "C"]], "stiffness": 10.0},
        r"loads\[1\]\.spring: both ends on body 'rocker'",
    ),
    (
        "loads/1",
        {"spring": [["rocker", "B"], ["ground", "O"]], "stiffness": -10.0},
        r"loads\[1\]\.stiffness: must not be negative, got -10\.0$",
    ),
    (
        "loads/1",
        {
            "body": "rocker",
            "point": "B",
            "direction": [1.0, 0.0],
            "table": {"of": "rockr", "at": [0.0, 1.0], "force": [0.0, 1.0]},
        },
        r"loads\[1\]\.table\.of: unknown joint 'rockr' \(did you mean 'rocker'\?\); joints: crank, rocker$",
    ),
    (
        "loads/1",
        {
            "body": "rocker",
            "point": "B",
            "direction": [1.0, 0.0],
            "table": {"of": "rocker", "at": [10.0, 5.0], "force": [0.0, 1.0]},
        },
        r"loads\[1\]\.table\.at: positions must increase strictly$",
    ),
    (
        "loads/1",
        {
            "body": "rocker",
            "point": "B",
            "direction": [0.0, 0.0],
            "table": {"of": "rocker", "at": [0.0, 5.0], "force": [0.0, 1.0]},
        },
        r"loads\[1\]\.direction: must not be \[0, 0\]",
    ),
    ("gravty", [0.0, -9.81], r"bad\.yaml:\d+: unknown field 'gravty' \(did you mean 'gravity'\?\)"),
    ("lods", [], r"unknown field 'lods' \(did you mean 'loads'\?\)"),
]


@pytest.mark.parametrize(("path", "value", "message"), CASES, ids=[f"{c[0]}={c[1]!r}"[:50] for c in CASES])
def test_a_bad_force_key_is_one_line_naming_the_key_and_the_reason(
    tmp_path: Path, path: str, value: Any, message: str
) -> None:
    with pytest.raises(solver.SceneError, match=message) as info:
        _load(tmp_path, _set(path, value))
    assert "\n" not in str(info.value)


def test_a_spherical_scene_with_forces_says_3d_forces_are_not_modelled(tmp_path: Path) -> None:
    text = solver.find_scene("spherical_converter").read_text(encoding="utf-8") + "\ngravity: [0.0, -9.81]\n"
    (tmp_path / "s.yaml").write_text(text, encoding="utf-8")
    with pytest.raises(
        solver.SceneError,
        match=r"s\.yaml:\d+: gravity: .*spatial \(seed 001\): 3-D forces and "
        r"moments are not modelled",
    ):
        solver.load_scene(tmp_path / "s.yaml")


def test_a_vector_loop_scene_with_forces_is_one_clear_error(tmp_path: Path) -> None:
    text = solver.find_scene("vectors/pl3_slider_crank").read_text(encoding="utf-8")
    (tmp_path / "v.yaml").write_text(text + "\nloads: []\n", encoding="utf-8")
    with pytest.raises(solver.SceneError, match=r"loads: .*a vector-loop scene \(seed 004\) has no body structure"):
        solver.load_scene(tmp_path / "v.yaml")


def test_an_attached_point_between_two_links_cannot_carry_a_load(tmp_path: Path) -> None:
    def edit(data: Any) -> None:
        data["groups"].append(
            {"type": "attached", "name": "odd", "point": "T", "base": "A", "along": ["O", "B"], "distance": 0.1}
        )

    with pytest.raises(
        solver.SceneError,
        match=r"attached 'odd': its base A and along \[O, B\] are not points of one "
        r"link",
    ):
        _load(tmp_path, edit)


def test_the_scene_without_its_errors_loads(tmp_path: Path) -> None:
    scene = _load(tmp_path, lambda data: None)
    assert scene.has_forces
