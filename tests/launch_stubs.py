"""Stand-ins for the parts of the launch API the launch files call.

``launch``, ``launch_ros`` and ``ament_index_python`` are not on PyPI, so the launch files are
run against these recorders here (each records the arguments it was built with); under a Jazzy
workspace the launch tests also load the files with the real packages.
"""

from __future__ import annotations

import sys
import types
from pathlib import Path
from typing import Any

import pytest

__all__ = ["Recorded", "LaunchConfig", "LaunchCtx", "install"]


class Recorded:
    """Any launch action or description: keeps what it was built with."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        self.args, self.kwargs = args, kwargs


class LaunchConfig:
    """``LaunchConfiguration(name)``: performs to the launch argument's value."""

    def __init__(self, name: str) -> None:
        self.name = name

    def perform(self, context: Any) -> str:
        return str(context.values[self.name])


class LaunchCtx:
    """``LaunchContext`` with the launch arguments' values."""

    def __init__(self, values: dict[str, str]) -> None:
        self.values = values


def install(monkeypatch: pytest.MonkeyPatch, share: Path) -> None:
    """Put the recorders in ``sys.modules`` for one test; the package share is ``share``."""

    def module(name: str, **attrs: Any) -> None:
        m = types.ModuleType(name)
        for k, v in attrs.items():
            setattr(m, k, v)
        monkeypatch.setitem(sys.modules, name, m)

    module("ament_index_python")
    module("ament_index_python.packages", get_package_share_directory=lambda name: str(share))
    module("launch", LaunchContext=LaunchCtx, LaunchDescription=Recorded)
    module("launch.actions", DeclareLaunchArgument=Recorded, OpaqueFunction=Recorded)
    module("launch.conditions", IfCondition=Recorded)
    module("launch.substitutions", LaunchConfiguration=LaunchConfig)
    module("launch_ros")
    module("launch_ros.actions", Node=Recorded)
    module("launch_ros.parameter_descriptions", ParameterValue=Recorded)
