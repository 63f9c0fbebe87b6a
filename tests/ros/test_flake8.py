"""ament_flake8 over the package's Python code (runs where ament's lint packages are installed)."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PATHS = ["linkage_ros", "solver", "launch", "tests", "setup.py"]


def test_flake8_finds_no_style_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    main = pytest.importorskip(
        "ament_flake8.main", reason="ament_flake8 is only available in a ROS 2 workspace"
    ).main_with_errors
    monkeypatch.chdir(ROOT)
    config = str(Path(__file__).with_name("ament_flake8.ini"))
    rc, errors = main(argv=["--config", config, *PATHS])
    assert rc == 0, f"{len(errors)} flake8 error(s):\n" + "\n".join(errors)
