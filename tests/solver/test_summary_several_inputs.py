"""Scenes with several inputs get the one summary (degrees, descriptions, input joints in one
line), and linkage-solve reads ω and ε the way linkage-run does."""

from __future__ import annotations

import argparse

import numpy as np
import pytest

import solver
from solver.cli import main
from solver.cli_inputs import per_input_values


def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_five_bar_summary_is_in_degrees_with_descriptions(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(capsys, "five_bar", "--count", "12")
    assert code == 0, err
    scene = solver.load_scene("five_bar")
    assert scene.descriptions, "five_bar.yaml describes its points and joints"
    lines = out.splitlines()
    assert lines[0].endswith("angles in degrees, everything else SI")
    assert "  extremes read off the 12 × 12 grid (every 30°)" in lines
    assert f"  point P — {scene.descriptions['P']}" in lines
    assert f"  joint left_distal — {scene.descriptions['left_distal']}" in lines
    # an input: one line of position, no velocity and acceleration that repeat its law
    i = lines.index(f"  joint q1 — {scene.descriptions['q1']} (an input)")
    assert lines[i + 1] == "    position: 0.00° … 330.00° (the samples' values)"
    assert lines[i + 2].startswith("  joint q2")
    distal = lines[lines.index(f"  joint left_distal — {scene.descriptions['left_distal']}") + 1]
    assert "°" in distal and "rad " not in distal
    assert " rad\n" not in out  # angles never in radians


def test_gripper_finger_has_descriptions(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(capsys, "gripper_finger", "--phi-count", "36")
    assert code == 0, err
    scene = solver.load_scene("gripper_finger")
    for name in (*scene.output_points, *scene.output_joints):
        assert f" {name} — {scene.descriptions[name]}" in out


def test_one_omega_applies_to_every_input_as_in_linkage_run(capsys: pytest.CaptureFixture[str]) -> None:
    code, plain, err = _run(capsys, "five_bar", "--count", "4", "--omega", "2", "--csv", "-")
    assert code == 0, err
    code, named, err = _run(capsys, "five_bar", "--count", "4", "--omega", "q1=2", "--omega", "q2=2", "--csv", "-")
    assert code == 0, err
    assert plain == named
    code, out, err = _run(capsys, "five_bar", "--count", "4", "--omega", "q2=-1", "--omega", "3")
    assert code == 0, err
    assert "ω: q1 = 3, q2 = -1 rad/s" in out.splitlines()[0]  # Q=W over the plain W, in any order
    from linkage_ros.cli import _laws

    scene = solver.load_scene("five_bar")
    args = argparse.Namespace(omega=[3.0, "q2=-1"], epsilon=[], phi0=[])
    run = _laws(scene, args)["omega"]
    solve = per_input_values(scene, ["q2=-1", "3"], option="--omega", default=1.0, limit=1e6)
    np.testing.assert_array_equal(run, solve)


def test_a_bad_omega_says_what_is_expected_in_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _run(capsys, "five_bar", "--omega", "fast")
    assert code == 2 and out == ""
    assert err == ("linkage-solve: error: --omega 'fast': give INPUT=VALUE with INPUT one of q1, q2, "
                   "or one VALUE for every input\n")


def test_help_without_a_scene_shows_the_several_input_options(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as exit_:
        main(["--help"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    for option in ("--range Q=LO:HI", "--count", "--region", "--samples", "--derivatives", "--omega W|Q=W"):
        assert option in out
