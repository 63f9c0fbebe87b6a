"""bench/drawn_load.py runs (its numbers are docs/scenes.md's, not asserted here: timings are noisy)."""

from __future__ import annotations

from bench import drawn_load


def test_the_drawn_load_bench_runs(capsys) -> None:  # type: ignore[no-untyped-def]
    assert drawn_load.main(["--repeat", "2"]) == 0
    out = capsys.readouterr().out
    assert "crank_rocker_drawn" in out and "ratio" in out
