"""Bad ``friction:`` keys are one SceneError line naming the key and the reason."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest
import yaml

import solver

ROOT = Path(__file__).resolve().parents[2]
BASE: dict[str, Any] = yaml.safe_load((ROOT / "tests/forces/scenes/friction_slider_crank.yaml").read_text("utf-8"))


def _load(tmp_path: Path, friction: Any) -> solver.Scene:
    data = copy.deepcopy(BASE)
    data["friction"] = friction
    path = tmp_path / "bad.yaml"
    path.write_text(yaml.safe_dump(data, sort_keys=False), encoding="utf-8")
    return solver.load_scene(path)


@pytest.mark.parametrize(("friction", "match"), [
    ({"pins": {"Q": {"mu": 0.1, "radius": 0.01}}}, r"friction\.pins\.Q.*no pin at 'Q'; pins: O, A, B"),
    ({"pins": {"O": {"mu": -0.1, "radius": 0.01}}}, r"friction\.pins\.O\.mu.*must not be negative, got -0\.1"),
    ({"pins": {"O": {"mu": 0.1, "radius": -0.01}}}, r"friction\.pins\.O\.radius.*must not be negative"),
    ({"pins": {"O": {"mu": 0.1, "radus": 0.01}}}, r"unknown field 'radus' \(did you mean 'radius'\?\)"),
    ({"pins": {"O": {"mu": "x", "radius": 0.01}}}, r"friction\.pins\.O\.mu.*must be a number"),
    ({"all_pins": {"mu": 20.0, "radius": 0.01}}, r"friction\.all_pins\.mu.*at most 10"),
    ({"slides": {"pistn": {"mu": 0.1}}}, r"unknown slider block 'pistn' \(did you mean 'piston'\?\); blocks: piston"),
    ({"slides": {"piston": {"mu": -1}}}, r"friction\.slides\.piston\.mu.*must not be negative"),
    ({"actuators": {"lift": {"force": 10.0}}}, r"unknown actuator 'lift'; actuators: none"),
    ({"pinz": {}}, r"unknown field 'pinz' \(did you mean 'pins'\?\)"),
    ([1, 2], r"friction.*must map pins, all_pins, slides, actuators"),
    ({"pins": [1]}, r"friction\.pins.*must map names to their friction"),
])
def test_bad_friction_is_one_line(tmp_path: Path, friction: Any, match: str) -> None:
    with pytest.raises(solver.SceneError, match=match) as info:
        _load(tmp_path, friction)
    assert "\n" not in str(info.value)


def test_zero_friction_is_the_ideal_mechanism(tmp_path: Path) -> None:
    """μ = 0 everywhere: no friction elements; the efforts are the ideal ones to the bit."""
    scene = _load(tmp_path, {"all_pins": {"mu": 0.0, "radius": 0.01}, "slides": {"piston": {"mu": 0.0}}})
    ideal = copy.deepcopy(BASE)
    del ideal["friction"]
    path = tmp_path / "ideal.yaml"
    path.write_text(yaml.safe_dump(ideal, sort_keys=False), encoding="utf-8")
    plain = solver.load_scene(path)
    assert scene.solve(0.3, omega=5.0, epsilon=1.0).effort("crank") == plain.solve(0.3, omega=5.0,
                                                                                    epsilon=1.0).effort("crank")
