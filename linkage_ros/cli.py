"""Command-line tools that need no ROS: ``linkage-run``, ``linkage-view``, ``linkage-mcap``.

* ``linkage-run SCENE``: run the node's engine on simulated time, write the MCAP recording and
  the rerun recording, print a summary per output.
* ``linkage-view RUN.mcap``: the same rerun view from the recorded messages (also from a file
  cut short by a crash).
* ``linkage-mcap recover BROKEN.mcap FIXED.mcap`` and ``linkage-mcap info RUN.mcap``.

Each ``*_main`` returns the exit status (0 ok, 1 runtime error, 2 bad input, 130 interrupted).
"""

from __future__ import annotations

import argparse
import importlib.util
import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path

__all__ = ["mcap_main", "run_main", "view_main"]

RUNS_DIR = Path("runs")
EXIT_OK, EXIT_ERROR, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130


NO_RERUN = (
    "rerun-sdk is not installed (pip install 'rerun-sdk>=0.41,<0.42'; it needs numpy >= 2, "
    "so in a ROS 2 Jazzy environment with the system numpy 1.26 use a venv for viewing)"
)


def _have_rerun() -> bool:
    return importlib.util.find_spec("rerun") is not None


def _err(msg: str) -> None:
    print(f"error: {msg}", file=sys.stderr)


def _finite(text: str) -> float:
    value = float(text)
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"not a finite number: {text!r}")
    return value


def _run_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="linkage-run",
        description="Run a mechanism on simulated time without ROS: record the node's topics "
                    "to MCAP (rosbag2 profile) and the motion to a rerun recording.")
    p.add_argument("scene", help="scene file, or the name of a shipped scene (e.g. harvester_finger)")
    span = p.add_mutually_exclusive_group()
    span.add_argument("--duration", type=_finite, metavar="S", help="simulated seconds")
    span.add_argument("--cycles", type=_finite, metavar="N",
                      help="turns of the input (default 1 when --duration is not given)")
    p.add_argument("--rate", type=_finite, default=100.0, metavar="HZ", help="ticks per second (100)")
    p.add_argument("--omega", type=_finite, default=2 * math.pi, metavar="W",
                   help="input angular velocity, rad/s (2π: one turn per second)")
    p.add_argument("--epsilon", type=_finite, default=0.0, metavar="E",
                   help="input angular acceleration, rad/s² (0)")
    p.add_argument("--phi0", type=_finite, default=0.0, metavar="RAD", help="input angle at t = 0")
    p.add_argument("--points", metavar="P,Q", help="published points (default: the scene's outputs)")
    p.add_argument("--on-unassemblable", choices=("stop", "reverse"), default="stop")
    p.add_argument("--mcap", type=Path, metavar="FILE",
                   help="MCAP output (default runs/<scene>-<time>.mcap)")
    p.add_argument("--rrd", type=Path, metavar="FILE",
                   help="rerun output (default runs/<scene>-<time>.rrd)")
    p.add_argument("--no-mcap", action="store_true", help="do not write the MCAP file")
    p.add_argument("--no-rrd", action="store_true", help="do not write the rerun file")
    p.add_argument("--spawn", action="store_true", help="also show the run in a rerun viewer")
    p.add_argument("--frame-id", default="world")
    p.add_argument("--namespace", default="/", help="node namespace of the recorded topics (/)")
    p.add_argument("--chunk-interval", type=_finite, default=1.0, metavar="S",
                   help="close and flush an MCAP chunk at least this often (1 s)")
    p.add_argument("--no-fast", action="store_true",
                   help="build and serialise every message through the builder (slower)")
    return p


def run_main(argv: Sequence[str] | None = None) -> int:
    """``linkage-run``."""
    args = _run_parser().parse_args(argv)
    try:
        import solver
        from linkage_ros.record.run import (
            RunOptions,
            duration_for_cycles,
            run_standalone,
            summary_lines,
        )
    except ImportError as exc:  # pragma: no cover - missing extra
        _err(f"{exc}; install the record extra: pip install 'linkage_ros[record]'")
        return EXIT_ERROR
    try:
        scene = solver.load_scene(args.scene)
        duration = (args.duration if args.duration is not None else
                    duration_for_cycles(args.cycles if args.cycles is not None else 1.0,
                                        args.omega, args.epsilon))
    except (solver.SolverError, ValueError, OSError) as exc:
        _err(str(exc))
        return EXIT_USAGE
    stem = f"{scene.name}-{time.strftime('%Y%m%d-%H%M%S')}"
    mcap = None if args.no_mcap else (args.mcap or RUNS_DIR / f"{stem}.mcap")
    rrd = None if args.no_rrd else (args.rrd or RUNS_DIR / f"{stem}.rrd")
    if (rrd is not None or args.spawn) and not _have_rerun():
        if args.rrd is not None or args.spawn:
            _err(NO_RERUN)
            return EXIT_USAGE
        print(f"note: {NO_RERUN}; no .rrd written", file=sys.stderr)
        rrd = None
    points = [p.strip() for p in args.points.split(",") if p.strip()] if args.points else None
    opts = RunOptions(
        scene=args.scene, duration=duration, rate=args.rate, omega=args.omega,
        epsilon=args.epsilon, phi0=args.phi0, mcap=mcap, rrd=rrd, spawn=args.spawn,
        points=points, on_unassemblable=args.on_unassemblable, frame_id=args.frame_id,
        namespace=args.namespace, chunk_interval_s=args.chunk_interval, fast=not args.no_fast)
    print(f"{scene.name}: {duration:g} s at {args.rate:g} Hz, ω = {args.omega:g} rad/s, "
          f"ε = {args.epsilon:g} rad/s², φ0 = {args.phi0:g} rad", flush=True)
    tty = sys.stderr if sys.stderr.isatty() else None
    try:
        result = run_standalone(opts, progress=tty)
    except (solver.SolverError, ValueError, KeyError) as exc:
        _err(str(exc))
        return EXIT_USAGE
    except (OSError, RuntimeError) as exc:
        _err(str(exc))
        return EXIT_ERROR
    data = result.data
    outputs = tuple(points or scene.output_points)
    for line in summary_lines(data, outputs, tuple(scene.output_joints), scene.joint_units):
        print(line)
    if set(result.statuses) - {"ok"}:
        print("status: " + ", ".join(f"{k}: {v} ticks" for k, v in sorted(result.statuses.items())))
    secs = result.seconds
    if mcap is not None:
        print(f"mcap: {mcap} ({result.messages} messages)")
    if rrd is not None:
        print(f"rerun: {rrd}  (view: rerun {rrd})")
    if result.arrow_scales:
        print(f"arrows: v × {result.arrow_scales['velocity']:g} s, "
              f"a × {result.arrow_scales['acceleration']:g} s²")
    print(f"{result.ticks} ticks in {secs['total']:.2f} s")
    if result.interrupted:
        print(f"interrupted at t = {data.t[-1] if data.n else 0.0:g} s; files finished",
              file=sys.stderr)
        return EXIT_INTERRUPTED
    return EXIT_OK


def view_main(argv: Sequence[str] | None = None) -> int:
    """``linkage-view``."""
    p = argparse.ArgumentParser(
        prog="linkage-view",
        description="Turn a recorded MCAP run into the rerun view (from the messages, without "
                    "solving again); works on files cut short by a crash.")
    p.add_argument("mcap", type=Path, help="recorded run (.mcap)")
    p.add_argument("-o", "--output", type=Path, metavar="RUN.rrd",
                   help="rerun file to write (default: next to the MCAP, .rrd)")
    p.add_argument("--spawn", action="store_true", help="show it in a rerun viewer")
    args = p.parse_args(argv)
    if not _have_rerun():
        _err(NO_RERUN)
        return EXIT_USAGE
    from linkage_ros.record.replay import run_data_from_mcap
    from linkage_ros.record.rerun import write_rrd

    try:
        data, contents = run_data_from_mcap(args.mcap)
    except (OSError, ValueError, KeyError) as exc:
        _err(f"{args.mcap}: {exc}")
        return EXIT_USAGE
    out = args.output or (None if args.spawn else args.mcap.with_suffix(".rrd"))
    try:
        write_rrd(data, out, spawn=args.spawn)
    except RuntimeError as exc:
        _err(str(exc))
        return EXIT_ERROR
    state = "finished" if contents.complete else "cut short (no footer), read up to the last chunk"
    print(f"{args.mcap}: {state}; {contents.message_count} messages, {data.n} ticks, "
          f"t = {data.t[0] if data.n else 0:g} … {data.t[-1] if data.n else 0:g} s")
    if out is not None:
        print(f"rerun: {out}")
    return EXIT_OK


def mcap_main(argv: Sequence[str] | None = None) -> int:
    """``linkage-mcap``."""
    p = argparse.ArgumentParser(prog="linkage-mcap", description="Inspect and repair MCAP runs.")
    sub = p.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("recover", help="write a valid, finished copy of a file cut short")
    rec.add_argument("broken", type=Path)
    rec.add_argument("fixed", type=Path)
    info = sub.add_parser("info", help="topics, counts and whether the file was finished")
    info.add_argument("file", type=Path)
    args = p.parse_args(argv)
    from linkage_ros.record.mcap import read_mcap, recover

    try:
        if args.command == "recover":
            contents = recover(args.broken, args.fixed)
            lost = contents.size - contents.valid_bytes
            print(f"{args.fixed}: {len(contents.messages)} messages on "
                  f"{len(contents.channels)} topics recovered "
                  f"({'the file was finished' if contents.complete else f'{lost} bytes cut'})")
            return EXIT_OK
        contents = read_mcap(args.file)
    except (OSError, ValueError) as exc:
        _err(str(exc))
        return EXIT_USAGE
    header = contents.header
    print(f"{args.file}: profile {header.profile if header else '?'}, "
          f"library {header.library if header else '?'}")
    print("finished (footer present)" if contents.complete else
          f"NOT finished: readable up to byte {contents.valid_bytes} of {contents.size}; "
          "run `linkage-mcap recover` before `ros2 bag play`")
    counts: dict[str, int] = {}
    for m in contents.messages:
        counts[m.topic] = counts.get(m.topic, 0) + 1
    times = [m.log_time for m in contents.messages]
    if times:
        print(f"{len(times)} messages, t = {min(times) / 1e9:g} … {max(times) / 1e9:g} s")
    for topic, typename in contents.topics().items():
        print(f"  {topic:40s} {typename:40s} {counts.get(topic, 0)}")
    return EXIT_OK
