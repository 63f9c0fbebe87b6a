"""bench/models.py runs (its numbers are docs/models.md's; timings are not asserted: the machine is
shared). The loop gaps are: MuJoCo's soft connects open, ours closed to round-off."""

from __future__ import annotations

import re

import pytest

pytest.importorskip("mujoco")
pytest.importorskip("rosbags")

from bench import models


def test_the_models_bench_runs(capsys: pytest.CaptureFixture[str]) -> None:
    assert models.main(["--quick"]) == 0
    out = capsys.readouterr().out
    assert "import of the 2F-85 in a fresh process" in out and "kinematics only" in out
    theirs, ours = (float(x) for x in re.search(r"MuJoCo \(soft connect\) (\S+) m; ours (\S+) m;", out).groups())
    assert theirs > 1e-7 and ours < 1e-15
