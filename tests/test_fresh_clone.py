"""The suite runs as a fresh clone's ``./dev test`` does, wherever it runs (issue 30): no pytest
cache, no Hypothesis example database, and CI in a new venv rather than a leftover one."""

from __future__ import annotations

import configparser
from pathlib import Path

from hypothesis import settings

ROOT = Path(__file__).resolve().parents[1]


def test_pytest_runs_without_its_cache_provider(pytestconfig: object) -> None:
    ini = configparser.ConfigParser()
    ini.read(ROOT / "pytest.ini", encoding="utf-8")
    assert "-p no:cacheprovider" in ini["pytest"]["addopts"]
    assert not pytestconfig.pluginmanager.has_plugin("cacheprovider")  # type: ignore[attr-defined]


def test_hypothesis_keeps_no_example_database() -> None:
    assert settings.default.database is None


def test_ci_runs_dev_test_in_a_new_venv() -> None:
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert 'fresh=$(mktemp -d)' in ci and "trap 'rm -rf \"$fresh\"' EXIT" in ci
    assert 'VENV="$fresh/venv"' in ci and ci.rstrip().endswith('./dev test "$@"')
