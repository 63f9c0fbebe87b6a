"""A drawn triad with one prismatic pair becomes a ``slider_triad``
(solver.structure.slider_triad_step), its mode read off the pose; the shipped example's drawing
goes back to the same group."""

from __future__ import annotations

import copy
import math

import numpy as np
import pytest
from scene_builders import build

from solver.errors import SceneError
from solver.structure import scene_dict_from_drawing

#: the shipped slider_triad_press drawn at φ = 0, in mm
DRAWN = {
    "scene": "drawn_slider_triad", "units": {"length": "mm", "angle": "deg"},
    "drawing": {"points": {"O": [0, 0], "B": [100, 0], "C": [390, 500], "G": [-450, -490], "H": [-450, 0],
                           "D": [-450, -800], "E": [-390, 90], "F": [-60, 300]},
                "ground": ["O", "C", "G", "H"],
                "links": {"crank": ["O", "B"], "plate": ["D", "E", "F"], "arm_b": ["B", "E"], "arm_c": ["C", "F"]},
                "slides": {"ram": {"point": "D", "on": "ground", "along": ["G", "H"], "joint": "stroke"}},
                "inputs": ["crank"]},
    "outputs": {"points": ["B", "D", "E", "F"], "joints": ["stroke"]},
}
ROUND_OFF = 1e-12  # of the drawing's size (m)


def test_the_drawn_slider_triad_is_found_and_solves_back_to_its_pose() -> None:
    data = scene_dict_from_drawing(DRAWN)
    kinds = [g["type"] for g in data["groups"]]
    assert kinds == ["crank", "slider_triad"]
    tri = data["groups"][1]
    assert tri["ends"] == ["B", "C"] and tri["points"] == ["D", "E", "F"]
    assert tri["guide"] == {"through": "G", "angle": pytest.approx(90.0, abs=1e-12)}
    assert tri["slide"] == "stroke" and tri["at"] == 0.0
    assert tri["angle"] == pytest.approx(math.degrees(math.atan2(890, 60)), abs=1e-12)  # arg(E − D)
    scene = build(data)
    k = scene.solve(np.array([-0.2, 0.0, 0.2]))  # the reference sample is the drawn input
    size = 1.3
    for name in ("D", "E", "F"):
        drawn = np.array(DRAWN["drawing"]["points"][name]) / 1000.0  # type: ignore[index]
        assert np.abs(k.point(name).position[1] - drawn).max() <= ROUND_OFF * size
    assert abs(k.joint("stroke").position[1] - (-0.31)) <= ROUND_OFF * size  # D from G along the guide
    # the same motion as the shipped group scene
    import solver
    shipped = solver.load_scene("slider_triad_press").solve(np.array([-0.2, 0.0, 0.2]))
    np.testing.assert_allclose(k.point("E").position, shipped.point("E").position, rtol=0, atol=1e-12)


def test_a_slide_point_off_its_line_is_refused() -> None:
    bad = copy.deepcopy(DRAWN)
    bad["drawing"]["points"]["D"] = [-449.0, -800]  # type: ignore[index]
    with pytest.raises(SceneError, match=r"D is drawn 1 off the line G–H it slides on"):
        scene_dict_from_drawing(bad)


def test_a_slider_triad_drawn_at_a_dead_point_is_refused() -> None:
    """The binary links' lines and the guide's normal at D meet in one point: E and F moved onto
    lines through P = (0, −800) on the normal at D, B and C kept on them."""
    bad = copy.deepcopy(DRAWN)
    pts = bad["drawing"]["points"]  # type: ignore[index]
    p = complex(0, -800)
    b, c = complex(100, 0), complex(390, 500)
    e, f = p + 0.5 * (b - p), p + 0.6 * (c - p)  # on the lines P–B and P–C
    pts.update({"E": [e.real, e.imag], "F": [f.real, f.imag]})
    with pytest.raises(SceneError, match=r"the slider triad ram, arm_b, arm_c, plate is drawn at a dead point"):
        scene_dict_from_drawing(bad)


def _swinging() -> dict:
    """The drawing with the ram replaced by a swinging block: A fixed on the line D–E of the plate."""
    other = copy.deepcopy(DRAWN)
    d = other["drawing"]  # type: ignore[index]
    d["points"]["A"] = [-417, -310.5]  # D + 0.55·(E − D)
    d["ground"] = ["O", "C", "A"]
    del d["points"]["G"], d["points"]["H"]
    d["slides"] = {"swivel": {"point": "A", "on": "plate", "along": ["D", "E"], "joint": "stroke"}}
    return other


@pytest.mark.parametrize("kind", ["swinging", "carried"])
def test_the_other_variants_are_found_and_solve_back_to_their_pose(kind: str) -> None:
    """The swinging block (a fixed A sliding along the plate's line D–E) and the guide on a moving
    link (D sliding along the crank's line O–B) become ``slider_triad`` groups (``block_at`` /
    ``guide: {on}``) that solve back to the drawn pose."""
    if kind == "swinging":
        drawing = _swinging()
    else:
        drawing = copy.deepcopy(DRAWN)
        d = drawing["drawing"]  # type: ignore[index]
        d["points"]["D"] = [200, 0]  # on the crank's line
        d["slides"] = {"ram": {"point": "D", "on": "crank", "along": ["O", "B"], "joint": "stroke"}}
        d["ground"] = ["O", "C"]
        del d["points"]["G"], d["points"]["H"]
    data = scene_dict_from_drawing(drawing)
    assert [g["type"] for g in data["groups"]] == ["crank", "slider_triad"]
    tri = data["groups"][1]
    if kind == "swinging":
        assert tri["block_at"] == "A" and tri["guide"]["offset"] == pytest.approx(0.0, abs=1e-9)
        assert tri["guide"]["angle"] == pytest.approx(0.0, abs=1e-9)  # the line D–E: along D→E
    else:
        assert tri["guide"] == {"on": ["O", "B"]}
    scene = build(data)
    k = scene.solve(np.linspace(-0.2, 0.2, 41))
    size = 1.3
    for name in ("D", "E", "F"):
        drawn = np.array(drawing["drawing"]["points"][name]) / 1000.0  # type: ignore[index]
        assert np.abs(k.point(name).position[20] - drawn).max() <= ROUND_OFF * size
    assert k.conditioning["plate"].min() > 0.05


def test_a_swinging_block_off_its_line_is_refused_in_one_line() -> None:
    bad = _swinging()
    bad["drawing"]["points"]["A"] = [-450, -300]  # type: ignore[index]
    with pytest.raises(SceneError, match=r"A is drawn 33\.6 off the line D–E it slides on") as err:
        scene_dict_from_drawing(bad)
    assert "\n" not in str(err.value)
