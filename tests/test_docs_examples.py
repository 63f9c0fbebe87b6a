"""The Python examples of README.md and the solver's docs run as pasted (one namespace per file,
the blocks in order, as a reader pastes them into one interpreter)."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
BLOCK = re.compile(r"^```python\n(.*?)^```", re.S | re.M)
PAGES = ["README.md", "docs/forces.md", "docs/compiled.md", "docs/inputs.md", "docs/dynamics.md", "docs/models.md"]


@pytest.mark.parametrize("page", PAGES)
def test_every_python_example_of_the_page_runs(page: str, monkeypatch: pytest.MonkeyPatch) -> None:
    blocks = BLOCK.findall((ROOT / page).read_text(encoding="utf-8"))
    assert blocks, f"{page}: no Python example found"
    monkeypatch.chdir(ROOT)
    namespace: dict[str, object] = {}
    for i, code in enumerate(blocks):
        with contextlib.redirect_stdout(io.StringIO()):
            exec(compile(code, f"{page} (example {i + 1})", "exec"), namespace)
