"""The one-instant bench's code paths, untimed: its baselines are the same mechanism as ours, and
its section replaces only itself in docs/speed-vs-error.md."""

from __future__ import annotations

import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import solver  # noqa: E402
from bench import instant  # noqa: E402


def test_the_plain_python_baseline_is_our_four_bars_b() -> None:
    scene = solver.load_scene("four_bar")
    at = {name: i for i, name in enumerate(scene.instant_layout())}
    for deg in (0, 37, 180, 299):
        phi = math.radians(deg)
        flat = scene.instant(phi)
        assert abs(instant.plain_b(phi) - complex(flat[at["B.x"]], flat[at["B.y"]])) < 1e-15


def test_ours_agrees_with_the_gauss_newton_anchor_over_a_turn() -> None:
    worst_b, worst_joint = instant._against_newton(solver.load_scene("four_bar").everything())
    assert worst_b <= instant.VALUE_TOL
    assert worst_joint <= instant.VALUE_TOL


def test_every_timed_loop_runs() -> None:
    scene = solver.load_scene("four_bar").everything()
    loops = instant._loops(scene, 1)
    assert set(loops) == {instant.OURS_API, instant.OURS_SOLVE, instant.OURS_OBJECTS, instant.OURS_FN,
                          instant.OURS_OLD, instant.PLAIN, instant.READS, instant.GN}
    for run in loops.values():
        run()


def test_the_section_replaces_only_itself(tmp_path: Path) -> None:
    md = tmp_path / "speed-vs-error.md"
    md.write_text("# Speed\n\n## four_bar\n\nfigures\n\n## Forces\n\nforces text\n")
    report = instant.Report(quick=True, machine={"cpu": "test", "python": "3"})
    methods = (instant.OURS_API, instant.OURS_SOLVE, instant.OURS_OBJECTS, instant.OURS_FN, instant.OURS_OLD,
               instant.PLAIN, instant.READS, instant.GN)
    report.per_instant_us = {name: 1.0 + i for i, name in enumerate(methods)}
    report.worst_b_m = report.worst_joint_rad = 1e-16
    report.build_ms, report.paths = {"four_bar": 1.0}, {"four_bar": 2}
    report.vectorised = {"ours, vectorised, every output fetched": 0.06,
                         "bare numpy positions only (bench.alternatives)": 0.03}
    instant.write_section(md, instant.section(report))
    first = md.read_text()
    assert first.count(instant.HEADING) == 1 and "forces text" in first and "figures" in first
    instant.write_section(md, instant.section(report))
    assert md.read_text() == first
    with instant.carry_section(md):  # another bench rewrites the file: the section comes back
        md.write_text("# Speed\n\n## four_bar\n\nnew figures\n")
    text = md.read_text()
    assert "new figures" in text and text.count(instant.HEADING) == 1
