"""launch/display.launch.py and config/linkage.rviz, checked without ROS.

The launch file is run against small in-test stand-ins for the launch API it calls
(``launch``, ``launch_ros``, ``ament_index_python``); under a Jazzy workspace the last test
loads it with the real packages.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path
from typing import Any

import launch_stubs
import pytest
import yaml
from launch_stubs import LaunchCtx, Recorded

from linkage_ros.urdf import generate_urdf

ROOT = Path(__file__).resolve().parents[2]
LAUNCH = ROOT / "launch" / "display.launch.py"
RVIZ = ROOT / "config" / "linkage.rviz"


def _load_launch() -> Any:
    spec = importlib.util.spec_from_file_location("display_launch", LAUNCH)
    assert spec is not None and spec.loader is not None
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_display_launch_starts_node_state_publisher_and_rviz_with_the_generated_urdf(
    monkeypatch: pytest.MonkeyPatch,
) -> None:
    launch_stubs.install(monkeypatch, ROOT)
    mod = _load_launch()
    description = mod.generate_launch_description()
    actions = [a for a in description.args[0] if isinstance(a, Recorded)]
    declared = {a.args[0] for a in actions if a.args and isinstance(a.args[0], str)}
    assert {"scene", "omega", "epsilon", "rate_hz", "frame_id", "rviz"} <= declared
    values = {name: default for name, (default, _) in mod.ARGUMENTS.items()}
    values["scene"] = "four_bar"
    nodes = mod._nodes(LaunchCtx(values))
    by_exe = {n.kwargs["executable"]: n.kwargs for n in nodes}
    assert set(by_exe) == {"mechanism_node", "robot_state_publisher", "rviz2"}
    description_param = by_exe["robot_state_publisher"]["parameters"][0]["robot_description"]
    assert description_param.args[0] == generate_urdf("four_bar", frame_id="world")
    assert by_exe["mechanism_node"]["parameters"][1]["scene"] == "four_bar"
    assert by_exe["mechanism_node"]["remappings"] == [("robot_description", "~/robot_description")]
    params_file, = [p for p in by_exe["mechanism_node"]["parameters"] if isinstance(p, str)]
    assert Path(params_file).is_file()
    rviz_args = by_exe["rviz2"]["arguments"]
    assert Path(rviz_args[rviz_args.index("-d") + 1]) == RVIZ


def test_rviz_config_shows_robot_model_markers_and_tf_in_the_world_frame() -> None:
    config = yaml.safe_load(RVIZ.read_text(encoding="utf-8"))
    manager = config["Visualization Manager"]
    displays = {d["Class"]: d for d in manager["Displays"]}
    assert displays["rviz_default_plugins/RobotModel"]["Description Topic"]["Value"] == "/robot_description"
    assert displays["rviz_default_plugins/RobotModel"]["Description Source"] == "Topic"
    assert displays["rviz_default_plugins/MarkerArray"]["Topic"]["Value"] == "/markers"
    assert displays["rviz_default_plugins/TF"]["Enabled"] is True
    assert manager["Global Options"]["Fixed Frame"] == "world"


def test_display_launch_loads_with_the_real_launch_packages() -> None:
    pytest.importorskip("launch_ros", reason="needs a ROS 2 Jazzy workspace (launch_ros)")
    mod = _load_launch()
    assert mod.generate_launch_description().entities
