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


FOUR_BAR = Path(solver.find_scene("four_bar")).read_text(encoding="utf-8")


def _load_text(tmp_path: Path, text: str | bytes) -> solver.Scene:
    path = tmp_path / "bad.yaml"
    if isinstance(text, bytes):
        path.write_bytes(text)
    else:
        path.write_text(text, encoding="utf-8")
    return solver.load_scene(path)


@pytest.mark.parametrize(
    ("old", "new", "message"),
    [
        ("M: +1}", "M: +1, M: -1}", r"bad\.yaml:12: refused: duplicate key 'M' \(first given on line 12\)"),
        ("  C: [0.4, 0.0]\n", "  C: [0.4, 0.0]\n  C: [0.5, 0.0]\n", r"bad\.yaml:10: refused: duplicate key 'C'"),
        ("length: 0.1}", "length: 1e-3}", r"groups\[0\]\.length: must be a number, got the text '1e-3'.*write 1\.0e-3"),
        ("lengths:", "lenghts:", r"bad\.yaml:12: groups\[1\]: unknown field 'lenghts' \(did you mean 'lengths'\?\)"),
        ("groups:", "gropus:", r"bad\.yaml:10: unknown field 'gropus' \(did you mean 'groups'\?\)"),
        ("joints:\n", "joint:\n", r"unknown field 'joint' \(did you mean 'joints'\?\)"),
        (
            "[0.4, 0.3]",
            "[1.0e+154, 0.3]",
            r"groups\[1\]\.lengths\.AB: length 1e\+154 is 1e\+154 m, outside 1e-09 … 1e\+09 m",
        ),
        ("[0.4, 0.3]", "[1.0e+200, 1.0e+200]", r"lengths\.AB: length 1e\+200"),
        ("length: 0.1}", f"length: {10**29}}}", r"groups\[0\]\.length: length 1e\+29 is 1e\+29 m, outside"),
        ("length: 0.1}", "length: 1.0e-10}", r"length 1e-10 is 1e-10 m, outside 1e-09 … 1e\+09 m"),
        ("C: [0.4, 0.0]", f"C: [{10**29}, 0.0]", r"fixed\.C: 1e\+29 is 1e\+29 m, beyond ±1e\+09 m"),
        ("length: 0.1}", "length: " + "9" * 5000 + "}", r"a value that cannot be read \(an integer of more than"),
        ("type: rrr,", "type: rrr, colour: red,", r"groups\[1\]: unknown field\(s\): colour"),
        ("point: B", "point: " + "B" * 500, r"groups\[1\]\.point: a name of 500 characters: at most 100"),
        ("  B: joint of", "  Q: joint of", r"descriptions\.Q: 'Q' is not a point or joint of the scene"),
        (
            "  B: joint of coupler AB and rocker CB",
            "  B: [1, 2]",
            r"descriptions\.B: must be a one-line text, got \[1, 2\]",
        ),
    ],
)
def test_bad_scene_text_is_one_scene_error_line_naming_file_line_entry_and_fault(
    tmp_path: Path, old: str, new: str, message: str
) -> None:
    assert old in FOUR_BAR
    with pytest.raises(solver.SceneError, match=message) as err:
        _load_text(tmp_path, FOUR_BAR.replace(old, new, 1))
    assert "\n" not in str(err.value) and len(str(err.value)) < 600


@pytest.mark.parametrize("section", ["groups:\n", "groups: 7\n", "groups: []\n"])
def test_empty_or_odd_groups_section_is_a_scene_error(tmp_path: Path, section: str) -> None:
    text = FOUR_BAR[: FOUR_BAR.index("groups:")] + section + FOUR_BAR[FOUR_BAR.index("joints:") :]
    with pytest.raises(
        solver.SceneError, match=r"groups: (is empty|must be a list of groups, got 7|name at least one)"
    ):
        _load_text(tmp_path, text)


BOMB = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n" + "".join(
    f"a{i}: &a{i} [{', '.join([f'*a{i - 1}'] * 10)}]\n" for i in range(1, 9)
)


@pytest.mark.parametrize(
    ("text", "message"),
    [
        (BOMB + FOUR_BAR.replace("{length: m, angle: deg}", "*a8"), r"more than 1,000,000 values once its aliases"),
        (BOMB + FOUR_BAR.replace("scene: four_bar", "scene: *a8"), r"more than 1,000,000 values once its aliases"),
        (BOMB + FOUR_BAR.replace("provenance: >-", "provenance: *a8\nxx: >-"), r"more than 1,000,000 values"),
        ("a: &a [*a]\n" + FOUR_BAR, r"bad\.yaml:1: refused: an alias refers to a node that contains it"),
        (FOUR_BAR + "description: " + "[" * 100_000 + "]" * 100_000 + "\n", r"nested more than 64 levels deep"),
        (FOUR_BAR + "description: " + "{a: " * 20_000 + "1" + "}" * 20_000 + "\n", r"nested more than 64 levels"),
        (FOUR_BAR.replace("O–A", "O-A").encode("utf-8").replace(b"four_bar", b"four_b\xe4r", 1), r"not UTF-8 text"),
        (bytes(range(256)) * 64, r"bad\.yaml:1: a binary file \(a NUL byte\), not YAML text"),
        (b"a: " + b"x" * (5 << 20), r"bad\.yaml: larger than 4 MiB: not a scene file"),
        ("", r"bad\.yaml: the file is empty"),
        ("groups: [unclosed\nunits: {}\n", r"bad\.yaml:2: not valid YAML: .*while parsing a flow sequence on line 1"),
    ],
)
def test_bombs_deep_nesting_odd_bytes_and_huge_files_are_refused_at_once(
    tmp_path: Path, text: str | bytes, message: str
) -> None:
    with pytest.raises(solver.SceneError, match=message) as err:
        _load_text(tmp_path, text)
    assert "\n" not in str(err.value)


def test_a_misspelt_key_is_reported_before_what_its_absence_breaks(tmp_path: Path) -> None:
    # without `lengths` the dyad would fail on a missing field: the typo is the fault named
    with pytest.raises(solver.SceneError, match=r"unknown field 'lenghts' \(did you mean 'lengths'\?\)"):
        _load_text(tmp_path, FOUR_BAR.replace("lengths:", "lenghts:").replace("M: +1", "M: 7"))
    misspelt_unit = r"bad\.yaml:6: units: unknown field 'lenght' \(did you mean 'length'\?\)"
    with pytest.raises(solver.SceneError, match=misspelt_unit):
        _load_text(tmp_path, FOUR_BAR.replace("{length: m,", "{lenght: m,"))


def test_parallel_slides_of_a_vector_loop_are_refused_on_load(tmp_path: Path) -> None:
    yoke = Path(solver.find_scene("vectors/pl2_scotch_yoke")).read_text(encoding="utf-8")
    text = yoke.replace("YA: {r: unknown, alpha: 90}", "YA: {r: unknown, alpha: 0}")
    with pytest.raises(solver.SceneError, match=r"contours\.yoke: Пл2\(OY\.r, YA\.r\): the two unknown lengths slide"):
        _load_text(tmp_path, text)


def test_an_angle_between_two_fixed_points_at_one_place_is_refused(tmp_path: Path) -> None:
    text = FOUR_BAR.replace("  C: [0.4, 0.0]\n", "  C: [0.4, 0.0]\n  P: [0.0, 0.0]\n").replace(
        "  rocker: {angle: [C, B]}\n", "  rocker: {angle: [C, B]}\n  zero: {angle: [O, P]}\n"
    )
    with pytest.raises(solver.SceneError, match=r"joint 'zero': angle of \[O, P\], two fixed points at one place"):
        _load_text(tmp_path, text)


def test_every_shipped_scene_describes_its_outputs() -> None:
    for name in solver.shipped_scenes():
        if name in ("five_bar", "gripper_finger"):  # other helpers' new scenes
            continue
        scene = solver.load_scene(name)
        missing = [n for n in (*scene.output_points, *scene.output_joints) if n not in scene.descriptions]
        assert not missing, (name, missing)


def test_a_merge_key_may_be_overridden_without_a_duplicate_key_error(tmp_path: Path) -> None:
    text = FOUR_BAR.replace("{type: rrr, name: dyad,", "{<<: {M: -1, point: B}, type: rrr, name: dyad,")
    scene = _load_text(tmp_path, text)
    assert scene.solve(1.0).point("B").position == pytest.approx(
        solver.load_scene("four_bar").solve(1.0).point("B").position
    )


def test_a_dyad_between_fixed_points_is_refused_on_load(tmp_path: Path) -> None:
    text = FOUR_BAR.replace("  C: [0.4, 0.0]\n", "  C: [0.4, 0.0]\n  F: [5.0, 0.0]\n").replace(
        "groups:\n", "groups:\n  - {type: rrr, name: tri, ends: [O, F], point: T, lengths: [0.4, 0.3], M: +1}\n"
    )
    with pytest.raises(solver.SceneError, match=r"rrr 'tri' reads only fixed points \(O, F\): it does not move"):
        _load_text(tmp_path, text)


@pytest.mark.parametrize("collecting", [True, False])
def test_reading_a_scene_leaves_the_garbage_collector_as_it_found_it(collecting: bool) -> None:
    import gc

    from solver._yaml import parse_yaml

    was = gc.isenabled()
    try:
        (gc.enable if collecting else gc.disable)()
        assert parse_yaml("a: [1, 2]") == {"a": [1, 2]}
        assert gc.isenabled() is collecting
        with pytest.raises(solver.SceneError, match="not valid YAML"):
            parse_yaml("a: [1\n")
        assert gc.isenabled() is collecting
    finally:
        (gc.enable if was else gc.disable)()
