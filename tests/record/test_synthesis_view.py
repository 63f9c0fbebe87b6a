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


@pytest.mark.slow
def test_linkage_synth_rrd_option(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """The console script linkage-synth (linkage_ros.synth_cli) writes the view with --rrd."""
    from linkage_ros.synth_cli import main

    t = load_template(TEMPLATE)
    xy = t.scene([0.05, 0.25, 0.02, 0.1, 20.0]).solve(np.array([0.3, 1.5, 2.9, 4.4])).point("P").position
    csv = tmp_path / "targets.csv"
    csv.write_text("\n".join(f"{float(x)!r}, {float(y)!r}" for x, y in xy) + "\n")
    out = tmp_path / "s.rrd"
    assert main([str(TEMPLATE), "--point", "P", "--through", str(csv), "--rrd", str(out)]) == 0
    text = capsys.readouterr().out
    assert f"wrote {out}" in text and text.splitlines()[-1].startswith("exact:")
    assert out.stat().st_size > 10_000
