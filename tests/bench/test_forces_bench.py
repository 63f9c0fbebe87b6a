"""The force bench's code paths on tiny sizes (nothing timed is asserted).

bench/forces.py measures the cost of efforts and pin loads over kinematics and puts kinepy side
by side with us on issue 17's four-bar. These tests run each path on a few samples, check that
the kinepy model is the same mechanism as ours (its torque within its own finite-difference
error of our exact one), and that the report's section replaces only itself in
docs/speed-vs-error.md, also when bench/speed_vs_error.py rewrites the rest of the file.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import solver  # noqa: E402
from bench import forces  # noqa: E402

TINY = forces.Config(quick=True, n_time=64, repeat=1, steps_deg=(1.0,))
KINEPY_AT_1_DEGREE = 1e-4
"""kinepy's central differences at 1° steps: ~3e-6 of the peak torque measured; a wrong model
(a sign, a frame, a load) is off by far more than this."""
REFERENCE = 1e-9
"""Issue 17's tolerance against the 50-digit reference."""


def _ours(count: int) -> np.ndarray:
    path = forces.scene_file("four_bar_loaded")
    assert path is not None
    scene = solver.load_scene(path)
    return np.asarray(scene.solve(forces.turn(count), omega=forces.OMEGA, epsilon=0.0).effort(scene.inputs[0]))


def test_every_scene_with_forces_gets_a_cost_row() -> None:
    for name in forces.SCENES:
        row = forces.cost_of_forces(name, TINY)
        assert row is not None, name
        assert row["quantities"] >= 3 and math.isfinite(row["ratio"]) and row["ratio"] > 0


def test_the_reference_torque_is_the_solvers_to_the_issue_tolerance(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(forces, "CACHE", tmp_path)
    monkeypatch.setattr(forces, "_ensure_cache", lambda: None)
    path = forces.scene_file("four_bar_loaded")
    assert path is not None
    want = forces.reference_torque(path, 8)
    assert np.max(np.abs(_ours(8) - want)) <= REFERENCE * np.max(np.abs(want))
    assert list(tmp_path.glob("forces_reference_*_8.json")), "the reference is cached"


def test_kinepy_models_the_same_four_bar() -> None:
    pytest.importorskip("kinepy")
    path = forces.scene_file("four_bar_loaded")
    assert path is not None
    system, pilot = forces.kinepy_four_bar(path)
    phi, got = forces.kinepy_torque(system, pilot, 1.0)
    assert len(phi) == 360 and not np.isfinite(got[0]) and not np.isfinite(got[-1])  # undefined at the ends
    want = _ours(360)
    assert np.max(np.abs(got[1:-1] - want[1:-1])) <= KINEPY_AT_1_DEGREE * np.max(np.abs(want))


def test_measure_and_section_on_tiny_sizes(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(forces, "reference_torque", lambda path, count: _ours(count))
    report = forces.measure(TINY, log=lambda _: None)
    text = forces.section(report)
    assert text.startswith(forces.HEADING + "\n")
    assert "ours, vectorised" in text and "four_bar_loaded" in text
    assert ("kinepy 0" in text) or ("kinepy not measured" in text)


def test_the_section_replaces_only_itself_and_survives_a_rewrite(tmp_path: Path) -> None:
    md = tmp_path / "speed-vs-error.md"
    md.write_text("# Speed against error\n\n## four_bar\n\nrows\n")
    forces.write_section(md, "## Forces\n\nfirst\n")
    forces.write_section(md, "## Forces\n\nsecond\n")
    assert md.read_text() == "# Speed against error\n\n## four_bar\n\nrows\n\n## Forces\n\nsecond\n"
    md.write_text(md.read_text() + "\n## After\n\nkept\n")
    forces.write_section(md, "## Forces\n\nthird\n")
    assert "third" in md.read_text() and "second" not in md.read_text() and md.read_text().endswith("kept\n")
    with forces.carry_section(md):  # what bench/speed_vs_error.py does around its own rewrite
        md.write_text("# Speed against error\n\n## four_bar\n\nnew rows\n")
    assert md.read_text() == "# Speed against error\n\n## four_bar\n\nnew rows\n\n## Forces\n\nthird\n"
