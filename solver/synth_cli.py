"""linkage-synth: dimensional synthesis from a template scene (docs/synthesis.md).

    linkage-synth TEMPLATE --point P --through targets.csv [--at at.csv] -o best.yaml
    linkage-synth TEMPLATE --joint J --pairs pairs.csv -o best.yaml          (function generation)
    linkage-synth TEMPLATE --point P --joint J --poses poses.csv -o best.yaml (motion generation)

Target files are CSV rows of numbers in SI units (x, y in m; angles in rad; ``#`` comments and a
header line allowed). A progress bar goes to stderr when it is a terminal; the summary (the
dimensions, the miss at each target, transmission angle range, Grashof type) to stdout, ending
with one line that says how exact the result is. Faults are one line on stderr, exit status 2.
"""

from __future__ import annotations

import math
import sys
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from ._cmdline import OMEGA_MAX, Parser, check_output, count, one_line, positive, quiet_pipe, within
from .errors import SolverError, SynthesisError

__all__ = ["main", "read_rows", "RrdWriter"]

PROG = "linkage-synth"


def read_rows(path: str, what: str) -> np.ndarray:
    """The numeric rows of a CSV file (comments after ``#``, one header line allowed)."""
    try:
        text = Path(path).read_text(encoding="utf-8")
    except OSError as exc:
        raise SynthesisError(f"{what} {path}: cannot read: {exc.strerror or exc}") from None
    except UnicodeDecodeError:
        raise SynthesisError(f"{what} {path}: not UTF-8 text") from None
    rows: list[list[float]] = []
    first = True
    for number, line in enumerate(text.splitlines(), 1):
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        header, first = first, False
        cells = [c.strip() for c in line.replace(";", ",").split(",")]
        try:
            values = [float(c) for c in cells]
        except ValueError:
            if header:
                continue  # a header line
            raise SynthesisError(f"{what} {path}:{number}: not a row of numbers: {one_line(line, 60)!r}") from None
        if not all(math.isfinite(v) for v in values):
            raise SynthesisError(f"{what} {path}:{number}: numbers must be finite, got {one_line(line, 60)!r}")
        if rows and len(values) != len(rows[0]):
            raise SynthesisError(f"{what} {path}:{number}: {len(values)} numbers, the rows above have {len(rows[0])}")
        rows.append(values)
    if not rows:
        raise SynthesisError(f"{what} {path}: no rows of numbers")
    return np.array(rows)


def _parser() -> Parser:
    p = Parser(prog=PROG, description="Dimensional synthesis from a template scene (docs/synthesis.md).")
    p.add_argument("template", help="a scene file with {free: [lo, hi]} values")
    p.add_argument("--point", help="the point that passes through the targets (path, motion generation)")
    p.add_argument("--joint", help="the joint: its value against the input (function), a body's angle (motion)")
    task = p.add_mutually_exclusive_group(required=True)
    task.add_argument("--through", metavar="CSV", help="path generation: rows x, y (m)")
    task.add_argument("--pairs", metavar="CSV", help="function generation: rows φ, q (rad; q in the joint's unit)")
    task.add_argument("--poses", metavar="CSV", help="motion generation: rows x, y (m), θ (rad)")
    p.add_argument("--at", metavar="CSV|LIST", help="input angles (rad) at the targets: timing (a file or a,b,c)")
    p.add_argument("-o", "--output", metavar="YAML", help="write the best design as a scene file")
    p.add_argument("--seed", type=int, default=0, help="seed of the search (default 0: the same designs on every "
                   "run)")
    p.add_argument("--time-limit", type=positive, metavar="S",
                   help="stop after S seconds with the best so far (default: no limit)")
    p.add_argument("--starts", type=count, default=None,
                   help="most starts of the multi-start sweep (default 64 short ones or 32: docs/synthesis.md)")
    p.add_argument("--min-transmission", type=within(0.0, 90.0, "degrees"), default=30.0, metavar="DEG",
                   help="smallest transmission angle of every dyad, degrees (default 30)")
    p.add_argument("--max-ratio", type=positive, help="longest link over the shortest at most this (default: no "
                   "limit)")
    p.add_argument("--input-range", metavar="LO,HI",
                   help="the range the input must turn through, rad (default a full turn)")
    runs = p.add_mutually_exclusive_group()
    runs.add_argument("--dask", metavar="ADDRESS", help="run the starts on this dask.distributed scheduler (default: "
                      "in this process)")
    runs.add_argument("--workers", type=count, default=None, metavar="N",
                      help="run N starts at once on N local processes (default: one, in this process; the "
                           "designs are the same)")
    p.add_argument("--all", action="store_true", help="list every distinct design found, not only the best")
    p.add_argument("--efficiency-weight", type=within(0.0, math.inf, "(a weight)"), default=0.0, metavar="W",
                   help="add W·(1 − the worst efficiency over the input range at --speed) to the search's figure "
                        "(a template with friction:, docs/forces.md#friction; default 0)")
    p.add_argument("--speed", type=within(0.0, OMEGA_MAX, "rad/s"), default=1.0, metavar="W",
                   help="input speed ω (rad/s) of the force terms (default 1)")
    p.add_argument("--rrd", metavar="FILE", help="write the rerun view of the search and its design (.rrd; "
                   "default: none)")
    return p


def _angles(text: str, what: str) -> np.ndarray:
    if Path(text).is_file():
        return read_rows(text, what).ravel()
    try:
        return np.array([float(v) for v in text.split(",")])
    except ValueError:
        raise SynthesisError(f"{what} must be a file or numbers separated by commas, "
                             f"got {one_line(text, 60)!r}") from None


class _Bar:
    """A progress bar on a terminal's stderr (nothing when it is not one)."""

    def __init__(self, stream: TextIO | None) -> None:
        self.stream = stream

    def __call__(self, done: int, total: int, best: float) -> None:
        if self.stream is None:
            return
        width = 30
        filled = int(width * done / max(total, 1))
        self.stream.write(f"\r{PROG}: [{'#' * filled}{'.' * (width - filled)}] start {done}/{total}  best {best:.3g}")
        self.stream.flush()

    def close(self) -> None:
        if self.stream is not None:
            self.stream.write("\n")
            self.stream.flush()


#: Writes a result's rerun view to a file: (result, path). The solver does not import rerun or
#: linkage_ros; the ``linkage-synth`` console script (linkage_ros.synth_cli) passes
#: linkage_ros.record.synthesis_view.write_synthesis_rrd.
RrdWriter = Callable[[Any, str], None]


@quiet_pipe
def main(argv: Sequence[str] | None = None, *, rrd_writer: RrdWriter | None = None) -> int:
    """The command (module docstring); ``rrd_writer`` serves ``--rrd`` (none: ``--rrd`` is refused)."""
    args = _parser().parse_args(sys.argv[1:] if argv is None else list(argv))
    bar = _Bar(sys.stderr if sys.stderr.isatty() else None)
    client: Any = None
    try:
        from .synthesis import synthesize

        if args.output:
            check_output(args.output, "-o")
        if args.rrd:
            if rrd_writer is None:
                raise SynthesisError("--rrd needs the linkage_ros package's linkage-synth (python -m "
                                     "linkage_ros.synth_cli); solver.synth_cli alone does not write rerun files")
            check_output(args.rrd, "--rrd")
        task: dict[str, Any] = {"point": args.point, "joint": args.joint}
        if args.through:
            task["through"] = read_rows(args.through, "--through")
        elif args.pairs:
            task["pairs"] = read_rows(args.pairs, "--pairs")
        else:
            task["poses"] = read_rows(args.poses, "--poses")
        if args.at:
            task["at"] = _angles(args.at, "--at")
        if args.input_range:
            lohi = _angles(args.input_range, "--input-range")
            if lohi.size != 2:
                raise SynthesisError(f"--input-range must be LO,HI, got {args.input_range!r}")
            task["input_range"] = (float(lohi[0]), float(lohi[1]))
        if args.dask:
            client = _client(args.dask)
        res = synthesize(
            args.template, **task, seed=args.seed, time_limit=args.time_limit,
            workers=client if client is not None else args.workers, starts=args.starts,
            min_transmission=math.radians(args.min_transmission), max_ratio=args.max_ratio, progress=bar,
            efficiency_weight=args.efficiency_weight, speed=args.speed,
        )
        bar.close()
        if args.output:
            res.save(args.output)
        print(res.summary().rsplit("\n", 1)[0])
        if args.all:
            for i, d in enumerate(res.solutions):
                tag = f" (cognate of design {d.cognate_of})" if d.cognate_of is not None else ""
                print(f"design {i}: largest miss {d.error:.3g}, {'feasible' if d.feasible else 'NOT feasible'}{tag}")
        if args.output:
            print(f"wrote {args.output}")
        if args.rrd and rrd_writer is not None:
            rrd_writer(res, args.rrd)
            print(f"wrote {args.rrd}")
        print(res.exactness())
        return 0
    except (SolverError, ValueError) as exc:
        bar.close()
        print(f"{PROG}: error: {one_line(str(exc))}", file=sys.stderr)
        return 2
    finally:
        if client is not None:
            client.close()


def _client(address: str) -> Any:
    try:
        from distributed import Client
    except ImportError:
        raise SynthesisError("--dask needs the 'distributed' package (pip install linkage_ros[synth])") from None
    try:
        return Client(address, timeout=10)
    except (OSError, TimeoutError, ValueError) as exc:
        raise SynthesisError(f"--dask {address}: cannot reach the scheduler: {one_line(str(exc), 120)}") from None


if __name__ == "__main__":
    sys.exit(main())
