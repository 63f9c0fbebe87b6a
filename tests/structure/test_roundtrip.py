"""Every shipped group scene as a drawing (at a random input value) → the same groups and modes,
and the drawn scene solves bit-identically to its equivalent group scene written to a file."""

from __future__ import annotations

import math
import random

import numpy as np
import pytest

from solver import load_scene, shipped_scenes
from solver._loader import parse_scene
from solver._yaml import load_yaml
from solver.errors import SceneError
from solver.scene import Scene
from solver.structure import find_structure, scene_dict_from_drawing
from solver.structure_cli import drawing_of_scene, dump_scene, positions_at

#: The shipped scenes that have no drawn form, and why (docs/scenes.md, "The drawn form").
NOT_DRAWN = {
    "hard/parallelogram": "through_change_points: continuous",
    "hard/antiparallelogram": "through_change_points: continuous",
    "spherical_converter": "spatial",
    "four_bar_vectors": "vector-loop",
    "harvester_finger_vectors": "vector-loop",
}

SCENES = sorted(n for n in shipped_scenes() if not n.startswith("vectors/") and n not in NOT_DRAWN)


def _signature(scene: Scene) -> list[tuple[str, tuple[str, ...], int | None]]:
    """Each group's kind, the points it provides and its mode (joints aside), in a canonical order."""
    out = []
    for g in scene.ordered:
        if g.kind == "joint":
            continue
        points = tuple(sorted(n for n in g.provides() if n not in g.joints()))
        out.append((g.kind, points, getattr(g, "mode", None)))
    return sorted(out, key=str)


def _values(scene: Scene, rng: random.Random) -> list[float]:
    return [rng.uniform(0.0, 2.0 * math.pi) if r is None else rng.uniform(*r) for r in scene.input_ranges]


def _grid(scene: Scene, n: int = 64) -> np.ndarray:
    cols = []
    for r in scene.input_ranges:
        cols.append(np.linspace(0.0, 2.0 * math.pi, n) if r is None else np.linspace(r[0], r[1], n))
    return cols[0] if len(cols) == 1 else np.stack(cols, axis=1)


@pytest.mark.parametrize("name", SCENES)
def test_shipped_scene_round_trip(name: str, tmp_path) -> None:
    path = shipped_scenes()[name]
    scene = load_scene(path)
    rng = random.Random(f"drawn-{name}")
    values = _values(scene, rng)
    drawn = drawing_of_scene(path, values)
    # the drawing decomposes into the same groups and modes
    group_form = scene_dict_from_drawing(drawn, source=name)
    again = Scene(parse_scene(group_form, file=name))
    assert _signature(again) == _signature(scene)
    # the drawn pose is reproduced at its own input value, and the mechanism is the original one
    size = max(abs(z) for z in positions_at(scene, values).values())
    for p, z in positions_at(scene, values).items():
        assert abs(positions_at(again, values)[p] - z) <= 1e-12 * size, p
    # the drawn file and its group file (written, read back) solve bit-identically
    drawn_file = tmp_path / "drawn.yaml"
    drawn_file.write_text(dump_scene(drawn), encoding="utf-8")
    group_file = tmp_path / "groups.yaml"
    group_file.write_text(dump_scene(group_form), encoding="utf-8")
    a, b = load_scene(drawn_file).everything(), load_scene(group_file).everything()
    grid = _grid(scene)
    ka, kb = a.solve(grid, mask=True), b.solve(grid, mask=True)
    assert np.array_equal(ka.valid, kb.valid)
    for p in a.point_names:
        assert np.array_equal(ka.point(p).position, kb.point(p).position, equal_nan=True), p
        assert np.array_equal(ka.point(p).acceleration, kb.point(p).acceleration, equal_nan=True), p
    for j in a.joint_names:
        assert np.array_equal(ka.joint(j).velocity, kb.joint(j).velocity, equal_nan=True), j
    if scene.has_forces:  # the force layer sees the same bodies
        fa, fb = load_scene(drawn_file), load_scene(group_file)
        ea, eb = fa.solve(grid, mask=True), fb.solve(grid, mask=True)
        for inp in fa.inputs:
            assert np.array_equal(ea.effort(inp), eb.effort(inp), equal_nan=True)
        eo = scene.solve(grid, mask=True)
        ok = eo.valid & ea.valid
        for inp in scene.inputs:
            ref = np.asarray(eo.effort(inp))[ok]
            assert np.allclose(np.asarray(ea.effort(inp))[ok], ref, rtol=1e-9, atol=1e-9 * np.abs(ref).max())


@pytest.mark.parametrize("name", sorted(NOT_DRAWN))
def test_scenes_without_a_drawn_form_say_why(name: str) -> None:
    with pytest.raises(SceneError, match="continuous|spatial|vector-loop"):
        drawing_of_scene(shipped_scenes()[name], [0.3])


def test_the_shipped_drawn_example_matches_its_group_form() -> None:
    path = shipped_scenes()["crank_rocker_drawn"]
    raw = load_yaml(path)
    st = find_structure(raw, source=str(path))
    assert [s.kind for s in st.ordered] == ["crank", "rrr", "attached"]
    assert st.mobility.count == 1
    scene = load_scene(path)
    phi = st.inputs_drawn["crank"]
    k = scene.everything().solve(np.array([phi]))
    scale = raw["units"]["length"] == "mm" and 1e-3
    for p, xy in raw["drawing"]["points"].items():
        z = complex(*xy) * scale
        assert abs(complex(*k.point(p).position[0]) - z) <= 1e-12 * 0.2, p
