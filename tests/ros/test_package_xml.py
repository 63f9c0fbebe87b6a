"""package.xml: format 3, ament_python, the dependencies the node and its tests use."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
EXEC = {"rclpy", "sensor_msgs", "geometry_msgs", "visualization_msgs", "trajectory_msgs",
        "diagnostic_msgs", "std_msgs", "builtin_interfaces", "rcl_interfaces", "python3-numpy",
        "python3-yaml", "python3-scipy"}
TEST = {"python3-pytest", "ament_copyright", "ament_flake8", "ament_pep257"}


def test_package_xml_declares_an_ament_python_package_with_its_dependencies() -> None:
    root = ET.parse(ROOT / "package.xml").getroot()
    assert root.tag == "package" and root.get("format") == "3"
    assert root.findtext("name") == "linkage_ros"
    assert root.findtext("export/build_type") == "ament_python"
    assert EXEC <= {e.text for e in root.findall("exec_depend")}
    assert TEST <= {e.text for e in root.findall("test_depend")}
    assert (ROOT / "resource" / "linkage_ros").is_file()  # the ament index marker


def test_setup_cfg_puts_scripts_where_ros2_run_finds_them() -> None:
    text = (ROOT / "setup.cfg").read_text(encoding="utf-8")
    assert "script_dir=$base/lib/linkage_ros" in text.replace(" ", "")
    assert "install_scripts=$base/lib/linkage_ros" in text.replace(" ", "")
