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


@pytest.mark.parametrize("option", [["--range", "q1=0:1"], ["--region"], ["--samples", "1,2"], ["--derivatives"]])
def test_a_several_input_option_on_a_one_input_scene_says_which_form_it_belongs_to(
    option: list[str], capsys: pytest.CaptureFixture[str]
) -> None:
    code, out, err = _out(capsys, "four_bar", *option)
    assert code == 2 and out == ""
    assert err == (f"linkage-solve: error: {option[0]} is an option for scenes with several inputs (e.g. five_bar); "
                   "four_bar has one: sweep its input with --phi-count N or --phi V1,V2,... (linkage-solve --help)\n")


def test_an_unknown_scene_with_a_several_input_option_is_reported_as_unknown(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, _, err = _out(capsys, "no_such_scene", "--range", "q1=0:1")
    assert code == 2 and err.startswith("linkage-solve: error: no_such_scene: no such scene file")


def test_count_is_phi_count_for_one_input_as_phi_count_is_count_for_several(
    capsys: pytest.CaptureFixture[str],
) -> None:
    code, out, _ = _out(capsys, "four_bar", "--count", "5", "--csv", "-")
    assert code == 0 and len(out.strip().splitlines()) == 1 + 5


def test_an_unknown_option_is_still_one_line(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit) as stop:
        main(["four_bar", "--bogus"])
    assert stop.value.code == 2
    err = capsys.readouterr().err.strip()
    assert err == "linkage-solve: error: unrecognized arguments: --bogus (see linkage-solve --help)"
