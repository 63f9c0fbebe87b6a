"""linkage-synth: a scene file every command loads, a final line on exactness, one-line faults."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest

from solver import load_scene
from solver.synth_cli import main
from solver.synthesis import load_template

HERE = Path(__file__).parent / "templates"
SLIDER = HERE / "slider_crank_path.yaml"


def _targets(tmp_path: Path) -> tuple[Path, np.ndarray]:
    t = load_template(SLIDER)
    xy = t.scene([0.05, 0.25, 0.02, 0.1, 20.0]).solve(np.array([0.3, 1.5, 2.9, 4.4])).point("P").position
    path = tmp_path / "targets.csv"
    path.write_text("x, y  # m\n" + "\n".join(f"{float(x)!r}, {float(y)!r}" for x, y in xy) + "\n")
    return path, xy


def test_cli_writes_a_scene_and_says_exact(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    csv, xy = _targets(tmp_path)
    out = tmp_path / "best.yaml"
    assert main([str(SLIDER), "--point", "P", "--through", str(csv), "-o", str(out)]) == 0
    text = capsys.readouterr().out
    assert text.splitlines()[-1].startswith("exact: largest miss")
    assert "groups[1].length" in text and "targets:" in text
    scene = load_scene(out)
    phases = [float(m.group(1)) for m in re.finditer(r"^ +\d+ +(-?\d+\.\d{9}) ", text, re.MULTILINE)]
    got = scene.solve(np.array(phases)).point("P").position
    assert np.abs(got - xy).max() < 1e-8  # the summary prints phases to 1e-9 rad


def test_cli_workers_same_summary(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """``--workers 2``: the starts on two local processes, the same design as in one process."""
    csv, _ = _targets(tmp_path)
    assert main([str(SLIDER), "--point", "P", "--through", str(csv)]) == 0
    one = capsys.readouterr().out
    assert main([str(SLIDER), "--point", "P", "--through", str(csv), "--workers", "2"]) == 0
    two = capsys.readouterr().out

    def timeless(text: str) -> str:
        return re.sub(r"\d+\.\d+ s\b", "T s", text)

    assert timeless(two) == timeless(one) and "exact" in one


@pytest.mark.parametrize(
    ("args", "content", "message"),
    [
        (["--point", "P", "--through", "{csv}"], "x,y\n0.1, 0.2\n0.1\n",
         r"targets\.csv:3: 1 numbers, the rows above have 2"),
        (["--point", "P", "--through", "{csv}"], "# x, y\n50, 0\n",
         r"target 0 \(50, 0\) m is out of any reachable range"),
        (["--point", "P", "--through", "{csv}"], "0.1, 0.2\n0.3, abc\n", r"targets\.csv:2: not a row of numbers"),
        (["--point", "Q", "--through", "{csv}"], "0.1, 0.2\n", r"point= must name a point of the template, got 'Q'"),
        (["--point", "P", "--through", "{csv}", "--at", "1,2"], "0.1, 0.2\n", r"at= must give one finite input angle"),
        (["--point", "P", "--through", "{csv}", "-o", "/nonexistent/dir/x.yaml"], "0.1, 0.2\n",
         r"the folder /nonexistent/dir does not exist"),
    ],
)
def test_cli_faults_one_line(tmp_path: Path, capsys: pytest.CaptureFixture[str], args: list[str], content: str,
                             message: str | None) -> None:
    csv = tmp_path / "targets.csv"
    csv.write_text(content)
    code = main([str(SLIDER), *[a.format(csv=csv) for a in args]])
    err = capsys.readouterr().err.strip()
    assert code == 2 and err.startswith("linkage-synth: error:") and "\n" not in err
    if message is not None:
        import re

        assert re.search(message, err), err


def test_rrd_needs_the_linkage_ros_entry_point(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    """solver.synth_cli alone never imports rerun or linkage_ros: --rrd is one line there."""
    csv, _ = _targets(tmp_path)
    code = main([str(SLIDER), "--point", "P", "--through", str(csv), "--rrd", str(tmp_path / "s.rrd")])
    err = capsys.readouterr().err.strip()
    assert code == 2 and "--rrd needs the linkage_ros package's linkage-synth" in err and "\n" not in err
