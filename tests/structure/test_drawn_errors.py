"""One SceneError line for every fault of a drawing, naming what to change (issue 31, item 6)."""

from __future__ import annotations

import random
import sys
import time
from pathlib import Path
from typing import Any

import pytest
import yaml

from solver import SceneError, load_scene
from solver.structure import scene_dict_from_drawing

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "fuzz"))
from scene_mutations import _data_mutation, _text_mutation, examine

FOUR_BAR: dict[str, Any] = {
    "points": {"O": [0, 0], "A": [30, 40], "B": [160, 120], "C": [200, 0]},
    "ground": ["O", "C"],
    "links": {"crank": ["O", "A"], "coupler": ["A", "B"], "rocker": ["C", "B"]},
    "inputs": ["crank"],
}


def scene(drawing: dict[str, Any], **more: Any) -> dict[str, Any]:
    return {"scene": "t", "units": {"length": "mm", "angle": "deg"}, "drawing": drawing,
            "outputs": {"points": [next(iter(drawing["points"]))]}, **more}


def refuse(drawing: dict[str, Any], match: str, **more: Any) -> str:
    with pytest.raises(SceneError, match=match) as info:
        scene_dict_from_drawing(scene(drawing, **more), source="t.yaml")
    text = str(info.value)
    assert "\n" not in text and text.startswith("t.yaml: ")
    return text


def with_(base: dict[str, Any], **changes: Any) -> dict[str, Any]:
    out = {k: (dict(v) if isinstance(v, dict) else v) for k, v in base.items()}
    out.update(changes)
    return out


def test_too_few_inputs_names_the_free_links() -> None:
    five = {"points": {"O1": [0, 0], "O2": [200, 0], "A1": [0, 150], "A2": [200, 150], "P": [100, 300]},
            "ground": ["O1", "O2"],
            "links": {"left": ["O1", "A1"], "right": ["O2", "A2"], "l1": ["A1", "P"], "l2": ["A2", "P"]},
            "inputs": ["left"]}
    refuse(five, r"mobility F = 3\(n − 1\) − 2j₁ − j₂ = 3·4 − 2·5 − 0 = 2 with 1 input\(s\) \(left\) does not match: "
                 r"l1, l2, right free \(sub-chain count \+1\): add an input or a link")


def test_too_many_inputs_names_the_over_constrained_link() -> None:
    refuse(with_(FOUR_BAR, inputs=["crank", "rocker"]),
           r"drawing.inputs: mobility .* = 1 with 2 input\(s\) \(crank, rocker\) does not match: coupler \[A, B\] has "
           r"A, B placed by other groups: over-constrained \(-1\)")


def test_an_extra_link_over_constrains() -> None:
    d = with_(FOUR_BAR)
    d["links"] = {**FOUR_BAR["links"], "brace": ["A", "C"]}
    refuse(d, r"= 0 with 1 input\(s\) \(crank\) does not match: brace \[A, C\] has A, C placed by other groups: "
              r"over-constrained \(-1\)")


def test_a_dyad_kind_without_a_group_is_named() -> None:
    rrp_moving = {"points": {"O": [0, 0], "A": [40, 0], "G": [120, 30], "C": [60, 90], "B": [80, 15]},
                  "ground": ["O", "C"], "links": {"crank": ["O", "A", "G"], "rod": ["C", "B"]}, "inputs": ["crank"],
                  "slides": {"block": {"point": "B", "on": "crank", "along": ["A", "G"]}}}
    refuse(rrp_moving, r"= 1 with 1 input\(s\) \(crank\) matches: rod, block form a dyad of a kind with no group yet "
                       r"\(a slide on a moving line whose block is pinned to a link not yet placed")


def test_a_point_on_no_link() -> None:
    d = with_(FOUR_BAR)
    d["points"] = {**FOUR_BAR["points"], "X": [5, 5]}
    refuse(d, r"t.yaml: drawing.points: 'X' is on no link: add it to a link \(or to ground\), or drop it")


def test_a_link_with_fewer_than_two_points() -> None:
    d = with_(FOUR_BAR)
    d["links"] = {**FOUR_BAR["links"], "stub": ["B"]}
    refuse(d, r"drawing.links.stub: a link joins at least two points, got \['B'\]")


def test_disconnected_parts() -> None:
    d = with_(FOUR_BAR)
    d["points"] = {**FOUR_BAR["points"], "X": [5, 5], "Y": [9, 9], "Z": [20, 3]}
    d["links"] = {**FOUR_BAR["links"], "a": ["X", "Y"], "b": ["Y", "Z"]}
    refuse(d, r"disconnected parts: a, b share no pin or slide with the ground's part")


def test_a_dyad_drawn_at_its_toggle() -> None:
    d = with_(FOUR_BAR)
    d["points"] = {"O": [0, 0], "A": [30, 0], "B": [120, 0], "C": [200, 0]}
    refuse(d, r"drawing.links.rocker: the dyad coupler–rocker is drawn at its toggle \(A, B, C in a line\): its "
              r"assembly mode is undefined there")


def test_a_slide_point_off_its_line() -> None:
    d = {"points": {"O": [0, 0], "A": [30, 40], "B": [150, 12], "G1": [-50, 10], "G2": [250, 10]},
         "ground": ["O", "G1", "G2"], "links": {"crank": ["O", "A"], "rod": ["A", "B"]}, "inputs": ["crank"],
         "slides": {"piston": {"point": "B", "on": "ground", "along": ["G1", "G2"]}}}
    refuse(d, r"drawing.slides.piston.point: B is drawn 2 off the line G1–G2 it slides on: move it onto the line "
              r"\(to \[150, 10\]\)")


def test_an_input_not_pinned_to_the_ground_first() -> None:
    refuse(with_(FOUR_BAR, inputs=["coupler"]), r"drawing.inputs\[0\].link: an input link is pinned to the ground at "
                                                 r"its first point; 'A' of coupler \[A, B\] is not a ground point")


def test_a_coupled_input_is_a_coupled_crank() -> None:
    """The drawn coupled input loads as the solver's coupled crank (issue 31, solver.groups.crank):
    the right crank turns by −1 times the left's angle, from its drawn angle."""
    import math

    from solver._loader import parse_scene
    from solver.scene import Scene

    five = {"points": {"O1": [0, 0], "O2": [200, 0], "A1": [0, 150], "A2": [200, 150], "P": [100, 300]},
            "ground": ["O1", "O2"],
            "links": {"left": ["O1", "A1"], "right": ["O2", "A2"], "l1": ["A1", "P"], "l2": ["A2", "P"]},
            "inputs": ["left", {"link": "right", "follows": "left", "ratio": -1}]}
    drawn = scene(five, outputs={"points": ["P"]})
    s = Scene(parse_scene(scene_dict_from_drawing(drawn, source="t.yaml"), file="t.yaml"))
    assert s.inputs == ("left",)
    k = s.solve(math.pi / 2)  # the drawn pose
    assert k.point("P").position == pytest.approx((0.1, 0.3), abs=1e-15)


def test_a_drawn_scene_names_no_fixed_or_groups() -> None:
    with pytest.raises(SceneError, match="a drawn scene has no 'groups'"):
        scene_dict_from_drawing({**scene(FOUR_BAR), "groups": []}, source="t.yaml")


def test_the_file_and_line_are_named(tmp_path: Path) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text("scene: bad\nunits: {length: mm, angle: deg}\ndrawing:\n  points: {O: [0, 0], A: [1, 1]}\n"
                    "  ground: [O]\n  links:\n    crank: [O, A]\n    stub: [A]\n  inputs: [crank]\n"
                    "outputs: {points: [A]}\n", encoding="utf-8")
    with pytest.raises(SceneError, match=r"bad.yaml:8: drawing.links.stub: a link joins at least two points"):
        load_scene(path)


def test_mutated_drawn_scenes_load_or_fail_in_one_line(tmp_path: Path) -> None:
    """The suite's scene fuzzer on the drawn example: nothing but one SceneError line escapes."""
    text = (Path(__file__).resolve().parents[2] / "config" / "scenes" / "crank_rocker_drawn.yaml").read_text()
    rng = random.Random(31)
    start, done, problems = time.monotonic(), 0, []
    while done < 40 or (done < 300 and time.monotonic() - start < 10.0):
        if rng.random() < 0.7:
            label, data = _data_mutation(yaml.safe_load(text), rng)
            raw = yaml.safe_dump(data, sort_keys=False, allow_unicode=True).encode()
        else:
            label, raw = _text_mutation(text, rng)
        path = tmp_path / f"m{done}.yaml"
        path.write_bytes(raw)
        r = examine(path, cli=False)
        if r["outcome"] == "traceback" or r["multiline"] or r["nonfinite"]:
            problems.append(f"{label}: {r['outcome']} {r['message'][-400:]}")
        done += 1
    assert not problems, "\n".join(problems[:5])
