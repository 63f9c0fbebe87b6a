"""Fixtures of the ROS package tests: the rclpy stand-in, installed per test."""

from __future__ import annotations

import importlib
import sys
from collections.abc import Iterator
from pathlib import Path
from types import ModuleType
from typing import Any

import pytest

HERE = Path(__file__).parent
if str(HERE) not in sys.path:  # fake_rclpy and the shared test scene, whatever the import mode
    sys.path.insert(0, str(HERE))

import fake_rclpy  # noqa: E402


@pytest.fixture
def ros(monkeypatch: pytest.MonkeyPatch) -> Iterator[dict[str, Any]]:
    """The rclpy stand-in in sys.modules and a freshly imported linkage_ros.node (as "node")."""
    modules = fake_rclpy.install(monkeypatch)
    node_module: ModuleType = importlib.import_module("linkage_ros.node")
    yield {**modules, "node": node_module}
    sys.modules.pop("linkage_ros.node", None)
    package = sys.modules.get("linkage_ros")
    if package is not None and hasattr(package, "node"):
        delattr(package, "node")
