"""Structural faults of a vector model are SceneErrors naming the contour and its unknowns (issue 3)."""

from __future__ import annotations

import copy
import math
from pathlib import Path
from typing import Any

import numpy as np
import pytest
import yaml

import solver
from solver import AssemblyError, SceneError
from solver._loader import parse_scene
from solver.scene import Scene


def _data(name: str) -> dict[str, Any]:
    return yaml.safe_load(Path(solver.find_scene(name)).read_text(encoding="utf-8"))


def _load(data: dict[str, Any]) -> Scene:
    return Scene(parse_scene(copy.deepcopy(data), file="test.yaml"))


def test_contour_with_three_unknowns_names_them() -> None:
    d = _data("four_bar_vectors")
    d["vector_model"]["vectors"]["CB"]["r"] = "unknown"
    with pytest.raises(SceneError, match=r"contours\.dyad: has 3 unknowns \(AB\.alpha, CB\.r, CB\.alpha\).*two"):
        _load(d)


def test_contour_with_one_unknown_names_it() -> None:
    d = _data("four_bar_vectors")
    d["vector_model"]["vectors"]["CB"]["alpha"] = 90
    with pytest.raises(SceneError, match=r"contours\.dyad: has 1 unknown\(s\) \(AB\.alpha\)"):
        _load(d)


def test_contour_whose_unknowns_an_earlier_one_solved_is_over_determined() -> None:
    d = _data("four_bar_vectors")
    d["vector_model"]["contours"]["again"] = {"sum": ["OA", "AB", "-CB", "-OC"], "M": 1}
    match = r"contours\.again: has 0 unknown\(s\) \(none\) \(AB\.alpha, CB\.alpha solved by earlier"
    with pytest.raises(SceneError, match=match):
        _load(d)


def test_contours_that_cannot_be_ordered_are_listed_with_their_unknowns() -> None:
    d = _data("four_bar_vectors")
    v = d["vector_model"]["vectors"]
    v["CB"]["r"] = "unknown"
    v["OX"] = {"r": "unknown", "alpha": "unknown"}
    d["vector_model"]["contours"]["other"] = {"sum": ["OX", "-CB"]}
    match = (
        r"cannot be put in a solvable order.*'dyad' has AB\.alpha, CB\.r, CB\.alpha; "
        r"'other' has OX\.r, OX\.alpha, CB\.r, CB\.alpha"
    )
    with pytest.raises(SceneError, match=match):
        _load(d)


def test_links_from_both_unknowns_are_rejected_except_in_pl4s() -> None:
    d = _data("vectors/pl2s_linked_slides")
    v = d["vector_model"]["vectors"]
    v["ZW"] = {"r": {"link": "ZA", "plus": 0.01}, "alpha": 120}
    d["vector_model"]["contours"]["carriage"]["sum"].append("ZW")
    with pytest.raises(SceneError, match=r"Пл2s\(OY\.r, ZA\.r\) has links from both of its unknowns.*except Пл4s"):
        _load(d)
    _load(_data("vectors/pl4s_bent_four_bar"))  # Пл4s: links from both unknowns, accepted


def test_length_on_length_link_to_an_unknown_is_rejected_as_inertial() -> None:
    d = _data("harvester_finger_vectors")
    d["vector_model"]["vectors"]["BX"] = {"r": {"link": "AB", "plus": 0.01}, "alpha": 30}
    d["vector_model"]["contours"]["finger_link"]["sum"].append("BX")
    match = r"Пл1s\(AB\.r, AB\.alpha\): the length of BX is linked to .*length-on-length.*'inertial' model"
    with pytest.raises(SceneError, match=match):
        _load(d)


def test_a_cycle_of_links_is_rejected() -> None:
    d = _data("harvester_finger_vectors")
    v = d["vector_model"]["vectors"]
    v["AC"]["alpha"] = {"link": "AE"}
    v["AE"]["alpha"] = {"link": "AC"}
    with pytest.raises(SceneError, match=r"links form a cycle: AC\.alpha → AE\.alpha → AC\.alpha"):
        _load(d)


def test_two_solution_module_needs_M_and_one_solution_module_refuses_it() -> None:
    d = _data("four_bar_vectors")
    del d["vector_model"]["contours"]["dyad"]["M"]
    with pytest.raises(SceneError, match=r"Пл4\(AB\.alpha, CB\.alpha\) has two solutions: give the assembly mode M"):
        _load(d)
    d = _data("harvester_finger_vectors")
    d["vector_model"]["contours"]["finger_link"]["M"] = 1
    with pytest.raises(SceneError, match=r"Пл1\(AB\.r, AB\.alpha\) has one solution; remove M"):
        _load(d)


def test_unknown_that_no_contour_solves_is_rejected() -> None:
    d = _data("four_bar_vectors")
    d["vector_model"]["vectors"]["XY"] = {"r": "unknown", "alpha": 0}
    with pytest.raises(SceneError, match=r"no contour solves the unknown\(s\) XY\.r"):
        _load(d)


def test_only_an_angle_can_be_the_input() -> None:
    d = _data("four_bar_vectors")
    d["vector_model"]["vectors"]["OA"]["r"] = "input"
    with pytest.raises(SceneError, match=r"vectors\.OA\.r: only an angle can be the input"):
        _load(d)


def test_contour_naming_a_missing_vector_lists_the_vectors() -> None:
    d = _data("four_bar_vectors")
    d["vector_model"]["contours"]["dyad"]["sum"][1] = "AX"
    match = r"contours\.dyad\.sum: 'AX' is not a vector; vectors: \['AB', 'CB', 'OA', 'OC'\]"
    with pytest.raises(SceneError, match=match):
        _load(d)


def test_unassemblable_position_raises_an_assembly_error_naming_the_contour() -> None:
    d = _data("four_bar_vectors")
    d["vector_model"]["vectors"]["CB"]["r"] = 0.05
    scene = _load(d)
    with pytest.raises(AssemblyError, match=r"group 'dyad' cannot be assembled"):
        scene.solve(np.linspace(0.0, 2 * math.pi, 16))
    k = scene.solve(np.linspace(0.0, 2 * math.pi, 16), mask=True)
    assert not k.valid.all()


def test_vector_model_is_planar() -> None:
    d = _data("four_bar_vectors")
    d["fixed"] = {"O": [0, 0, 0], "C": [0.4, 0, 0]}
    with pytest.raises(SceneError, match=r"vector model is planar"):
        _load(d)


def test_internal_parameters_are_neither_points_nor_joints() -> None:
    s = solver.load_scene("harvester_finger_vectors")
    assert not [n for n in (*s.point_names, *s.joint_names) if n.endswith((".r", ".alpha", ".input"))]
    with pytest.raises(SceneError, match=r"unknown point 'AB\.r'"):
        s.with_outputs(points=["AB.r"])
