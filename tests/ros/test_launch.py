"""launch/mechanism.launch.py (every node parameter a launch argument, issue 30) and
config/params.yaml.

launch and launch_ros are not on PyPI: the launch file is run against the stand-ins of
tests/launch_stubs.py (as tests/relay/test_relay_launch.py does); under a Jazzy workspace the last
test loads it with the real packages."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import launch_stubs
import pytest
import yaml
from launch_stubs import LaunchCtx, Recorded

from linkage_ros.parameters import PARAMETERS, validate_parameter

ROOT = Path(__file__).resolve().parents[2]
LAUNCH = ROOT / "launch" / "mechanism.launch.py"
PARAMS = ROOT / "config" / "params.yaml"
NAMES = {spec.name for spec in PARAMETERS}


def _load(monkeypatch: pytest.MonkeyPatch) -> Any:
    launch_stubs.install(monkeypatch, ROOT)
    spec = importlib.util.spec_from_file_location("mechanism_launch", LAUNCH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _node(mod: Any, **values: str) -> dict[str, Any]:
    args = {name: default for name, (default, _) in mod.ARGUMENTS.items()}
    args.update(values)
    (node,) = mod._nodes(LaunchCtx(args))
    return node.kwargs  # type: ignore[no-any-return]


def test_every_node_parameter_is_a_launch_argument(monkeypatch: pytest.MonkeyPatch) -> None:
    mod = _load(monkeypatch)
    description = mod.generate_launch_description()
    declared = {a.args[0] for a in description.args[0] if isinstance(a, Recorded) and a.args}
    assert declared == NAMES | {"params_file"}
    assert _node(mod)["parameters"] == []  # nothing given: the node's own defaults


def test_given_arguments_reach_the_node_typed(monkeypatch: pytest.MonkeyPatch) -> None:
    mod = _load(monkeypatch)
    node = _node(mod, scene="excavator", input_source="topic", rate_hz="200",
                 input_joints="[boom_cylinder_rod_joint, arm_cylinder_rod_joint, bucket_cylinder_rod_joint]",
                 input_omegas="[0.1, -0.1, 0]", mode="kinematic", params_file=str(PARAMS))
    assert node["executable"] == "mechanism_node"
    file, given = node["parameters"]
    assert file == str(PARAMS) and given == {
        "scene": "excavator", "input_source": "topic", "rate_hz": 200.0, "mode": "kinematic",
        "input_joints": ["boom_cylinder_rod_joint", "arm_cylinder_rod_joint", "bucket_cylinder_rod_joint"],
        "input_omegas": [0.1, -0.1, 0.0]}
    for name, value in given.items():
        assert validate_parameter(name, value) is None, name
    with pytest.raises(ValueError, match="launch argument omega must be a number, got 'fast'"):
        _node(mod, omega="fast")
    with pytest.raises(ValueError, match="launch argument input_phi0s must be a list of numbers"):
        _node(mod, input_phi0s="[a, b]")


def test_params_file_is_in_ros_parameters_form_with_valid_values() -> None:
    data = yaml.safe_load(PARAMS.read_text(encoding="utf-8"))
    params = data["/**"]["ros__parameters"]
    assert set(params) <= NAMES and NAMES - set(params) <= {"points"}  # points follows the scene
    for name, value in params.items():
        assert validate_parameter(name, value) is None, name


def test_launch_description_builds_with_ros_launch() -> None:
    pytest.importorskip("launch_ros", reason="launch_ros is only available in a ROS 2 Jazzy workspace")
    from launch.launch_description_sources import get_launch_description_from_python_launch_file

    description = get_launch_description_from_python_launch_file(str(LAUNCH))
    declared = {e.name for e in description.entities if type(e).__name__ == "DeclareLaunchArgument"}
    assert declared == NAMES | {"params_file"}
