"""What a shipped scene tells its user (provenance, descriptions) is about the mechanism, and true."""

from __future__ import annotations

import math
import re
from pathlib import Path

import pytest

import solver
from solver import assembly

SCENES = sorted(
    str(p.relative_to(Path(solver.find_scene("four_bar")).parent).with_suffix(""))
    for p in Path(solver.find_scene("four_bar")).parent.rglob("*.yaml")
)


@pytest.mark.parametrize("name", SCENES)
def test_scene_texts_describe_the_mechanism_not_the_projects_issues(name: str) -> None:
    text = Path(solver.find_scene(name)).read_text(encoding="utf-8")
    assert not re.search(r"\bissue\s*#?\d+|\bthe issue\b", text, re.IGNORECASE), name


def test_the_double_rockers_stated_gap_is_the_solvers() -> None:
    scene = solver.load_scene("hard/double_rocker")
    ((lo, hi),) = assembly.gaps(scene)["dyad"]
    bound = math.degrees(math.acos(-0.40625))
    assert math.degrees(lo) == pytest.approx(bound, abs=1e-12)
    assert math.degrees(hi) == pytest.approx(360.0 - bound, abs=1e-12)
    stated = f"φ in ({math.degrees(lo):.4f}°, {math.degrees(hi):.4f}°)"
    assert stated == "φ in (113.9695°, 246.0305°)"
    assert stated in " ".join(scene.provenance.split())


@pytest.mark.parametrize("name", ["five_bar", "gripper_finger"])
def test_several_input_and_urdf_scenes_describe_every_output(name: str) -> None:
    scene = solver.load_scene(name)
    for output in (*scene.output_points, *scene.output_joints):
        assert scene.descriptions.get(output), output


def _field_table() -> dict[str, set[str]]:
    """docs/scenes.md's table of group fields: {type: {field, …}} (``guide.angle`` as ``guide``)."""
    text = (Path(__file__).resolve().parents[2] / "docs" / "scenes.md").read_text(encoding="utf-8")
    table: dict[str, set[str]] = {}
    kind = ""
    for line in text.splitlines():
        row = line.replace("\\|", "¦")  # an escaped pipe inside a cell
        cells = [c.strip() for c in row.strip().strip("|").split("|")] if line.startswith("| ") else []
        if len(cells) == 5 and cells[1].startswith("`"):
            kind = cells[0].strip("`") or kind
            table.setdefault(kind, set()).add(cells[1].strip("`").split(".")[0])
    return table


def test_the_scene_docs_table_lists_every_group_type_and_every_field_the_shipped_scenes_use() -> None:
    from solver._yaml import load_yaml
    from solver.groups import GROUP_TYPES

    table = _field_table()
    assert set(table) == set(GROUP_TYPES)
    assert "angle" in table["attached"]
    for name in SCENES:
        data = load_yaml(solver.find_scene(name))
        for group in data.get("groups") or []:
            used = set(group) - {"type", "name"}
            assert used <= table[group["type"]], (name, group["type"], used - table[group["type"]])
