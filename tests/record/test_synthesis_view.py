"""The rerun view of a synthesis: targets, curve, mechanism along it, convergence, in one .rrd."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

import solver
from solver.synthesis import load_template

pytest.importorskip("rerun")

from linkage_ros.record.synthesis_view import write_synthesis_rrd

TEMPLATE = Path(__file__).parents[1] / "synthesis" / "templates" / "slider_crank_path.yaml"


@pytest.mark.slow
def test_synthesis_rrd_written(tmp_path: Path) -> None:
    t = load_template(TEMPLATE)
    targets = t.scene([0.05, 0.25, 0.02, 0.1, 20.0]).solve(np.array([0.3, 1.5, 2.9, 4.4])).point("P").position
    res = solver.synthesize(t, point="P", through=targets, seed=0)
    out = tmp_path / "synthesis.rrd"
    write_synthesis_rrd(res, out)
    assert out.stat().st_size > 10_000
