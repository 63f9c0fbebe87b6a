"""``linkage-synth``: the solver's synthesis command with ``--rrd`` served (docs/synthesis.md).

The command itself is :mod:`solver.synth_cli` (the solver never imports rerun or linkage_ros);
this entry point hands it the rerun view's writer (:mod:`linkage_ros.record.synthesis_view`,
imported only when a view is written, so a run without ``--rrd`` needs no rerun). Without the
rerun package ``--rrd`` is refused in one line before the search starts (exit status 2).
"""

from __future__ import annotations

import importlib.util
import sys
from collections.abc import Sequence
from typing import Any

from solver.synth_cli import PROG
from solver.synth_cli import main as solver_main

__all__ = ["main"]


def _write_rrd(res: Any, path: str) -> None:
    from .record.synthesis_view import write_synthesis_rrd

    write_synthesis_rrd(res, path)


def main(argv: Sequence[str] | None = None) -> int:
    args = list(sys.argv[1:] if argv is None else argv)
    if any(a == "--rrd" or a.startswith("--rrd=") for a in args) and importlib.util.find_spec("rerun") is None:
        print(f"{PROG}: error: --rrd needs the 'rerun-sdk' package (pip install linkage_ros[view])", file=sys.stderr)
        return 2
    return solver_main(args, rrd_writer=_write_rrd)


if __name__ == "__main__":
    sys.exit(main())
