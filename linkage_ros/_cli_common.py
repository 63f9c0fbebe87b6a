"""What ``linkage-run``, ``linkage-view`` and ``linkage-mcap`` share (:mod:`linkage_ros.cli`).

Their exit statuses, the one-line error on stderr, whether rerun-sdk is there, and the rerun
viewer they open with ``--spawn``. No ROS, no rerun import at module level.
"""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

from solver._cmdline import one_line

__all__ = [
    "EXIT_ERROR",
    "EXIT_INTERRUPTED",
    "EXIT_OK",
    "EXIT_USAGE",
    "NO_RERUN",
    "check_input",
    "err",
    "have_rerun",
    "os_error",
    "show",
    "spawn_file",
]

EXIT_OK, EXIT_ERROR, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130

NO_RERUN = (
    "rerun-sdk is not installed (pip install 'rerun-sdk>=0.41,<0.42'; it needs numpy >= 2, "
    "so in a ROS 2 Jazzy environment with the system numpy 1.26 use a venv for viewing)"
)


def have_rerun() -> bool:
    return importlib.util.find_spec("rerun") is not None


def err(msg: str, prog: str = "linkage") -> None:
    print(f"{prog}: error: {one_line(msg)}", file=sys.stderr)


def os_error(exc: OSError) -> str:
    name = f"{exc.filename}: " if exc.filename else ""
    return f"{name}{exc.strerror or exc}"


def check_input(path: Path, what: str) -> None:
    if not path.exists():
        raise ValueError(f"{path}: no such file")
    if path.is_dir():
        raise ValueError(f"{path}: is a directory, not {what}")


def spawn_file(rrd: Path | None, stem: str) -> Path:
    """The file a spawned viewer opens: the .rrd written anyway, else a temporary one."""
    from linkage_ros.record.viewer import temporary_rrd

    return rrd if rrd is not None else temporary_rrd(stem)


def show(rrd: Path, prog: str) -> bool:
    """Open ``rrd`` in the rerun viewer; where it cannot be, one line saying how to view it."""
    from linkage_ros.record.viewer import show as show_in_viewer

    note = show_in_viewer(rrd)
    if note is not None:
        print(f"{prog}: note: {note}", file=sys.stderr)
    return note is None
