"""Mutation fuzzing of the shipped scenes in the suite (issue #13): seeded and bounded in time.

Every mutated file either loads or is refused with one SceneError line; nothing else escapes
(no traceback), a key given twice is never accepted, a scene that loads has finite values at
every sample it reports valid and not singular (vectorised and per tick), and ``linkage-solve``
on it exits 0 or 2 with one line on stderr. ``tests/fuzz/run_fuzzer.py`` runs the same checks on
about 1,000 files, each in a fresh process with a timeout and a memory limit.
"""

from __future__ import annotations

import time
from pathlib import Path

import pytest
from scene_mutations import examine, mutations, special_cases

SEED = 20261123
COUNT = 600
BUDGET_S = 30.0
"""Stop drawing mutations after this long (at least MIN_DONE are checked whatever the machine)."""
MIN_DONE = 60
SPECIAL_BUDGET_S = 2.0
"""Each special case (bombs, deep nesting, odd bytes, huge file) is refused within this."""


def _problems(label: str, dup: bool, r: dict) -> list[str]:  # type: ignore[type-arg]
    out = []
    if r["outcome"] == "traceback" or r["cli"] == "traceback":
        out.append(f"{label}: traceback {r['message'] or r.get('cli_message', '')}")
    if dup and r["outcome"] == "loaded":
        out.append(f"{label}: a duplicate key was accepted")
    if r["nonfinite"]:
        out.append(f"{label}: {r['nonfinite']} non-finite values at valid, non-singular samples")
    if r["multiline"] or r.get("cli_lines"):
        out.append(f"{label}: an error of more than one line: {r['message']!r}")
    if r["cli"] not in (0, 2, None, "traceback"):
        out.append(f"{label}: linkage-solve exited {r['cli']}")
    return out


def test_mutated_shipped_scenes_load_or_fail_with_one_scene_error_line(tmp_path: Path) -> None:
    start = time.monotonic()
    problems: list[str] = []
    done = loaded = 0
    for i, (label, raw, dup) in enumerate(mutations(SEED, COUNT)):
        if done >= MIN_DONE and time.monotonic() - start > BUDGET_S:
            break
        path = tmp_path / f"m{i}.yaml"
        path.write_bytes(raw)
        r = examine(path, cli=i % 4 == 0)
        problems += _problems(label, dup, r)
        if r["outcome"] == "rejected":
            assert str(path) in r["message"], r["message"]  # the message names the file
        loaded += r["outcome"] == "loaded"
        done += 1
    assert not problems, "\n".join(problems[:10])
    assert done >= MIN_DONE and loaded > 0


SPECIAL = [pytest.param(label, raw, dup, id=label) for label, raw, dup in special_cases(big=False)]


@pytest.mark.parametrize(("label", "raw", "dup"), SPECIAL)
def test_the_issues_special_cases_are_refused_fast_in_one_line(
    tmp_path: Path, label: str, raw: bytes, dup: bool
) -> None:
    path = tmp_path / "case.yaml"
    path.write_bytes(raw)
    start = time.monotonic()
    r = examine(path, cli=True)
    assert time.monotonic() - start < SPECIAL_BUDGET_S * 4  # load + solve + linkage-solve
    assert not _problems(label, dup, r)
    assert r["outcome"] == "rejected" and r["cli"] == 2, (label, r)
