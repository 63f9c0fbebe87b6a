"""Command-line tools that need no ROS: ``linkage-run``, ``linkage-view``, ``linkage-mcap``.

* ``linkage-run SCENE``: run the node's engine on simulated time, write the MCAP recording and
  the rerun recording, print a summary per output.
* ``linkage-view RUN.mcap``: the same rerun view from the recorded messages (also from a file
  cut short by a crash).
* ``linkage-mcap recover BROKEN.mcap FIXED.mcap`` and ``linkage-mcap info RUN.mcap``.

Each ``*_main`` returns the exit status (0 ok, 1 runtime error, 2 bad input, 130 interrupted,
141 when the reader of its output went away, e.g. ``| head``). A bad command line, scene or
output path is one line on stderr. Only the default ``runs/`` folder is created; an explicit
output path must be a file name in an existing folder.

``linkage-run`` is written here; ``linkage-view`` and ``linkage-mcap`` (the commands on a recorded
file) in :mod:`linkage_ros._cli_recorded`, what the three share in :mod:`linkage_ros._cli_common`.
Every command is imported from here (the console scripts name ``linkage_ros.cli``).
"""

from __future__ import annotations

import argparse
import math
import os
import shutil
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from solver._cmdline import (
    EPSILON_MAX,
    OMEGA_MAX,
    PHI_MAX,
    Parser,
    bounded,
    check_output,
    positive,
    quiet_pipe,
)

from ._cli_common import EXIT_ERROR, EXIT_INTERRUPTED, EXIT_OK, EXIT_USAGE, NO_RERUN, err, os_error, show, spawn_file
from ._cli_common import have_rerun as _have_rerun  # looked up here at each run (tests replace it)
from ._cli_recorded import mcap_main, view_main

if TYPE_CHECKING:  # for the annotation; imported where used, when a run has loads
    from .forces import LoadArrows

__all__ = ["mcap_main", "rerun_command", "run_main", "view_main"]

RUNS_DIR = Path("runs")
MAX_TICKS = 10_000_000
"""Most ticks of one run (every tick is kept in memory for the rerun view and the summary)."""


def _law(limit: float) -> Any:
    """An argument type for ``--omega``/``--epsilon``/``--phi0``: a plain number (checked here,
    with the messages of :func:`bounded`), or ``Q=V`` for one input (kept as text, checked against
    the scene's inputs by :func:`solver.cli_inputs.per_input_values` once the scene is loaded)."""
    plain = bounded(limit)

    def parse(text: str) -> float | str:
        return text if "=" in text else plain(text)

    parse.__name__ = "number"
    return parse


#: linkage-run's defaults of the motion law (every input of a several-input scene alike).
LAW_DEFAULTS = {"--omega": (2 * math.pi, OMEGA_MAX), "--epsilon": (0.0, EPSILON_MAX), "--phi0": (0.0, PHI_MAX),
                "--omega0": (0.0, OMEGA_MAX)}
#: An actuator's stroke extends from its closed length at this rate (m/s) unless told otherwise.
STROKE_RATE = 0.1
STROKE_DEFAULTS: dict[str, Callable[[tuple[float, float]], float]] = {
    "--omega": lambda r: STROKE_RATE, "--epsilon": lambda r: 0.0, "--phi0": lambda r: r[0], "--omega0": lambda r: 0.0}


def _laws(scene: Any, args: argparse.Namespace) -> dict[str, tuple[float, ...]]:
    """Per input (in the order of ``scene.inputs``) φ0, ω, ε from the command line: the last plain
    value of an option applies to every input, ``Q=V`` items then set input Q (repeatable, as for
    ``linkage-solve``; docs/inputs.md). One value per input; one input: a 1-tuple."""
    from solver.cli_inputs import per_input_values

    out: dict[str, tuple[float, ...]] = {}
    inputs = tuple(getattr(scene, "inputs", (scene.input_joint,)))
    ranges = tuple(getattr(scene, "input_ranges", ())) or (None,) * len(inputs)
    for option, attr in (("--phi0", "phi0"), ("--omega", "omega"), ("--epsilon", "epsilon"), ("--omega0", "omega0")):
        default, limit = LAW_DEFAULTS[option]
        items = getattr(args, attr, [])
        plain = [v for v in items if isinstance(v, float)]
        named = [v for v in items if isinstance(v, str)]
        # each input's own default: an actuator starts closed and extends at STROKE_RATE
        own = [default if r is None else STROKE_DEFAULTS[option](r) for r in ranges]
        base = (plain[-1],) * len(inputs) if plain else tuple(own)
        if not named:
            out[attr] = base
        else:
            values = per_input_values(scene, named, option=option, default=math.nan, limit=limit)
            out[attr] = tuple(b if math.isnan(v) else float(v) for v, b in zip(values, base))
    return out


def _run_parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="linkage-run",
        description="Run a mechanism on simulated time without ROS: record the node's topics "
                    "to MCAP (rosbag2 profile) and the motion to a rerun recording.")
    p.add_argument("scene", help="scene file, or the name of a shipped scene (e.g. harvester_finger)")
    span = p.add_mutually_exclusive_group()
    span.add_argument("--duration", type=positive, metavar="S",
                      help="simulated seconds (> 0; default: the time of --cycles 1, or 5 s with --dynamics)")
    span.add_argument("--cycles", type=positive, metavar="N",
                      help="turns of the input, or full strokes of an actuator (> 0; default 1 when --duration "
                           "is not given)")
    p.add_argument("--rate", type=positive, default=100.0, metavar="HZ", help="ticks per second (100)")
    p.add_argument("--omega", type=_law(OMEGA_MAX), action="append", default=[], metavar="W|Q=W",
                   help="input angular velocity, rad/s (2π: one turn per second; an actuator's stroke: m/s, "
                        "0.1); with several inputs repeat Q=W per input (a plain W applies to every input)")
    p.add_argument("--epsilon", type=_law(EPSILON_MAX), action="append", default=[], metavar="E|Q=E",
                   help="input angular acceleration, rad/s² (0); Q=E per input as for --omega")
    p.add_argument("--phi0", type=_law(PHI_MAX), action="append", default=[], metavar="RAD|Q=RAD",
                   help="input angle at t = 0 (0; an actuator's stroke: m, its closed length); Q=RAD per "
                        "input as for --omega")
    p.add_argument("--points", metavar="P,Q", help="published points (default: the scene's outputs)")
    p.add_argument("--on-unassemblable", choices=("stop", "reverse"), default="stop",
                   help="where the mechanism cannot be assembled: hold the last valid position, or reverse the "
                        "input (default stop)")
    p.add_argument("--mcap", type=Path, metavar="FILE",
                   help="MCAP output (default runs/<scene>-<time>.mcap)")
    p.add_argument("--rrd", type=Path, metavar="FILE",
                   help="rerun output (default runs/<scene>-<time>.rrd)")
    p.add_argument("--no-mcap", action="store_true", help="do not write the MCAP file")
    p.add_argument("--no-rrd", action="store_true", help="do not write the rerun file")
    p.add_argument("--spawn", action="store_true",
                   help="also show the run in a rerun viewer (where there is a display)")
    p.add_argument("--frame-id", default="world", help="frame of the published points and markers (default "
                                                       "world)")
    p.add_argument("--namespace", default="/", help="node namespace of the recorded topics (/)")
    p.add_argument("--chunk-interval", type=positive, default=1.0, metavar="S",
                   help="close and flush an MCAP chunk at least this often (1 s)")
    p.add_argument("--no-fast", action="store_true",
                   help="build and serialise every message through the builder (slower)")
    dyn = p.add_argument_group("dynamics (issue 22: the motion from the equation of motion, docs/dynamics.md)")
    dyn.add_argument("--dynamics", action="store_true",
                     help="integrate the inputs from --phi0 and --omega0 under the drive and the loads "
                          "instead of prescribing ω and ε; prints the run-up, ω, δ, the drive's peaks and "
                          "the energy balance, and plots the energies")
    dyn.add_argument("--omega0", type=_law(OMEGA_MAX), action="append", default=[], metavar="W|Q=W",
                     help="with --dynamics: input rate at t = 0, rad/s (an actuator's stroke: m/s) (0); Q=W per "
                          "input as for --omega")
    dyn.add_argument("--drive", metavar="free|motor|EFFORT",
                     help="with --dynamics: free, motor, or a constant effort in N·m (N for an actuator's "
                          "stroke or a slide; several inputs: one per input, comma-separated); default: the "
                          "scene's motor, else free")
    dyn.add_argument("--tolerance", type=positive, default=1e-9, metavar="TOL",
                     help="with --dynamics: the integrator's rtol = atol (1e-9)")
    return p


def _dynamic_options(args: argparse.Namespace) -> None:
    """The options that go with ``--dynamics`` and those that do not; ValueError: one line."""
    if not args.dynamics:
        used = [o for o, v in (("--omega0", args.omega0), ("--drive", args.drive)) if v]
        if used:
            raise ValueError(f"{', '.join(used)}: only with --dynamics (a kinematic run takes --omega and --epsilon)")
        return
    if args.cycles is not None:
        raise ValueError("--cycles does not go with --dynamics (the turns follow from the motion): give --duration S")
    used = [o for o, v in (("--omega", args.omega), ("--epsilon", args.epsilon)) if v]
    if used:
        raise ValueError(f"{', '.join(used)}: the kinematic law; with --dynamics the motion follows from the "
                         "equation of motion (the initial rate: --omega0)")


def _run_outputs(args: argparse.Namespace, stem: str) -> tuple[Path | None, Path | None]:
    """The MCAP and rerun paths: explicit ones checked (no folder created), defaults under runs/."""
    mcap = None if args.no_mcap else args.mcap
    rrd = None if args.no_rrd else args.rrd
    for path, flag in ((mcap, "--mcap"), (rrd, "--rrd")):
        if path is not None:
            check_output(path, flag)
    if mcap is not None and rrd is not None and Path(mcap).resolve() == Path(rrd).resolve():
        raise ValueError(f"--mcap and --rrd name the same file {mcap}")
    if (not args.no_mcap and mcap is None) or (not args.no_rrd and rrd is None):
        if RUNS_DIR.exists() and not RUNS_DIR.is_dir():
            raise ValueError(f"{RUNS_DIR} is a file, not the folder for the default outputs")
    if not args.no_mcap and mcap is None:
        mcap = RUNS_DIR / f"{stem}.mcap"
    if not args.no_rrd and rrd is None:
        rrd = RUNS_DIR / f"{stem}.rrd"
    return mcap, rrd


def _duration(args: argparse.Namespace, laws: dict[str, tuple[float, ...]], duration_for_cycles: Any,
              inputs: Sequence[str] = (), ranges: Sequence[Any] = ()) -> float:
    """``--duration``, else the time of ``--cycles`` turns (default 1; an actuator's cycle is its
    whole stroke, ``ranges``); with several inputs, of the input that completes them first (the
    fastest; docs/recording.md)."""
    if args.duration is not None:
        return float(args.duration)
    cycles = args.cycles if args.cycles is not None else 1.0
    turning = [(w, e) for w, e in zip(laws["omega"], laws["epsilon"]) if w != 0.0 or e != 0.0]
    if not turning:
        what = f"--cycles {args.cycles:g}" if args.cycles is not None else "the default one turn"
        if len(laws["omega"]) > 1:
            raise ValueError(f"with ω = 0 and ε = 0 for every input ({', '.join(inputs)}) no input turns, so "
                             f"{what} never ends: give --duration S (or a non-zero --omega / --epsilon)")
        raise ValueError(f"with --omega 0 and --epsilon 0 the input never turns, so {what} never ends: "
                         "give --duration S (or a non-zero --omega / --epsilon)")
    spans = {i: r[1] - r[0] for i, r in enumerate(ranges) if r is not None}  # a cycle of a stroke: the stroke
    return min(float(duration_for_cycles(cycles, w, e, span=spans.get(i, 2 * math.pi)))
               for i, (w, e) in enumerate(zip(laws["omega"], laws["epsilon"])) if w != 0.0 or e != 0.0)


def _check_ticks(duration: float, rate: float) -> int:
    """The ticks of a run of ``duration`` s at ``rate`` Hz; ValueError beyond :data:`MAX_TICKS`."""
    ticks = math.floor(duration * rate * (1 + 1e-12)) + 1
    if ticks > MAX_TICKS:
        raise ValueError(f"{duration:g} s at {rate:g} Hz is {ticks:,} ticks: at most {MAX_TICKS:,} "
                         "in one run (a shorter --duration or a lower --rate)")
    return ticks


def _start_line(scene: Any, duration: float, rate: float, ticks: int, laws: dict[str, tuple[float, ...]]) -> str:
    """The run's first line: time, ticks and each input's law."""
    from solver.summary import motion_line

    head = f"scene {scene.name}: {duration:g} s of simulated time at {rate:g} Hz ({ticks} ticks), "
    units = tuple(getattr(scene, "input_units", ())) or ("rad",) * len(laws["omega"])

    def start(p: float, unit: str) -> str:  # an angle in degrees, an actuator's stroke in m
        return f"s0 = {p:g} m" if unit == "m" else f"φ0 = {math.degrees(p):g}°"

    if len(laws["omega"]) == 1:
        return head + (f"input '{scene.input_joint}' from {start(laws['phi0'][0], units[0])}; "
                       f"{motion_line(laws['omega'][0], laws['epsilon'][0], units[0])}")
    each = "; ".join(
        f"'{q}' from {start(p, u)}, {motion_line(w, e, u).split('; angles')[0]}"
        for q, p, w, e, u in zip(scene.inputs, laws["phi0"], laws["omega"], laws["epsilon"], units))
    return head + f"{len(scene.inputs)} inputs: {each}; angles in degrees, everything else SI"


def _dynamic_start_line(scene: Any, duration: float, rate: float, ticks: int, start: dict[str, Any]) -> str:
    """A dynamic run's first line: time, ticks and each input's initial state."""
    def each_start(q: str, p: float, w: float) -> str:  # an angle in degrees, an actuator's stroke in m
        if scene.joint_units.get(q, "rad") == "m":
            return f"'{q}' from s0 = {p:g} m, ṡ0 = {w:g} m/s"
        return f"'{q}' from φ0 = {math.degrees(p):g}°, ω0 = {w:g} rad/s"

    each = "; ".join(each_start(q, float(p), float(w))
                     for q, p, w in zip(scene.inputs, *(np.atleast_1d(start[k]) for k in ("phi0", "omega0"))))
    return (f"scene {scene.name}: {duration:g} s of simulated time at {rate:g} Hz (up to {ticks} ticks), the "
            f"motion from the equation of motion: {each}; angles in degrees, everything else SI")


def _load_rule(scales: dict[str, float]) -> LoadArrows:
    """The load arrows' rule from a run's arrow scales (``load``, and ``load_knee`` with a knee,
    ``load_decade`` where a tenfold adds less than a knee length)."""
    from .forces import LoadArrows

    return LoadArrows(scales["load"], scales.get("load_knee", math.inf), decade=scales.get("load_decade"))


@quiet_pipe
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
        err(f"{exc}; install the record extra: pip install 'linkage_ros[record]'", "linkage-run")
        return EXIT_ERROR
    points = [p.strip() for p in args.points.split(",") if p.strip()] if args.points else None
    try:  # everything the command line says is checked before the run starts
        if args.duration is not None:
            _check_ticks(args.duration, args.rate)
        _dynamic_options(args)
        scene = solver.load_scene(args.scene)
        laws = _laws(scene, args)
        if args.dynamics:
            from linkage_ros.record.dynamic_run import DEFAULT_DURATION, parse_drive

            duration = float(args.duration) if args.duration is not None else DEFAULT_DURATION
            drive = parse_drive(args.drive, tuple(scene.inputs))
        else:
            duration = _duration(args, laws, duration_for_cycles, tuple(getattr(scene, "inputs", ())),
                                 tuple(getattr(scene, "input_ranges", ())))
        ticks = _check_ticks(duration, args.rate)
        for p in points or ():
            if p not in scene.point_names:
                raise ValueError(f"--points: '{p}' is not a point of {scene.name}; "
                                 f"points: {', '.join(scene.point_names)}")
        stem = f"{scene.name.replace('/', '_')}-{time.strftime('%Y%m%d-%H%M%S')}"
        mcap, rrd = _run_outputs(args, stem)
    except (solver.SolverError, ValueError) as exc:
        err(str(exc), "linkage-run")
        return EXIT_USAGE
    except OSError as exc:
        err(os_error(exc), "linkage-run")
        return EXIT_USAGE
    if (rrd is not None or args.spawn) and not _have_rerun():
        if args.rrd is not None or args.spawn:
            err(NO_RERUN, "linkage-run")
            return EXIT_USAGE
        print(f"note: {NO_RERUN}; no .rrd written", file=sys.stderr)
        rrd = None
    for default in (mcap, rrd):
        if default is not None and default.parent == RUNS_DIR:
            RUNS_DIR.mkdir(exist_ok=True)  # the one folder made on the user's behalf
    one = len(laws["omega"]) == 1
    shown = spawn_file(rrd, stem) if args.spawn else rrd  # the viewer opens a file
    opts = RunOptions(
        scene=args.scene, duration=duration, rate=args.rate,
        omega=laws["omega"][0] if one else laws["omega"],
        epsilon=laws["epsilon"][0] if one else laws["epsilon"],
        phi0=laws["phi0"][0] if one else laws["phi0"], mcap=mcap, rrd=shown, spawn=False,
        points=points, on_unassemblable=args.on_unassemblable, frame_id=args.frame_id,
        namespace=args.namespace, chunk_interval_s=args.chunk_interval, fast=not args.no_fast)
    trajectory = None
    if args.dynamics:  # the motion from the equation of motion (linkage_ros.record.dynamic_run)
        from linkage_ros.record.dynamic_run import law_of, simulate_ticks

        start = {name: laws[name][0] if one else list(laws[name]) for name in ("phi0", "omega0")}
        try:
            trajectory = simulate_ticks(scene, duration=duration, rate=args.rate, phi0=start["phi0"],
                                        omega0=start["omega0"], drive=drive, tolerance=args.tolerance)
        except solver.SolverError as exc:
            err(str(exc), "linkage-run")
            return EXIT_USAGE
        opts.scene, opts.law, opts.energy = scene, law_of(trajectory), trajectory.energy()  # type: ignore[assignment]
        opts.duration = duration if trajectory.status == "done" else float(trajectory.t[-1])
        print(_dynamic_start_line(scene, duration, args.rate, ticks, start), flush=True)
    else:
        print(_start_line(scene, duration, args.rate, ticks, laws), flush=True)
    tty = sys.stderr if sys.stderr.isatty() else None
    try:
        result = run_standalone(opts, progress=tty)
    except (solver.SolverError, ValueError, KeyError) as exc:
        err(str(exc), "linkage-run")
        return EXIT_USAGE
    except OSError as exc:
        err(os_error(exc), "linkage-run")
        return EXIT_ERROR
    except RuntimeError as exc:
        err(str(exc), "linkage-run")
        return EXIT_ERROR
    data = result.data
    outputs = tuple(points or scene.output_points)
    from linkage_ros.record.forces import force_sections  # scenes with forces: their lines

    for line in summary_lines(data, outputs, tuple(scene.output_joints), scene.joint_units,
                              descriptions=getattr(scene, "descriptions", {}), inputs=tuple(scene.inputs),
                              sections=force_sections(scene, data)):
        print(line)
    if trajectory is not None:
        from linkage_ros.record.dynamic_run import dynamics_lines

        for line in dynamics_lines(scene, trajectory, phi0=laws["phi0"][0]):
            print(line)
    if set(result.statuses) - {"ok"}:
        print("status: " + ", ".join(f"{k}: {v} ticks" for k, v in sorted(result.statuses.items())))
    secs = result.seconds
    if mcap is not None:
        print(f"mcap: {mcap} ({result.messages} messages)")
    if rrd is not None:
        print(f"rerun: {rrd}  (view: {rerun_command()} {rrd})")
    if result.arrow_scales:
        sv, sa = result.arrow_scales["velocity"], result.arrow_scales["acceleration"]
        print(f"arrows in the rerun view: velocity drawn as v × {sv:g} s (1 m/s is an arrow {sv:g} m long), "
              f"acceleration as a × {sa:g} s² (1 m/s² is {sa:g} m long)"
              + (f", pin loads as R {_load_rule(result.arrow_scales).describe()}"
                 if "load" in result.arrow_scales else ""))
    simulated = float(data.t[-1] - data.t[0]) if data.n else 0.0
    print(f"{result.ticks} ticks in {secs['total']:.2f} s of wall-clock time ({simulated:g} s simulated)")
    if result.interrupted:
        print(f"interrupted at t = {data.t[-1] if data.n else 0.0:g} s; files finished",
              file=sys.stderr)
        return EXIT_INTERRUPTED
    if args.spawn and shown is not None:
        show(shown, "linkage-run")
    return EXIT_OK


def rerun_command(*, executable: str | None = None, cwd: Path | None = None) -> str:
    """How to start the rerun viewer from the user's shell: ``rerun`` when PATH finds the one
    next to this Python (an activated venv) or there is none there, else that one's path,
    relative to ``cwd`` when below it (``.venv/bin/rerun`` from a clone, as README.md writes)."""
    here = Path(executable or sys.executable).parent / "rerun"  # not resolved: a venv's python is a link
    if not os.access(here, os.X_OK):
        return "rerun"
    found = shutil.which("rerun")
    if found is not None and Path(found).resolve() == here.resolve():
        return "rerun"
    base = Path.cwd() if cwd is None else cwd
    return str(here.relative_to(base)) if here.is_relative_to(base) else str(here)
