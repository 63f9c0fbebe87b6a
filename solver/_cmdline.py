"""What every command of the project shares: one-line errors, numbers, output paths, pipes.

* :class:`Parser`: argparse whose errors are one line (``prog: error: …; see prog --help``) with
  exit status 2, and which takes ``-1e3`` as a number, not an option;
* :func:`finite`, :func:`positive`, :func:`count`: argument types whose messages name the value;
* :func:`check_output`: an output path must be a file in an existing folder (nothing is created
  on the user's behalf; only the default ``runs/`` folder is, by the command that owns it);
* :func:`quiet_pipe`: a closed pipe (``… | head``) ends the command quietly (status 141, as a
  command killed by SIGPIPE), Ctrl-C with status 130 and no traceback;
* :func:`error_line`: a user's mistake (a SolverError, ValueError or OSError) as the command's one
  error line on stderr, exit status 2; :func:`write_out`: a command's text to a file or stdout.
"""

from __future__ import annotations

import argparse
import functools
import math
import os
import re
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any, NoReturn

__all__ = [
    "Parser", "finite", "positive", "count", "bounded", "check_output", "quiet_pipe", "EXIT_PIPE", "one_line",
    "OMEGA_MAX", "EPSILON_MAX", "PHI_MAX", "error_line", "write_out",
]

EXIT_PIPE = 141  # 128 + SIGPIPE, what a shell reports for a command whose reader went away
EXIT_INTERRUPTED = 130

#: ``-5``, ``-0.5``, ``-.5``, ``-1e3``, ``-1.5E-3``, ``-inf``, ``-nan``: values, not options.
_NEGATIVE = re.compile(r"^-(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$|^-(inf|infinity|nan)$", re.IGNORECASE)


def one_line(text: str, limit: int = 400) -> str:
    text = " ".join(str(text).split())
    return text if len(text) <= limit else text[: limit - 3] + "..."


class Parser(argparse.ArgumentParser):
    """An ArgumentParser with one-line errors and negative numbers in exponent form."""

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self._negative_number_matcher = _NEGATIVE

    def error(self, message: str) -> NoReturn:
        self.exit(2, f"{self.prog}: error: {one_line(message)} (see {self.prog} --help)\n")


def _number(text: str, what: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number{what}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"{text!r} is not a finite number")
    return value


def finite(text: str) -> float:
    """A finite number."""
    return _number(text, "")


#: Largest |ω| (rad/s), |ε| (rad/s²) and |φ| (rad) taken on a command line: beyond, ω²·a_q and the
#: angle's reduction lose meaning long before float64 overflows (an analog of 1e9 m at ω = 1e6
#: rad/s is an acceleration of 1e21 m/s², still finite).
OMEGA_MAX, EPSILON_MAX, PHI_MAX = 1e6, 1e12, 1e6


def bounded(limit: float) -> Callable[[str], float]:
    """An argument type: a finite number with |x| ≤ ``limit``."""

    def parse(text: str) -> float:
        value = _number(text, "")
        if abs(value) > limit:
            raise argparse.ArgumentTypeError(f"|{text}| is beyond {limit:g}")
        return value

    parse.__name__ = "number"
    return parse


def within(low: float, high: float, unit: str) -> Callable[[str], float]:
    """An argument type: a finite number in [low, high) in the unit the user types (``unit``,
    e.g. degrees), refused in that unit: ``must be in [0, 90) degrees, got 95``."""

    def parse(text: str) -> float:
        value = _number(text, "")
        if not low <= value < high:
            raise argparse.ArgumentTypeError(f"must be in [{low:g}, {high:g}) {unit}, got {text}")
        return value

    parse.__name__ = "number"
    return parse


def positive(text: str) -> float:
    """A finite number > 0."""
    value = _number(text, " > 0")
    if value <= 0.0:
        raise argparse.ArgumentTypeError(f"must be > 0, got {text}")
    return value


def count(text: str) -> int:
    """A whole number ≥ 1."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number ≥ 1") from None
    if value < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, got {text}")
    return value


def check_output(path: str | os.PathLike[str], what: str = "output") -> Path:
    """``path`` if a file can be written there without creating folders; else ValueError."""
    p = Path(path)
    if p.is_dir():
        raise ValueError(f"{what} {p}: is a directory; give a file name")
    if str(path) == "" or p.name in ("", ".", ".."):
        raise ValueError(f"{what} {str(path)!r}: not a file name")
    parent = p.parent
    if not parent.exists():
        blocker = next((q for q in [parent, *parent.parents] if q.exists() and not q.is_dir()), None)
        if blocker is not None:
            raise ValueError(f"{what} {p}: {blocker} is a file, not a folder")
        raise ValueError(f"{what} {p}: the folder {parent} does not exist (create it first)")
    if not parent.is_dir():
        raise ValueError(f"{what} {p}: {parent} is a file, not a folder")
    if not os.access(parent, os.W_OK | os.X_OK) or (p.exists() and not os.access(p, os.W_OK)):
        raise ValueError(f"{what} {p}: permission denied")
    return p


def error_line(prog: str, exc: BaseException) -> int:
    """Print ``prog: error: …`` for ``exc`` in one line (an OSError as its reason and file) and
    return the exit status 2. (A BrokenPipeError is the reader going away: re-raise it before.)"""
    if isinstance(exc, OSError):
        text = f"{one_line(exc.strerror or str(exc))}: {exc.filename or ''}"
    else:
        text = one_line(str(exc))
    print(f"{prog}: error: {text}", file=sys.stderr)
    return 2


def write_out(text: str, output: str | os.PathLike[str]) -> None:
    """``text`` to the file ``output``, or to stdout where it is ``-``."""
    if str(output) == "-":
        sys.stdout.write(text)
    else:
        Path(output).write_text(text, encoding="utf-8")


def quiet_pipe(main: Callable[..., int]) -> Callable[..., int]:
    """Wrap a command's ``main``: a closed stdout ends it quietly, Ctrl-C without a traceback."""

    @functools.wraps(main)
    def wrapper(*args: Any, **kwargs: Any) -> int:
        try:
            code = main(*args, **kwargs)
            sys.stdout.flush()
            return code
        except BrokenPipeError:
            _silence_stdout()
            return EXIT_PIPE
        except KeyboardInterrupt:
            print(file=sys.stderr)
            return EXIT_INTERRUPTED

    return wrapper


def _silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail again."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):  # not a real file (a test's capture): nothing to silence
        pass
