"""linkage-run's "view:" hint is a command the user's shell can run (README.md: `.venv/bin/rerun`)."""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from linkage_ros.cli import rerun_command


@pytest.fixture
def venv(tmp_path: Path) -> Path:
    """A venv-like folder: bin/python and an executable bin/rerun."""
    bin_ = tmp_path / "clone" / ".venv" / "bin"
    bin_.mkdir(parents=True)
    for name in ("python", "rerun"):
        (bin_ / name).write_text("#!/bin/sh\n")
        (bin_ / name).chmod(0o755)
    return bin_


def test_without_an_activated_venv_the_hint_is_the_venvs_rerun_relative_to_the_clone(
    venv: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setenv("PATH", "/usr/bin:/bin")
    clone = venv.parent.parent
    assert rerun_command(executable=str(venv / "python"), cwd=clone) == ".venv/bin/rerun"


def test_from_another_folder_the_hint_is_the_viewers_absolute_path(
    venv: Path, monkeypatch: pytest.MonkeyPatch, tmp_path: Path
) -> None:
    monkeypatch.setenv("PATH", "/usr/bin:/bin")
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    assert rerun_command(executable=str(venv / "python"), cwd=elsewhere) == str(venv / "rerun")


def test_with_the_venv_on_path_the_hint_is_plain_rerun(venv: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("PATH", f"{venv}{os.pathsep}/usr/bin:/bin")
    assert rerun_command(executable=str(venv / "python"), cwd=venv.parent.parent) == "rerun"


def test_without_a_viewer_next_to_python_the_hint_is_plain_rerun(tmp_path: Path) -> None:
    assert rerun_command(executable=str(tmp_path / "python"), cwd=tmp_path) == "rerun"
