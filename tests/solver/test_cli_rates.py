"""linkage-solve reads --omega/--epsilon as linkage-run does: ``W`` or ``Q=W`` naming the input."""

from __future__ import annotations

import argparse

import pytest

import solver
from linkage_ros.cli import _laws
from solver.cli import main


def _out(capsys: pytest.CaptureFixture[str], *args: str) -> tuple[int, str, str]:
    code = main(list(args))
    got = capsys.readouterr()
    return code, got.out, got.err


def test_a_named_rate_of_the_one_input_is_the_plain_rate(capsys: pytest.CaptureFixture[str]) -> None:
    code, named, err = _out(capsys, "four_bar", "--phi-count", "8", "--omega", "crank=2",
                            "--epsilon", "crank=-0.5", "--csv", "-")
    assert code == 0, err
    code, plain, err = _out(capsys, "four_bar", "--phi-count", "8", "--omega", "2", "--epsilon", "-0.5", "--csv", "-")
    assert code == 0 and named == plain


def test_a_rate_naming_another_input_is_refused_in_linkage_runs_words(capsys: pytest.CaptureFixture[str]) -> None:
    code, out, err = _out(capsys, "four_bar", "--omega", "q1=2")
    assert code == 2 and out == ""
    assert err == ("linkage-solve: error: --omega 'q1=2': give INPUT=VALUE with INPUT one of crank, "
                   "or one VALUE for every input\n")
    scene = solver.load_scene("four_bar")
    with pytest.raises(ValueError, match="give INPUT=VALUE with INPUT one of crank, or one VALUE for every input"):
        _laws(scene, argparse.Namespace(omega=["q1=2"], epsilon=[], phi0=[]))


def test_a_named_rate_that_is_not_a_number_says_so(capsys: pytest.CaptureFixture[str]) -> None:
    code, _, err = _out(capsys, "four_bar", "--epsilon", "crank=fast")
    assert code == 2 and err == "linkage-solve: error: --epsilon 'crank=fast': 'fast' is not a number\n"
