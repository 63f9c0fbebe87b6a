"""Opening a rerun recording in the rerun viewer, or saying in one line why it cannot be.

``linkage-run --spawn`` and ``linkage-view --spawn`` write the ``.rrd`` file first and then start
the viewer on it (``rerun FILE.rrd``, its own session, so it outlives the command). Two ways it
cannot show anything are caught early instead of the viewer's many lines of logs and a gRPC
client that retries for seconds:

* no display: on Linux and the BSDs none of ``DISPLAY``, ``WAYLAND_DISPLAY``,
  ``WAYLAND_SOCKET`` is set (:func:`display_problem`); the viewer is not started;
* the viewer fails fast (a display that cannot be opened, a broken GPU driver): it exits within
  :data:`FAIL_FAST_S` with a non-zero status; its last ``Error:`` line is the reason. (Exit
  status 0 at once means a viewer was already running and the file was streamed to it.)

Either way the caller prints one line that says how to view the file instead
(:func:`how_to_view`).

The viewer is started with ``XDG_RUNTIME_DIR`` set (:func:`viewer_environment`): without it the
window system's client library prints ``error: XDG_RUNTIME_DIR is invalid or not set in the
environment.`` twice (a harmless probe for Wayland that a user reads as an error); where the
variable is missing or not a folder, a private one (``<tmp>/linkage-ros-runtime-<uid>``, mode 0700)
takes its place.
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

__all__ = ["FAIL_FAST_S", "ViewerError", "display_problem", "how_to_view", "open_viewer", "show",
           "temporary_rrd", "viewer_environment", "viewer_executable"]

#: Seconds the viewer is watched after its start: one that exits within them has failed.
FAIL_FAST_S = 1.5
_POLL_S = 0.05
_DISPLAY_VARIABLES = ("DISPLAY", "WAYLAND_DISPLAY", "WAYLAND_SOCKET")


class ViewerError(RuntimeError):
    """The viewer cannot show the recording; the message is one line saying why."""


def display_problem(environ: dict[str, str] | None = None, platform: str | None = None) -> str | None:
    """Why no viewer window can open here, or None (macOS and Windows always have a display)."""
    env = os.environ if environ is None else environ
    platform = sys.platform if platform is None else platform
    if platform.startswith(("darwin", "win", "cygwin")):
        return None
    if any(env.get(name) for name in _DISPLAY_VARIABLES):
        return None
    return "no display (none of DISPLAY, WAYLAND_DISPLAY is set)"


def viewer_environment(environ: dict[str, str] | None = None) -> dict[str, str]:
    """The environment to start the rerun viewer in: ``environ`` (default: this process's) with
    ``XDG_RUNTIME_DIR`` set to a private folder when it is missing or not an absolute folder
    (POSIX only), so that the viewer starts without printing an error."""
    env = dict(os.environ if environ is None else environ)
    if os.name != "posix":
        return env
    current = env.get("XDG_RUNTIME_DIR", "")
    if not (current and os.path.isabs(current) and os.path.isdir(current)):
        env["XDG_RUNTIME_DIR"] = _private_runtime_dir()
    return env


def _private_runtime_dir() -> str:
    """``<tmp>/linkage-ros-runtime-<uid>``, made with mode 0700 (one per user, reused: the viewer
    outlives the command that started it); a fresh temporary folder when that name is taken by a
    folder of another user or with wider permissions."""
    path = os.path.join(tempfile.gettempdir(), f"linkage-ros-runtime-{os.getuid()}")
    try:
        os.mkdir(path, 0o700)
    except FileExistsError:
        pass
    except OSError:
        return tempfile.mkdtemp(prefix="linkage-ros-runtime-")
    info = os.lstat(path)
    if not os.path.isdir(path) or os.path.islink(path) or info.st_uid != os.getuid() or info.st_mode & 0o077:
        return tempfile.mkdtemp(prefix="linkage-ros-runtime-")
    return path


def how_to_view(rrd: str | os.PathLike[str]) -> str:
    """What to run instead, on a machine with a display."""
    return f"view it with `rerun {rrd}` where there is a display"


def open_viewer(rrd: str | os.PathLike[str], *, executable: str | None = None,
                fail_fast_s: float = FAIL_FAST_S) -> int:
    """Start the rerun viewer on ``rrd`` in its own session; its process id. Raises
    :class:`ViewerError` with one line when there is no display, no viewer, or the viewer fails
    (exits with a non-zero status) within ``fail_fast_s``."""
    problem = display_problem()
    if problem is not None:
        raise ViewerError(problem)
    if executable is None:
        raise ViewerError("the rerun viewer is not installed (pip install rerun-sdk)")
    log = tempfile.TemporaryFile()  # the viewer's logs: read only if it fails
    try:
        process = subprocess.Popen([executable, str(Path(rrd))], stdin=subprocess.DEVNULL,
                                   stdout=log, stderr=log, start_new_session=True, env=viewer_environment())
    except OSError as exc:
        log.close()
        raise ViewerError(f"cannot start {executable}: {exc.strerror or exc}") from None
    deadline = time.monotonic() + fail_fast_s
    while time.monotonic() < deadline:
        code = process.poll()
        if code == 0:  # a viewer was already running: the file was streamed to it
            log.close()
            return process.pid
        if code is not None:
            log.seek(0)
            reason = _last_error(log.read().decode("utf-8", "replace"))
            log.close()
            raise ViewerError(f"the rerun viewer exited at once (status {code}): {reason}")
        time.sleep(_POLL_S)
    log.close()  # the viewer keeps writing to the (already unlinked) file it was given
    return process.pid


def show(rrd: str | os.PathLike[str]) -> str | None:
    """Open ``rrd`` in the viewer next to this Python (else on PATH); None when it started, else
    one line: why not, and how to view the file instead."""
    try:
        open_viewer(rrd, executable=viewer_executable())
    except ViewerError as exc:
        return f"no viewer started: {exc}; {how_to_view(rrd)}"
    return None


def viewer_executable() -> str | None:
    """The ``rerun`` viewer next to this Python (a venv's bin), else the one on PATH, else None."""
    here = os.path.join(os.path.dirname(sys.executable), "rerun")
    return here if os.access(here, os.X_OK) else shutil.which("rerun")


def temporary_rrd(stem: str) -> Path:
    """A new empty ``.rrd`` file in the temporary folder, for a viewer to open."""
    handle, name = tempfile.mkstemp(prefix=f"{stem}-", suffix=".rrd")
    os.close(handle)
    return Path(name)


def _last_error(output: str) -> str:
    """The viewer's reason: the tail of its last ``Error:`` line (after the source location)."""
    errors = [line.strip() for line in output.splitlines() if line.strip().startswith("Error:")]
    if not errors:
        lines = [line.strip() for line in output.splitlines() if line.strip()]
        return lines[-1][:200] if lines else "no output"
    return errors[-1].rsplit(": ", 1)[-1][:200]
