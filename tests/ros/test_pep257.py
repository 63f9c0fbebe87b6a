"""ament_pep257 over the package's Python code (runs where ament's lint packages are installed)."""

from __future__ import annotations

from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
PATHS = ["linkage_ros", "solver", "launch"]
#: ament's defaults (D100–D105, D203) plus the project's docstring habits: summaries may run over
#: two lines, need not be imperative or end in a period, and the closing quotes may end the last
#: line. (Checked with pydocstyle 6 against linkage_ros, solver and launch: no errors.)
IGNORE = ["D100", "D101", "D102", "D103", "D104", "D105", "D106", "D107", "D203", "D205", "D209",
          "D212", "D213", "D400", "D401", "D402", "D404", "D415"]


def test_pep257_finds_no_docstring_errors(monkeypatch: pytest.MonkeyPatch) -> None:
    main = pytest.importorskip(
        "ament_pep257.main", reason="ament_pep257 is only available in a ROS 2 workspace"
    ).main
    monkeypatch.chdir(ROOT)
    assert main(argv=["--ignore", *IGNORE, "--", *PATHS]) == 0, "docstring errors (see output)"
