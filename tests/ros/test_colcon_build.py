"""The package builds with colcon in a temporary workspace and `colcon test` passes.

Uses the colcon next to this Python (the venv's, from PyPI) or on PATH. The inner `colcon test`
runs tests/ros without this file's marker and without the DDS tests (``-m "not colcon and not
dds"``), so it does not recurse and does not start nodes twice; the installed
``lib/linkage_ros/mechanism_node`` is started here instead and must publish.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import pytest

ROOT = Path(__file__).resolve().parents[2]
INNER = "LINKAGE_ROS_COLCON_INNER"
SEED_SCENES = {"four_bar", "harvester_finger", "slider_crank", "spherical_converter"}
TIMEOUT_S = 600

pytestmark = pytest.mark.colcon


def colcon_executable() -> str:
    beside = Path(sys.executable).with_name("colcon")
    found = str(beside) if beside.is_file() else shutil.which("colcon")
    if found is None:
        pytest.skip("colcon is not installed (pip install colcon-common-extensions)")
    return found


@pytest.fixture(scope="module")
def workspace(tmp_path_factory: pytest.TempPathFactory) -> Path:
    if os.environ.get(INNER):
        pytest.skip("already inside the colcon test that this test runs")
    colcon = colcon_executable()
    ws = tmp_path_factory.mktemp("colcon_ws")
    common = [colcon, "--log-base", str(ws / "log")]
    where = ["--paths", str(ROOT), "--build-base", str(ws / "build"), "--install-base", str(ws / "install")]
    build = subprocess.run(
        [*common, "build", *where], capture_output=True, text=True, timeout=TIMEOUT_S, cwd=ws
    )
    assert build.returncode == 0, build.stdout + build.stderr
    return ws


def test_colcon_installs_the_node_the_index_marker_launch_and_config(workspace: Path) -> None:
    prefix = workspace / "install" / "linkage_ros"
    node = prefix / "lib" / "linkage_ros" / "mechanism_node"
    assert node.is_file() and os.access(node, os.X_OK)
    assert (prefix / "share" / "ament_index" / "resource_index" / "packages" / "linkage_ros").is_file()
    share = prefix / "share" / "linkage_ros"
    assert (share / "package.xml").is_file()
    assert "mechanism.launch.py" in {p.name for p in (share / "launch").glob("*.launch.py")}
    assert "params.yaml" in {p.name for p in (share / "config").glob("*.yaml")}
    assert SEED_SCENES <= {p.stem for p in (share / "config" / "scenes").glob("*.yaml")}


def test_the_installed_packages_find_the_installed_scenes(workspace: Path, tmp_path: Path) -> None:
    prefix = workspace / "install" / "linkage_ros"
    (site,) = (prefix / "lib").glob("python3*/site-packages")
    env = {**os.environ, "PYTHONPATH": str(site), "AMENT_PREFIX_PATH": str(prefix)}
    env.pop("LINKAGE_SCENES", None)
    code = (
        "import solver, linkage_ros.engine as e; "
        f"assert solver.__file__.startswith({str(site)!r}), solver.__file__; "
        f"assert str(solver.find_scene('four_bar')).startswith({str(prefix)!r}); "
        "print(e.Engine('four_bar', e.Motion()).frame(0.1).status)"
    )
    run = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, env=env, cwd=tmp_path, timeout=120
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "ok"


def test_the_installed_node_starts_and_publishes(workspace: Path, start_node: Any, client: Any) -> None:
    prefix = workspace / "install" / "linkage_ros"
    (site,) = (prefix / "lib").glob("python3*/site-packages")
    env = {**os.environ, "PYTHONPATH": str(site), "AMENT_PREFIX_PATH": str(prefix)}
    listener = client.listen({"/colcon/joint_states": "sensor_msgs/msg/JointState"})
    process = start_node("-r", "__ns:=/colcon", "-p", "scene:=four_bar",
                         executable=str(prefix / "lib" / "linkage_ros" / "mechanism_node"), env=env)
    try:
        assert client.spin_until(lambda: len(listener.messages) >= 1, 30.0), process.output()
    finally:
        assert process.stop(signal.SIGTERM) == 0, process.output()


def test_colcon_test_passes(workspace: Path) -> None:
    colcon = colcon_executable()
    results = workspace / "test_results"
    common = [colcon, "--log-base", str(workspace / "log")]
    where = ["--paths", str(ROOT), "--build-base", str(workspace / "build"),
             "--install-base", str(workspace / "install")]
    env = {**os.environ, INNER: "1"}
    run = subprocess.run(
        [*common, "test", *where, "--test-result-base", str(results),
         "--pytest-args", "tests/ros", "-m", "not colcon and not dds"],
        capture_output=True, text=True, timeout=TIMEOUT_S, cwd=workspace, env=env,
    )
    assert run.returncode == 0, run.stdout + run.stderr
    summary = subprocess.run(
        [*common, "test-result", "--test-result-base", str(results), "--verbose"],
        capture_output=True, text=True, timeout=120, cwd=workspace,
    )
    assert summary.returncode == 0, summary.stdout + summary.stderr
    suite = ET.parse(results / "linkage_ros" / "pytest.xml").getroot()
    suite = suite if suite.tag == "testsuite" else suite.find("testsuite")
    assert suite is not None
    assert int(suite.get("tests", "0")) > 50
    assert (int(suite.get("failures", "0")), int(suite.get("errors", "0"))) == (0, 0)
