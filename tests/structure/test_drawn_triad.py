"""A drawn class-3 group becomes a ``triad`` (solver.structure.triad_step), its mode read off the pose."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scene_builders import build

from solver.errors import SceneError
from solver.structure import scene_dict_from_drawing

TRIAD = {
    "scene": "drawn_triad", "units": {"length": "mm", "angle": "deg"},
    "drawing": {"points": {"O": [0, 0], "A": [20, 30], "B": [80, 90], "D": [140, 60], "E": [100, 20],
                           "F": [200, 80], "G": [150, -40]},
                "ground": ["O", "F", "G"],
                "links": {"crank": ["O", "A"], "l1": ["A", "B"], "ternary": ["B", "D", "E"], "l2": ["F", "D"],
                          "l3": ["G", "E"]},
                "inputs": ["crank"]},
    "outputs": {"points": ["A", "B", "D", "E"]},
}
ROUND_OFF = 1e-12  # of the drawing's size (m)


def test_the_drawn_triad_is_found_and_solves_back_to_its_pose() -> None:
    data = scene_dict_from_drawing(TRIAD)
    kinds = [g["type"] for g in data["groups"]]
    assert kinds == ["crank", "triad"]
    tri = data["groups"][1]
    assert tri["ends"] == ["A", "F", "G"] and tri["points"] == ["B", "D", "E"]
    assert tri["angle"] == pytest.approx(math.degrees(math.atan2(60 - 90, 140 - 80)), abs=1e-12)  # arg(D − B)
    scene = build(data)
    phi0 = math.atan2(30, 20)
    k = scene.solve(np.array([phi0 - 0.2, phi0, phi0 + 0.2]))  # the reference sample is the drawn input
    size = 0.25
    for name in ("B", "D", "E"):
        drawn = np.array(TRIAD["drawing"]["points"][name]) / 1000.0  # type: ignore[index]
        assert np.abs(k.point(name).position[1] - drawn).max() <= ROUND_OFF * size


def test_a_triad_drawn_at_a_dead_point_is_refused() -> None:
    """The three binary links' lines meet in one point P = (110, 300): two modes merge there."""
    bad = copy.deepcopy(TRIAD)
    pts = bad["drawing"]["points"]  # type: ignore[index]
    pts.update({"A": [71.0, 27.0], "F": [155.0, -60.0], "G": [95.0, -120.0]})
    with pytest.raises(SceneError, match=r"the triad l1, l2, l3, ternary is drawn at a dead point"):
        scene_dict_from_drawing(bad)
