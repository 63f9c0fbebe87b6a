"""The lock of tested versions: ./dev installs through constraints.txt, and ./dev lock rewrites it
from the venv (the project itself, pip, setuptools and wheel left out)."""

from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[1]
PIN = re.compile(r"^[A-Za-z0-9_.\-]+==[^=\s]+$")


def _pins(text: str) -> dict[str, str]:
    lines = [line for line in text.splitlines() if line and not line.startswith("#")]
    assert all(PIN.match(line) for line in lines), [line for line in lines if not PIN.match(line)]
    return {name.lower().replace("_", "-"): version for name, version in (line.split("==") for line in lines)}


def test_the_committed_lock_pins_what_the_suite_runs_on() -> None:
    text = (ROOT / "constraints.txt").read_text(encoding="utf-8")
    assert "./dev lock" in text.split("\n\n")[0]  # the header says how to refresh it
    pins = _pins(text)
    assert {"pyyaml", "numpy", "pytest", "rosbags", "mcap", "rerun-sdk", "ros-jazzy-rclpy"} <= set(pins)
    assert not {"linkage-ros", "pip", "setuptools", "wheel"} & set(pins)


def test_dev_installs_through_the_lock_and_its_stamp_hashes_it() -> None:
    dev = (ROOT / "dev").read_text(encoding="utf-8")
    assert re.search(r'pip install -q "\$\{lock\[@\]\}" -e', dev)
    assert 'lock=(-c "$LOCK")' in dev and 'hashed+=("$LOCK")' in dev
    assert "./dev lock" in dev.split("set -euo pipefail")[0]  # documented in the header


@pytest.mark.skipif(shutil.which("bash") is None, reason="./dev is a bash script")
def test_dev_lock_writes_the_venvs_versions(tmp_path: Path) -> None:
    venv = Path(sys.prefix)
    out = tmp_path / "constraints.txt"
    env = {**os.environ, "VENV": str(venv), "LOCK": str(out)}
    done = subprocess.run(["bash", str(ROOT / "dev"), "lock"], cwd=ROOT, env=env, capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr
    text = out.read_text(encoding="utf-8")
    assert text.startswith("# Versions the test suite passed with; ./dev installs through `pip install -c "
                           "constraints.txt`.")
    pins = _pins(text)
    assert pins["pyyaml"] == yaml.__version__ and pins["numpy"] == np.__version__
    assert "linkage-ros" not in pins
