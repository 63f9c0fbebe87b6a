"""launch/relay.launch.py: driver joint_states → mechanism_node in topic mode → robot_state_publisher.

launch and launch_ros are not installable here (not on PyPI): the launch file is parsed, and run
against small in-test stand-ins for the launch API it calls, as tests/urdf/test_urdf_display.py
does; under a Jazzy workspace the last test loads it with the real packages.
"""

from __future__ import annotations

import ast
import importlib.util
from pathlib import Path
from typing import Any

import launch_stubs
import pytest
import yaml
from launch_stubs import LaunchCtx, Recorded

from linkage_ros.parameters import SPECS, validate_parameter
from linkage_ros.urdf import generate_urdf

ROOT = Path(__file__).resolve().parents[2]
LAUNCH = ROOT / "launch" / "relay.launch.py"
PARAMS = ROOT / "config" / "params.yaml"
ARGUMENTS = {"scene", "input_topic", "input_joint", "urdf", "frame_id", "rviz", "topic_epsilon", "topic_max_gap"}


def _load(monkeypatch: pytest.MonkeyPatch) -> Any:
    launch_stubs.install(monkeypatch, ROOT)
    spec = importlib.util.spec_from_file_location("relay_launch", LAUNCH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _nodes(mod: Any, **values: str) -> dict[str, dict[str, Any]]:
    args = {name: default for name, (default, _) in mod.ARGUMENTS.items()}
    args.update(values)
    return {n.kwargs["executable"]: n.kwargs for n in mod._nodes(LaunchCtx(args))}


def test_launch_file_parses_and_declares_its_arguments() -> None:
    tree = ast.parse(LAUNCH.read_text(encoding="utf-8"), filename=str(LAUNCH))
    assert "generate_launch_description" in {n.name for n in tree.body if isinstance(n, ast.FunctionDef)}
    arguments = next(
        n.value for n in tree.body
        if isinstance(n, ast.Assign) and any(getattr(t, "id", "") == "ARGUMENTS" for t in n.targets)
    )
    assert {ast.literal_eval(k) for k in arguments.keys} == ARGUMENTS  # type: ignore[attr-defined]


def test_node_runs_in_topic_mode_on_the_drivers_topic_and_state_publisher_gets_the_scenes_urdf(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    mod = _load(monkeypatch)
    description = mod.generate_launch_description()
    declared = {a.args[0] for a in description.args[0] if isinstance(a, Recorded) and a.args}
    assert ARGUMENTS <= declared
    nodes = _nodes(mod, input_topic="/arm/joint_states")
    assert set(nodes) == {"mechanism_node", "robot_state_publisher", "rviz2"}
    node = nodes["mechanism_node"]
    params_file, overrides = node["parameters"]
    assert Path(params_file).is_file()
    assert overrides == {"scene": "four_bar", "frame_id": "world", "input_source": "topic",
                         "topic_epsilon": "zero", "topic_max_gap": 0.25}
    assert node["remappings"] == [("input_joint_states", "/arm/joint_states"),
                                  ("robot_description", "~/robot_description")]  # not robot_state_publisher's
    urdf = nodes["robot_state_publisher"]["parameters"][0]["robot_description"].args[0]
    assert urdf == generate_urdf("four_bar", frame_id="world")


def test_the_users_urdf_and_driver_joint_are_passed_through(monkeypatch: pytest.MonkeyPatch) -> None:
    mod = _load(monkeypatch)
    nodes = _nodes(
        mod, scene="gripper_finger", input_joint="finger_joint", urdf="gripper_finger.urdf", frame_id="palm"
    )
    overrides = nodes["mechanism_node"]["parameters"][1]
    assert overrides["input_joint"] == "finger_joint" and overrides["scene"] == "gripper_finger"
    urdf = nodes["robot_state_publisher"]["parameters"][0]["robot_description"].args[0]
    assert urdf == (ROOT / "config" / "urdf" / "gripper_finger.urdf").read_text(encoding="utf-8")


def test_the_epsilon_rule_and_the_gap_reach_the_node_as_its_parameters(monkeypatch: pytest.MonkeyPatch) -> None:
    mod = _load(monkeypatch)
    overrides = _nodes(mod, topic_epsilon="difference", topic_max_gap="0.05")["mechanism_node"]["parameters"][1]
    assert overrides["topic_epsilon"] == "difference"
    assert overrides["topic_max_gap"] == 0.05 and isinstance(overrides["topic_max_gap"], float)
    for name in ("topic_epsilon", "topic_max_gap"):
        assert validate_parameter(name, overrides[name]) is None


def test_a_gap_that_is_not_a_number_is_refused_in_one_line(monkeypatch: pytest.MonkeyPatch) -> None:
    mod = _load(monkeypatch)
    with pytest.raises(ValueError, match=r"^topic_max_gap must be a number of seconds, got 'soon'$"):
        _nodes(mod, topic_max_gap="soon")


def test_the_node_parameters_default_as_in_params_yaml_and_are_valid(monkeypatch: pytest.MonkeyPatch) -> None:
    mod = _load(monkeypatch)
    params = yaml.safe_load(PARAMS.read_text(encoding="utf-8"))["/**"]["ros__parameters"]
    for name in ("topic_epsilon", "topic_max_gap"):
        default = yaml.safe_load(mod.ARGUMENTS[name][0])
        assert default == params[name] == SPECS[name].default, name
    overrides = _nodes(mod)["mechanism_node"]["parameters"][1]  # scene: four_bar, not params.yaml's
    assert {name: validate_parameter(name, value) for name, value in overrides.items()} == dict.fromkeys(overrides)


def test_relay_launch_loads_with_the_real_launch_packages() -> None:
    pytest.importorskip("launch_ros", reason="needs a ROS 2 Jazzy workspace (launch_ros)")
    spec = importlib.util.spec_from_file_location("relay_launch", LAUNCH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.generate_launch_description().entities
