"""``linkage-solve`` with several inputs: per-input motion laws, CSV columns named per input, the
derivative columns, the assemblable-region map and one-line errors."""

from __future__ import annotations

import csv
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from multi_builders import FIVE_BAR

import solver
from solver.cli import main as linkage_solve
from solver.cli_inputs import csv_header
from solver.multi import assemblable

REF = json.loads((Path(__file__).resolve().parent.parent / "data" / "reference_five_bar.json").read_text())
TOL_REL = 1e-9


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = linkage_solve(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def _csv(text: str) -> tuple[list[str], np.ndarray]:
    rows = list(csv.reader(io.StringIO(text)))
    return rows[0], np.array(rows[1:], dtype=float)


def test_csv_names_each_input_and_matches_the_50_digit_reference(capsys: pytest.CaptureFixture[str]) -> None:
    picks = [0, 17, 60, 103, 120]
    rows = ";".join(f"{float(REF['q'][i][0])!r},{float(REF['q'][i][1])!r}" for i in picks)
    code, out, err = _run(capsys, "five_bar", "--samples", rows, "--omega", "q1=2", "--omega", "q2=-1.5",
                          "--epsilon", "q1=0.7", "--epsilon", "q2=3", "--csv", "-")
    assert code == 0, err
    header, body = _csv(out)
    assert header == csv_header(solver.load_scene("five_bar"))
    assert header[:2] == ["q1", "q2"]
    col = dict(zip(header, body.T))
    for axis in ("x", "y"):
        i = "xy".index(axis)
        for key, prefix, scale in (("velocity", "v", 0.25 * 2.0), ("acceleration", "a", 0.25 * 7.0)):
            want = np.array([float(REF["points"]["P"][key][p][i]) for p in picks])
            got = col[f"P.{prefix}{axis}"]
            assert (np.abs(got - want) / np.maximum(np.abs(want), scale)).max() <= TOL_REL


def test_derivative_columns_are_the_jacobian_and_hessian(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(capsys, "five_bar", "--deg", "--range", "q1=40:140", "--range", "q2=40:140",
                          "--count", "4", "--csv", "-", "--derivatives")
    assert code == 0, err
    header, body = _csv(out)
    col = dict(zip(header, body.T))
    q = np.column_stack([col["q1"], col["q2"]])
    k = solver.load_scene("five_bar").solve(q)
    np.testing.assert_array_equal(col["P.y.d_q2"], k.point("P").jacobian[:, 1, 1])
    np.testing.assert_array_equal(col["P.x.d2_q1_q2"], k.point("P").hessian[:, 0, 0, 1])
    np.testing.assert_array_equal(col["left_distal.d2_q2_q2"], k.joint("left_distal").hessian[:, 1, 1])
    np.testing.assert_allclose(q[[0, -1]], np.radians([[40, 40], [140, 140]]), rtol=0, atol=1e-15)


def _short_five_bar(tmp_path: Path) -> Path:
    data = yaml.safe_load(yaml.safe_dump(FIVE_BAR))
    data["groups"][2]["lengths"] = [0.2, 0.2]
    path = tmp_path / "short.yaml"
    path.write_text(yaml.safe_dump(data), encoding="utf-8")
    return path


def test_region_map_shows_where_the_five_bar_closes(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = _short_five_bar(tmp_path)
    code, out, err = _run(capsys, str(path), "--region", "--count", "12")
    assert code == 0, err
    lines = out.splitlines()
    assert "assemblable region over 12 × 12 samples of (q1, q2)" in lines[0]
    grid = [line.split()[-1] for line in lines[2:]]
    assert len(grid) == 12 and all(len(row) == 12 for row in grid)
    axis = np.linspace(0.0, 2 * math.pi, 12, endpoint=False)
    region = assemblable(solver.load_scene(path), [axis, axis])
    shown = np.array([[c != "." for c in row] for row in grid[::-1]]).T  # rows: q2 from the top
    np.testing.assert_array_equal(shown, region)
    assert not region.all() and region.any()


def test_unassemblable_samples_fail_in_one_line_or_are_masked(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    path = str(_short_five_bar(tmp_path))
    code, out, err = _run(capsys, path, "--deg", "--samples", "90,90;180,0", "--csv", "-")
    assert code == 2 and out == ""
    assert err.startswith("linkage-solve: error: ") and "group 'distal' cannot be assembled at 1 sample(s)" in err
    assert err.count("\n") == 1
    code, out, err = _run(capsys, path, "--deg", "--samples", "90,90;180,0", "--csv", "-", "--mask")
    assert code == 0
    _, body = _csv(out)
    assert body.shape[0] == 1


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--omega", "q3=1"], r"--omega 'q3=1': give INPUT=VALUE with INPUT one of q1, q2"),
        (["--epsilon", "q1"], r"--epsilon 'q1': give INPUT=VALUE"),
        (["--range", "q1=0"], r"--range 'q1=0': give INPUT=LO:HI"),
        (["--samples", "1,2,3"], r"--samples: each row needs 2 values, one per input \(q1, q2\)"),
        (["--region", "--samples", "1,2"], r"--region maps a grid"),
    ],
)
def test_bad_options_are_one_line_errors(capsys: pytest.CaptureFixture[str], argv: list[str], message: str) -> None:
    code, out, err = _run(capsys, "five_bar", *argv)
    assert code == 2
    assert err.count("\n") == 1
    import re

    assert re.search(message, err), err


def test_summary_names_the_inputs_and_the_extremes(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(capsys, "five_bar", "--count", "8", "--omega", "q1=2", "--omega", "q2=-1")
    assert code == 0, err
    assert out.startswith("scene five_bar: 64 of 64 samples of the inputs (q1, q2) assemblable; ω: q1 = 2, q2 = -1")
    assert "  point P" in out and "    position: x " in out and "max speed |v| = " in out
    assert "singular samples (derivatives NaN there): 1: (q1 = 180.00°, q2 = 0.00°)" in out


def test_single_input_scenes_keep_their_command(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(capsys, "four_bar", "--phi", "0.1,0.2", "--csv", "-")
    assert code == 0, err
    assert out.splitlines()[0].startswith("phi,A.x,A.y")
