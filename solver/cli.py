"""``linkage-solve``: sweep a scene over the crank angle and print a summary or write a CSV.

A scene driven by an actuator is swept over its stroke instead (both ends included, in m;
``--range LO:HI`` narrows it, ``--phi`` gives strokes in m, ``--omega``/``--epsilon`` are m/s and
m/s²); its CSV's first column is named by the input (m), and every stroke in the summary is in m.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from typing import Any, TextIO

import numpy as np

from . import assembly, classify
from ._cmdline import (
    EPSILON_MAX,
    OMEGA_MAX,
    PHI_MAX,
    Parser,
    bounded,
    check_output,
    count,
    error_line,
    quiet_pipe,
)
from ._extremes import Evaluate
from .cli_inputs import force_columns, force_table, help_epilog, is_multi_input, per_input_values
from .cli_inputs import main as main_inputs
from .errors import SolverError, format_intervals
from .forces.report import force_section
from .kinematics import Kinematics
from .scene import Scene, load_scene
from .structure_cli import structure_main
from .summary import Output, Section, Sweep, motion_line, provenance_lines, summary_lines

__all__ = ["main", "csv_header", "write_csv", "summary", "stability_lines"]

AXES = "xyz"
#: Options of the several-input form only (solver/cli_inputs.py): named as such for a one-input scene.
SEVERAL_INPUTS_ONLY = ("--samples", "--region", "--derivatives")


def _parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="linkage-solve",
        description="Exact kinematics of a linkage scene over one turn of its input (or given angles).",
        epilog=help_epilog(),
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("scene", help="scene file, or the name of a shipped scene (e.g. harvester_finger)")
    grid = p.add_mutually_exclusive_group()
    grid.add_argument("--phi-count", type=count, default=360, metavar="N",
                      help="N angles over one turn (default 360; --count N the same, as for several inputs)")
    grid.add_argument("--count", type=count, dest="phi_count", default=argparse.SUPPRESS, help=argparse.SUPPRESS)
    grid.add_argument("--phi", type=_floats, metavar="V1,V2,...",
                      help="these input angles (rad, or deg with --deg); an actuator's strokes in m")
    p.add_argument("--deg", action="store_true", help="--phi values are in degrees (the summary always shows degrees; "
                   "the CSV's phi column stays in rad, like every column SI)")
    p.add_argument("--range", action="append", default=[], metavar="LO:HI",
                   help="an actuator's strokes to sweep, m, from LO to HI (LO < HI), both ends included "
                   "(default its whole stroke); for several inputs Q=LO:HI, see below")
    p.add_argument(
        "--omega", type=_rate(OMEGA_MAX), default=None, metavar="W|Q=W",
        help="input angular velocity, rad/s (an actuator's stroke: m/s) (default 1: velocities and accelerations "
        "then equal the analogs d/dφ, d²/dφ²; forces include inertia at 1 rad/s, --omega 0 for statics); Q=W names "
        "the input, as "
        "linkage-run reads it",
    )
    p.add_argument(
        "--epsilon",
        type=_rate(EPSILON_MAX),
        default=0.0,
        metavar="E|Q=E",
        help="input angular acceleration, rad/s² (an actuator's stroke: m/s²) (default 0); Q=E names the input",
    )
    p.add_argument("--csv", metavar="FILE|-", help="write the table as CSV (SI units, phi in rad) to FILE or stdout; "
                   "a scene with forces adds each input's effort and every pin's load")
    p.add_argument("--structure", action="store_true",
                   help="print the decomposition instead: the groups in order with their modes and lengths, and the "
                   "mobility count (a drawn scene: also as drawn)")
    p.add_argument(
        "--mask",
        action="store_true",
        help="where the mechanism cannot be assembled, leave those angles out instead of failing",
    )
    return p


def _rate(limit: float) -> Any:
    """A rate as a number, or ``Q=V`` kept as text until the scene names its input (linkage-run's form)."""
    number = bounded(limit)

    def parse(text: str) -> float | str:
        return text if "=" in text else number(text)

    return parse


def _one_rate(scene: Scene, value: float | str, *, option: str, default: float, limit: float) -> float:
    if not isinstance(value, str):
        return value
    return float(per_input_values(scene, [value], option=option, default=default, limit=limit)[0])


def _floats(text: str) -> list[float]:
    try:
        values = [bounded(PHI_MAX)(v) for v in text.split(",") if v.strip()]
    except argparse.ArgumentTypeError as exc:
        raise argparse.ArgumentTypeError(f"not a comma-separated list of finite numbers: {text!r} ({exc})") from None
    if not values:
        raise argparse.ArgumentTypeError("give at least one angle")
    return values


def csv_header(scene: Scene) -> list[str]:
    cols = [_input_column(scene)]
    axes = AXES[: scene.dim]
    for p in scene.output_points:
        for prefix in ("", "v", "a"):
            cols += [f"{p}.{prefix}{a}" for a in axes]
    for j in scene.output_joints:
        cols += [f"{j}.q", f"{j}.dq", f"{j}.ddq"]
    return cols + force_columns(scene)


def _input_column(scene: Scene) -> str:
    """``phi`` (rad) for a crank, the input's own name for an actuator's stroke (m)."""
    return scene.input_joint if scene.input_units[0] == "m" else "phi"


def _stroke(scene: Scene) -> bool:
    return scene.input_units[0] == "m"


def _at(scene: Scene, values: Sequence[float]) -> str:
    """``φ = 12.0000°, …`` or, for a stroke, ``s = 0.8000 m, …``."""
    if _stroke(scene):
        return "s = " + ", ".join(f"{v:.4f} m" for v in values)
    return f"φ = {_degrees(values)}"


def stroke_grid(scene: Scene, ranges: Sequence[str], count: int) -> np.ndarray:
    """The strokes to sweep (m): ``count`` over the stroke, or over ``--range LO:HI`` (or
    ``Q=LO:HI``), both ends included."""
    lo, hi = scene.input_ranges[0] or (0.0, 0.0)
    for item in ranges:
        name, sep, span = item.rpartition("=")
        a, colon, b = span.partition(":")
        if (sep and name != scene.input_joint) or not colon:
            raise SolverError(f"--range {item!r}: give LO:HI (m) or {scene.input_joint}=LO:HI")
        try:
            lo, hi = bounded(PHI_MAX)(a), bounded(PHI_MAX)(b)
        except argparse.ArgumentTypeError as exc:
            raise SolverError(f"--range {item!r}: {exc}") from None
        if not lo < hi:
            raise SolverError(f"--range {item!r}: LO must be less than HI (the sweep runs from LO to HI, both "
                              "included; for the other direction read the table from its end)")
    return np.linspace(lo, hi, count)


def table(scene: Scene, k: Kinematics) -> np.ndarray:
    """The CSV's columns as one (N, columns) array."""
    cols: list[np.ndarray] = [k.phi[:, None]]
    for p in scene.output_points:
        m = k.point(p)
        cols += [m.position, m.velocity, m.acceleration]
    for j in scene.output_joints:
        m = k.joint(j)
        cols += [m.position[:, None], m.velocity[:, None], m.acceleration[:, None]]
    return np.hstack(cols + force_table(scene, k))


def write_csv(scene: Scene, k: Kinematics, out: TextIO) -> None:
    out.write(",".join(csv_header(scene)) + "\n")
    data = table(scene, k)[k.valid]
    np.savetxt(out, data, delimiter=",", fmt="%.17g")


def summary(
    scene: Scene,
    k: Kinematics,
    *,
    deg: bool = True,
    periodic: bool = False,
    given: bool = False,
    sections: Sequence[Section] = (),
) -> str:
    """The summary of a sweep (solver.summary: one vocabulary with linkage-run, angles in
    degrees, extremes refined to the closed form), then the singular positions, dead centres,
    transmission angles and gaps, then ``sections``. ``periodic``: the samples are one whole turn
    (a joint's net rotation includes the step back to the start; extremes refined across it);
    ``given``: the angles are the user's own (``--phi``): extremes are those of these angles,
    not refined between them; ``deg`` is kept for callers of the old signature (angles are
    always in degrees)."""
    valid = np.asarray(k.valid, bool)
    phi = k.phi[valid]
    w = float(k.omega.flat[0]) if k.omega.size else 0.0
    e = float(k.epsilon.flat[0]) if k.epsilon.size else 0.0
    unit = scene.input_units[0]
    span = " over one turn" if periodic else " over its stroke" if unit == "m" and not given else ""
    lines = [f"scene {scene.name}: {len(phi)} positions{span} of the input '{scene.input_joint}'; "
             f"{motion_line(w, e, unit)}"]
    lines += provenance_lines(scene.provenance)
    desc = getattr(scene, "descriptions", {})
    # the samples of a sweep in increasing φ can be refined between neighbours; given angles cannot
    ordered = not given and len(phi) > 1 and bool(np.all(np.diff(k.phi) > 0))

    def output(name: str, m: Any, unit: str = "m", point: bool = True) -> Output:
        evaluate = _evaluator(scene, name, point=point, omega=w, epsilon=e) if ordered else None
        return Output(name, m.position[valid], m.velocity[valid], m.acceleration[valid], unit, desc.get(name, ""),
                      evaluate)

    points = [output(p, k.point(p)) for p in scene.output_points]
    joints = [output(j, k.joint(j), scene.joint_units.get(j, "rad"), False) for j in scene.output_joints]
    idx = np.flatnonzero(valid)
    gaps = np.diff(idx, append=idx[-1] + 1 if idx.size else 0) > 1
    if periodic and idx.size and (idx[0] != 0 or idx[-1] != len(valid) - 1):
        gaps[-1] = True  # the step from the last sample round to the first crosses a gap
    sweep = Sweep(phi=phi, points=points, joints=joints, periodic=periodic and bool(valid.all()),
                  inputs=tuple(scene.inputs) if len(phi) else (), wraps=periodic, gaps=gaps,
                  edges=_gap_edges(scene, phi) if gaps.any() and ordered else None,
                  sampling=(f"the samples (every {360.0 / len(valid):.4g}°)" if periodic
                            else None if ordered else "the given angles"), units=scene.input_units)
    lines += summary_lines(sweep)
    lines.extend(stability_lines(scene, k))
    for section in sections:
        lines += section(sweep)
    return "\n".join(lines)


def _gap_edges(scene: Scene, phi: np.ndarray) -> np.ndarray:
    """(N, 2): for each sample the exact φ where the nearest unassemblable interval before it
    ends and the nearest one after it begins (solver.assembly), unwrapped next to the sample."""
    intervals = [iv for ivs in assembly.gaps(scene).values() for iv in ivs]
    out = np.full((len(phi), 2), np.nan)
    if not intervals:
        return out
    starts = np.array([lo for lo, _ in intervals])
    stops = np.array([hi for _, hi in intervals])
    two_pi = 2.0 * math.pi
    if _stroke(scene):  # strokes do not wrap
        ahead = np.where(starts[None, :] >= phi[:, None], starts[None, :] - phi[:, None], np.inf).min(axis=1)
        behind = np.where(stops[None, :] <= phi[:, None], phi[:, None] - stops[None, :], np.inf).min(axis=1)
    else:
        ahead = np.mod(starts[None, :] - phi[:, None], two_pi).min(axis=1)
        behind = np.mod(phi[:, None] - stops[None, :], two_pi).min(axis=1)
    out[:, 0], out[:, 1] = phi - behind, phi + ahead
    return out


def _evaluator(scene: Scene, name: str, *, point: bool, omega: float, epsilon: float) -> Evaluate:
    """``name`` at any φ from the closed form (NaN where not assemblable): refines extremes."""
    one = scene.with_outputs(points=(name,) if point else (), joints=() if point else (name,))

    def evaluate(phi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        k = one.solve(phi, omega=omega, epsilon=epsilon, mask=True)
        m = k.point(name) if point else k.joint(name)
        bad = ~np.asarray(k.valid, bool)
        out = tuple(np.array(a, float) for a in (m.position, m.velocity, m.acceleration))
        for a in out:
            a[bad] = np.nan
        return out[0], out[1], out[2]

    return evaluate


def _degrees(values: Sequence[float]) -> str:
    return ", ".join(f"{math.degrees(v):.4f}°" for v in values)


def stability_lines(scene: Scene, k: Kinematics) -> list[str]:
    """Singular positions, dead centres, transmission angles, Grashof class and gaps.

    Named as docs/stability.md defines them: a *singular position* is one where a group's
    conditioning is 0 (its linear system is singular): a *change point* (both assemblies meet)
    or a toggle at the edge of an unassemblable range; a *dead centre* is a regular position
    where an output joint stands still (dq/dφ = 0, a rocker's or slider's extreme position).
    Every angle is computed over the whole turn in closed form or by bisection to rounding
    (solver.classify), not read off the sampled sweep.
    """
    lines: list[str] = []
    singular: list[str] = []
    for g in scene.plan.groups:
        for kind, where in classify.toggles(scene, g).items():
            what = {
                "change points": "change points (both assemblies meet; conditioning 0)",
                "range edges": "toggles at the edges of the unassemblable range (conditioning 0)",
            }[kind]
            singular.append(f"    {g.name}: {what} at {_at(scene, where)}")
    centres: list[str] = []
    for j in scene.output_joints:
        if j == scene.input_joint:
            continue
        stops = classify.dead_centres(scene, j)
        if stops:
            derivative = "dq/ds" if _stroke(scene) else "dq/dφ"
            centres.append(f"    {j}: dead centre ({derivative} = 0) at {_at(scene, stops)}")
    flagged = int(np.count_nonzero(k.singular & k.valid))
    over = "over the stroke" if _stroke(scene) else "over the turn"
    lines.append(f"  singular positions {over}, a group's conditioning 0 ({flagged} of the samples singular):")
    lines.extend(singular or ["    none"])
    if centres:
        lines.append(f"  dead centres {over} (an output joint at rest, its extreme position; not singular):")
        lines.extend(centres)
    for g in scene.plan.groups:
        mu = classify.transmission_range(scene, g)
        if mu is not None:
            dyad: Any = g  # an RRR dyad (transmission_range is None for any other group)
            a, c = dyad.ends
            b = dyad.point
            lines.append(
                f"  transmission angle of {g.name} (between {_link(a, b)} and {_link(c, b)}): "
                f"{math.degrees(mu[0]):.4f}° … {math.degrees(mu[1]):.4f}°"
            )
        grashof = classify.grashof(scene, g)
        if grashof is not None:
            lines.append(f"  four-bar {g.name}: {grashof}")
    label = "s" if _stroke(scene) else "φ"
    for name, intervals in assembly.gaps(scene).items():
        lines.append(f"  gap: {name} cannot be assembled for {label} in "
                     f"{format_intervals(intervals, scene.input_units[0])}")
    return lines


def _link(p: str, q: str) -> str:
    """A link by its joints: ``AB`` for one-letter names, ``crank_pin–B`` otherwise."""
    return f"{p}{q}" if len(p) == 1 and len(q) == 1 else f"{p}–{q}"


@quiet_pipe
def main(argv: Sequence[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    if "--structure" in argv:  # the decomposition, not a sweep (solver/structure_cli.py)
        rest = [a for a in argv if a != "--structure"]
        if len(rest) != 1 or rest[0].startswith("-"):
            _parser().error(f"--structure takes the scene alone, got {' '.join(rest) or 'no scene'}")
        return structure_main(rest[0])
    if is_multi_input(argv):  # several inputs: the grid form (solver/cli_inputs.py, docs/inputs.md)
        return main_inputs(argv)
    parser = _parser()
    args, extra = parser.parse_known_args(argv)
    several = next((a.split("=", 1)[0] for a in extra if a.split("=", 1)[0] in SEVERAL_INPUTS_ONLY), None)
    if several is None and extra:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    try:
        if several is not None:
            load_scene(args.scene)  # a scene that does not load says so first
            raise SolverError(f"{several} is an option for scenes with several inputs (e.g. five_bar); {args.scene} "
                              "has one: sweep its input with --phi-count N or --phi V1,V2,... (linkage-solve --help)")
        if args.csv and args.csv != "-":
            check_output(args.csv, "--csv")
        scene = load_scene(args.scene)
        stroke = _stroke(scene)
        if args.range and not stroke:
            raise SolverError(f"--range is an option for scenes with several inputs (e.g. five_bar); {args.scene} "
                              "has one: sweep its input with --phi-count N or --phi V1,V2,... (linkage-solve --help)")
        if stroke and args.deg:
            raise SolverError(f"--deg: the input '{scene.input_joint}' of {args.scene} is an actuator's stroke, in m")
        if stroke and args.phi is not None and args.range:
            raise SolverError("--phi and --range: give the strokes, or their range, not both")
        if args.phi is not None:
            phi = np.radians(args.phi) if args.deg else np.asarray(args.phi, float)
        elif stroke:
            phi = stroke_grid(scene, args.range, args.phi_count)
        else:
            phi = np.linspace(0.0, 2 * math.pi, args.phi_count, endpoint=False)
        omega = _one_rate(scene, 1.0 if args.omega is None else args.omega, option="--omega", default=1.0,
                          limit=OMEGA_MAX)
        epsilon = _one_rate(scene, args.epsilon, option="--epsilon", default=0.0, limit=EPSILON_MAX)
        k = scene.solve(phi, omega=omega, epsilon=epsilon, mask=args.mask)
        if args.csv:
            if args.mask:
                label = "s" if stroke else "φ"
                for name, intervals in assembly.gaps(scene).items():
                    text = format_intervals(intervals, scene.input_units[0])
                    print(f"linkage-solve: gap: {name} cannot be assembled for {label} in {text}", file=sys.stderr)
            flagged = k.phi[np.asarray(k.singular & k.valid)]
            if flagged.size:
                shown = _at(scene, flagged[:8].tolist())
                more = f" and {flagged.size - 8} more" if flagged.size > 8 else ""
                loads = "; efforts and loads there are nan (unbounded)" if scene.has_forces else ""
                print(
                    f"linkage-solve: note: singular position at {shown}{more}: analogs there are the "
                    f"limit along the branch, or nan where none exists{loads} (see docs/stability.md)",
                    file=sys.stderr,
                )
            if args.csv == "-":
                write_csv(scene, k, sys.stdout)
            else:
                with open(args.csv, "w", encoding="utf-8", newline="") as fh:
                    write_csv(scene, k, fh)
        else:
            n = int(np.count_nonzero(k.valid))
            given = None if args.phi is None else "at the given angle" if n == 1 else f"read off the {n} given angles"
            sections = [force_section(scene, k, sampling=given,
                                      default_speed=args.omega is None and args.epsilon == 0.0)]
            print(summary(scene, k, periodic=args.phi is None and not stroke, given=args.phi is not None,
                          sections=sections))
    except BrokenPipeError:
        raise  # the reader went away (`| head`): quiet_pipe ends quietly
    except (SolverError, ValueError, OSError) as exc:
        return error_line("linkage-solve", exc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
