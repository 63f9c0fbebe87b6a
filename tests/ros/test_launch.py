"""launch/mechanism.launch.py and config/params.yaml."""

from __future__ import annotations

import ast
from pathlib import Path

import pytest
import yaml

from linkage_ros.parameters import PARAMETERS, validate_parameter

ROOT = Path(__file__).resolve().parents[2]
LAUNCH = ROOT / "launch" / "mechanism.launch.py"
PARAMS = ROOT / "config" / "params.yaml"
LAUNCH_ARGUMENTS = {"scene", "omega", "epsilon", "rate_hz"}


def test_launch_file_parses_and_declares_the_four_arguments() -> None:
    tree = ast.parse(LAUNCH.read_text(encoding="utf-8"), filename=str(LAUNCH))
    functions = {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    assert "generate_launch_description" in functions
    arguments = next(
        n.value for n in tree.body
        if isinstance(n, ast.Assign) and any(getattr(t, "id", "") == "ARGUMENTS" for t in n.targets)
    )
    assert {ast.literal_eval(k) for k in arguments.keys} == LAUNCH_ARGUMENTS  # type: ignore[attr-defined]


def test_params_file_is_in_ros_parameters_form_with_valid_values() -> None:
    data = yaml.safe_load(PARAMS.read_text(encoding="utf-8"))
    params = data["/**"]["ros__parameters"]
    names = {spec.name for spec in PARAMETERS}
    assert set(params) <= names and names - set(params) <= {"points"}  # points follows the scene
    for name, value in params.items():
        assert validate_parameter(name, value) is None, name


def test_launch_arguments_default_to_the_values_of_params_yaml() -> None:
    tree = ast.parse(LAUNCH.read_text(encoding="utf-8"), filename=str(LAUNCH))
    arguments = next(
        n.value for n in tree.body
        if isinstance(n, ast.Assign) and any(getattr(t, "id", "") == "ARGUMENTS" for t in n.targets)
    )
    defaults = {name: default for name, (default, _) in ast.literal_eval(arguments).items()}
    params = yaml.safe_load(PARAMS.read_text(encoding="utf-8"))["/**"]["ros__parameters"]
    assert {name: yaml.safe_load(text) for name, text in defaults.items()} == {n: params[n] for n in defaults}


def test_launch_description_builds_with_ros_launch() -> None:
    pytest.importorskip("launch_ros", reason="launch_ros is only available in a ROS 2 Jazzy workspace")
    from launch.launch_description_sources import get_launch_description_from_python_launch_file

    description = get_launch_description_from_python_launch_file(str(LAUNCH))
    declared = {e.name for e in description.entities if type(e).__name__ == "DeclareLaunchArgument"}
    assert declared == LAUNCH_ARGUMENTS
