"""``linkage-solve`` for a scene with several inputs (docs/inputs.md).

``linkage-solve SCENE`` dispatches here when the scene has k > 1 inputs. The samples are a grid
over the inputs (``--count N`` values of each over one turn, narrowed by ``--range``) or given
rows (``--samples``); motion laws are per input::

    linkage-solve five_bar --deg --range q1=40:140 --range q2=40:140 --count 11 \\
        --omega q1=2 --omega q2=-1.5 --epsilon q1=0.7 --epsilon q2=3 --csv -
    linkage-solve five_bar --region --count 36            # the assemblable region as a text image

The CSV has one column per input (named by it, rad), then per point ``P.x,P.y,P.vx,…,P.ay`` and
per joint ``J.q,J.dq,J.ddq`` (v = J·ω, a = J·ε + ωᵀHω), with ``--derivatives`` the jacobian
``P.x.d_q1`` … and the hessian ``P.x.d2_q1_q2`` … (upper triangle) of every output, and last, for
a scene with forces, each input's effort and every pin's and slide's load (:func:`force_columns`).
"""

from __future__ import annotations

import argparse
import math
import sys
import textwrap
from collections.abc import Sequence
from typing import TextIO

import numpy as np

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
from .errors import SolverError
from .forces.friction_report import friction_columns, friction_table
from .forces.report import force_section
from .kinematics import Kinematics
from .multi import assemblable
from .scene import Scene, load_scene
from .summary import Output, Section, Sweep, provenance_lines, summary_lines

__all__ = [
    "csv_header",
    "force_columns",
    "force_table",
    "help_epilog",
    "is_multi_input",
    "main",
    "per_input_values",
    "region_lines",
    "samples_of",
]

AXES = "xy"
#: The most samples a grid may have (N^k grows fast; an (N, k) solve keeps every output's arrays).
MAX_SAMPLES = 4_000_000
#: Characters of the region map: assemblable, assemblable but singular, not assemblable.
CELLS = {"ok": "#", "singular": "s", "no": "."}


def _parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="linkage-solve",
        description="Exact kinematics of a linkage scene with several inputs over a grid of its inputs.",
    )
    p.add_argument("scene", help="scene file, or the name of a shipped scene (e.g. five_bar)")
    p.add_argument("--count", "--phi-count", type=count, default=36, metavar="N",
                   help="values of each input on the grid (36)")
    p.add_argument("--range", action="append", default=[], metavar="Q=LO:HI",
                   help="an input's range on the grid, from LO to HI (LO < HI), both ends included (default one "
                   "turn, end excluded; an actuator's whole stroke)")
    p.add_argument("--samples", metavar="Q1,Q2;Q1,Q2;...", help="these rows of input values instead of a grid")
    p.add_argument("--phi", metavar="Q1,Q2,...", help="one instant: one value per input (angles in rad, or deg "
                   "with --deg; an actuator's stroke in m), as --samples Q1,Q2,... is")
    p.add_argument("--deg", action="store_true", help="--range, --samples and --phi angles are in degrees "
                   "(an actuator's stroke stays in m; the CSV's input columns stay in rad, like every column SI)")
    p.add_argument("--omega", action="append", default=[], metavar="W|Q=W",
                   help="angular velocity, rad/s: W for every input, Q=W for input Q (repeatable; default 1)")
    p.add_argument("--epsilon", action="append", default=[], metavar="E|Q=E",
                   help="angular acceleration, rad/s²: E for every input, Q=E for input Q (repeatable; default 0)")
    p.add_argument("--csv", metavar="FILE|-", help="write the table as CSV (SI units, inputs in rad); a scene "
                   "with forces adds each input's effort and every pin's load")
    p.add_argument("--derivatives", action="store_true", help="add every output's jacobian and hessian to the CSV")
    p.add_argument("--mask", action="store_true", help="leave out the samples that cannot be assembled")
    p.add_argument("--region", action="store_true",
                   help="print the assemblable region of a two-input scene over the grid (a text image)")
    return p


def help_epilog() -> str:
    """The options of the several-input form, for ``linkage-solve --help`` without a scene."""
    p = _parser()
    rows = []
    for action in p._actions:  # the parser's own option list: one source for both helps
        if not action.option_strings or action.dest in ("help", "scene"):
            continue
        flags = ", ".join(action.option_strings) + (f" {action.metavar}" if action.metavar else "")
        rows += textwrap.wrap(str(action.help), 96, initial_indent=f"  {flags:<26} ", subsequent_indent=" " * 29)
    head = ("A scene with several inputs (e.g. five_bar) is swept over a grid of its inputs instead, with "
            "these options (docs/inputs.md; linkage-solve five_bar --help):")
    return "\n".join([*textwrap.wrap(head, 96), *rows])


def is_multi_input(argv: Sequence[str]) -> bool:
    """Whether the scene named in ``argv`` has several inputs (False when it cannot be loaded:
    the single-input command then reports the fault as usual)."""
    p = argparse.ArgumentParser(add_help=False)
    p.add_argument("scene", nargs="?")
    try:
        known, _ = p.parse_known_args([a for a in argv if a not in ("-h", "--help")])
    except SystemExit:
        return False
    if not known.scene:
        return False
    try:
        return len(load_scene(known.scene).inputs) > 1
    except (SolverError, OSError, ValueError):
        return False


def per_input_values(
    scene: Scene, items: Sequence[str], *, option: str, default: float, limit: float
) -> np.ndarray:
    """``V`` and ``Q=V`` items to one value per input, as linkage-run reads them: the last plain
    ``V`` applies to every input (else ``default``), then each ``Q=V`` sets input Q."""
    expected = f"give INPUT=VALUE with INPUT one of {', '.join(scene.inputs)}, or one VALUE for every input"
    base = default
    named: list[tuple[str, str, str]] = []
    for item in items:
        name, sep, value = item.partition("=")
        if sep:
            named.append((item, name, value))
            continue
        try:
            base = bounded(limit)(item)
        except argparse.ArgumentTypeError as exc:
            why = "" if "not a number" in str(exc) else f" ({exc})"
            raise SolverError(f"{option} {item!r}: {expected}{why}") from None
    out = {q: base for q in scene.inputs}
    for item, name, value in named:
        if name not in out:
            raise SolverError(f"{option} {item!r}: {expected}")
        try:
            out[name] = bounded(limit)(value)
        except argparse.ArgumentTypeError as exc:
            raise SolverError(f"{option} {item!r}: {exc}") from None
    return np.array([out[q] for q in scene.inputs])


def samples_of(scene: Scene, args: argparse.Namespace) -> tuple[np.ndarray, list[np.ndarray] | None]:
    """The (N, k) samples and, for a grid, its axes (one array per input, rad)."""
    unit = math.pi / 180.0 if args.deg else 1.0
    k = len(scene.inputs)
    # --deg scales the angles; an actuator's stroke stays in m
    scales = {q: 1.0 if u == "m" else unit for q, u in zip(scene.inputs, scene.input_units)}
    given = getattr(args, "phi", None)
    if given is not None and args.samples is not None:
        raise SolverError("--phi and --samples: give one instant (--phi) or rows of them (--samples), not both")
    if given is not None and ";" in given:
        raise SolverError(f"--phi {given!r}: one instant, one value per input ({', '.join(scene.inputs)}); "
                          "several instants: --samples Q1,Q2;Q1,Q2")
    if given is not None or args.samples is not None:
        option = "--phi" if given is not None else "--samples"
        rows = [r for r in (given if given is not None else args.samples).split(";") if r.strip()]
        try:
            values = np.array([[bounded(PHI_MAX)(v) for v in r.split(",")] for r in rows], float)
        except (argparse.ArgumentTypeError, ValueError) as exc:
            raise SolverError(f"{option}: rows of {k} comma-separated finite numbers, split by ';' ({exc})") from None
        if values.ndim != 2 or values.shape[1] != k:
            raise SolverError(f"{option}: {'give' if given is not None else 'each row needs'} {k} values, one per "
                              f"input ({', '.join(scene.inputs)})")
        return values * np.array([scales[q] for q in scene.inputs]), None
    if args.count**k > MAX_SAMPLES:
        raise SolverError(f"--count {args.count} gives {args.count}^{k} samples, more than {MAX_SAMPLES:,}")
    # one turn of an angle; an actuator's whole stroke (m, both ends), which --deg never scales
    axes = {q: np.linspace(0.0, 2.0 * math.pi, args.count, endpoint=False) if r is None else np.linspace(*r, args.count)
            for q, r in zip(scene.inputs, scene.input_ranges)}
    for item in args.range:
        name, sep, span = item.partition("=")
        lo, colon, hi = span.partition(":")
        if not sep or not colon or name not in axes:
            raise SolverError(f"--range {item!r}: give INPUT=LO:HI with INPUT one of {', '.join(scene.inputs)}")
        try:
            a, b = bounded(PHI_MAX)(lo), bounded(PHI_MAX)(hi)
        except argparse.ArgumentTypeError as exc:
            raise SolverError(f"--range {item!r}: {exc}") from None
        if not a < b:
            raise SolverError(f"--range {item!r}: LO must be less than HI (the grid runs from LO to HI, both "
                              "included; a range across 0 of an angle: write e.g. 300:420 in degrees)")
        axes[name] = np.linspace(a * scales[name], b * scales[name], args.count)
    grid = [axes[q] for q in scene.inputs]
    mesh = np.meshgrid(*grid, indexing="ij")
    return np.stack([m.ravel() for m in mesh], axis=-1), grid


def csv_header(scene: Scene, *, derivatives: bool = False) -> list[str]:
    cols = list(scene.inputs)
    pairs = [(a, b) for i, a in enumerate(scene.inputs) for b in scene.inputs[i:]]
    for p in scene.output_points:
        for prefix in ("", "v", "a"):
            cols += [f"{p}.{prefix}{a}" for a in AXES[: scene.dim]]
    for j in scene.output_joints:
        cols += [f"{j}.q", f"{j}.dq", f"{j}.ddq"]
    if derivatives:
        for p in scene.output_points:
            for a in AXES[: scene.dim]:
                cols += [f"{p}.{a}.d_{q}" for q in scene.inputs] + [f"{p}.{a}.d2_{q}_{r}" for q, r in pairs]
        for j in scene.output_joints:
            cols += [f"{j}.d_{q}" for q in scene.inputs] + [f"{j}.d2_{q}_{r}" for q, r in pairs]
    return cols + force_columns(scene)


def force_columns(scene: Scene) -> list[str]:
    """The CSV's force columns (none for a scene without bodies, gravity or loads), after the
    kinematics' (docs/forces.md): per input ``Q.effort`` (N·m for a crank, N for a slider), per
    pin ``pin.P.BODY.fx,pin.P.BODY.fy`` (the force in N on BODY at P from the other body of the
    pin, world frame: ``k.reaction(P, on=BODY, by=other)``), per prismatic pair
    ``slide.P.BLOCK.fx,…fy,…couple`` (the guide's normal force on the block, N, and its couple
    about P, N·m: ``k.slide_reaction(BLOCK)``; with friction, plus its friction along the guide),
    then with ``friction:`` ``loss.NAME`` (W) per pin point / block / actuator, ``friction.power``
    (W), ``efficiency`` and ``locked`` (solver.forces.friction_report). NaN at a singular sample
    (unbounded loads) and where the mechanism self-locks."""
    if not getattr(scene, "has_forces", False):
        return []
    cols = [f"{q}.effort" for q in scene.inputs]
    for pin in scene.pins:
        cols += [f"pin.{pin.point}.{pin.body}.fx", f"pin.{pin.point}.{pin.body}.fy"]
    for s in scene.slides:
        cols += [f"slide.{s.point}.{s.body}.fx", f"slide.{s.point}.{s.body}.fy", f"slide.{s.point}.{s.body}.couple"]
    return cols + friction_columns(scene)


def force_table(scene: Scene, k: Kinematics) -> list[np.ndarray]:
    """The values of :func:`force_columns` as (N, c) blocks, in that order."""
    if not getattr(scene, "has_forces", False):
        return []
    n = np.shape(k.valid)[0]
    cols: list[np.ndarray] = [np.broadcast_to(np.asarray(k.effort(q), float), (n,))[:, None] for q in scene.inputs]
    for pin in scene.pins:
        cols.append(np.broadcast_to(np.asarray(k.reaction(pin.point, on=pin.body, by=pin.other), float), (n, 2)))
    for s in scene.slides:
        pair = k.slide_reaction(s.body)
        cols += [np.broadcast_to(np.asarray(pair.force, float), (n, 2)),
                 np.broadcast_to(np.asarray(pair.couple, float), (n,))[:, None]]
    return cols + friction_table(scene, k)


def _table(scene: Scene, k: Kinematics, derivatives: bool) -> np.ndarray:
    n = len(scene.inputs)
    upper = np.triu_indices(n)
    cols: list[np.ndarray] = [k.phi]
    for p in scene.output_points:
        m = k.point(p)
        cols += [m.position, m.velocity, m.acceleration]
    for j in scene.output_joints:
        m = k.joint(j)
        cols += [m.position[:, None], m.velocity[:, None], m.acceleration[:, None]]
    if derivatives:
        for p in scene.output_points:
            jacobian, hessian = k.derivatives(p)
            for axis in range(scene.dim):
                cols += [jacobian[:, axis, :], hessian[:, axis][:, upper[0], upper[1]]]
        for j in scene.output_joints:
            jacobian, hessian = k.derivatives(j)
            cols += [jacobian, hessian[:, upper[0], upper[1]]]
    return np.hstack(cols + force_table(scene, k))


def write_csv(scene: Scene, k: Kinematics, out: TextIO, *, derivatives: bool = False) -> None:
    out.write(",".join(csv_header(scene, derivatives=derivatives)) + "\n")
    np.savetxt(out, _table(scene, k, derivatives)[k.valid], delimiter=",", fmt="%.17g")


def _value(v: float, unit: str) -> str:
    """An input's value: an angle in degrees, a stroke (``unit`` "m") in m."""
    return f"{v:.4f} m" if unit == "m" else f"{math.degrees(v):.2f}°"


def _sample(scene: Scene, row: np.ndarray) -> str:
    return "(" + ", ".join(f"{q} = {_value(v, u)}" for q, v, u in zip(scene.inputs, row, scene.input_units)) + ")"


def summary(scene: Scene, k: Kinematics, *, sampling: str | None = None, sections: Sequence[Section] = ()) -> str:
    """The one summary of :mod:`solver.summary` (as for one input: degrees, descriptions, input
    joints in one line), over the samples of the inputs, then the singular samples. Extremes are
    those of the samples (said so: a grid is not refined), ``sampling`` says how they were taken."""
    valid = np.asarray(k.valid, bool)
    units = scene.input_units
    mixed = "m" in units  # strokes: each rate with its own unit
    rate = {"rad": (" rad/s", " rad/s²"), "m": (" m/s", " m/s²")}

    def laws(values: np.ndarray, which: int) -> str:
        text = ", ".join(f"{q} = {x:g}{rate[u][which] if mixed else ''}"
                         for q, x, u in zip(scene.inputs, values, units))
        return text if mixed else f"{text}{rate['rad'][which]}"

    w = laws(k.omega[0], 0) if len(k.omega) else ""
    e = laws(k.epsilon[0], 1) if len(k.epsilon) else ""
    lines = [
        f"scene {scene.name}: {int(valid.sum())} of {len(valid)} samples of the inputs ({', '.join(scene.inputs)}) "
        f"assemblable; ω: {w}; ε: {e}; angles in degrees, {'strokes in m, ' if mixed else ''}everything else SI"
    ]
    lines += provenance_lines(scene.provenance)
    desc = getattr(scene, "descriptions", {})

    def output(name: str, point: bool) -> Output:
        m = k.point(name) if point else k.joint(name)
        unit = "m" if point else scene.joint_units.get(name, "rad")
        return Output(name, m.position[valid], m.velocity[valid], m.acceleration[valid], unit, desc.get(name, ""))

    sweep = Sweep(
        phi=k.phi[valid], points=[output(p, True) for p in scene.output_points],
        joints=[output(j, False) for j in scene.output_joints], inputs=tuple(scene.inputs), sampling=sampling,
        units=units)
    lines += summary_lines(sweep)
    singular = np.flatnonzero(valid & np.asarray(k.singular, bool))
    shown = ", ".join(_sample(scene, k.phi[i]) for i in singular[:4])
    more = f" and {len(singular) - 4} more" if len(singular) > 4 else ""
    lines.append(f"  singular samples (derivatives NaN there): {len(singular)}{': ' + shown + more if shown else ''}")
    for section in sections:  # after the kinematics' own lines, as for one input (solver.cli.summary)
        lines += section(sweep)
    return "\n".join(lines)


def _sampling(axes: Sequence[np.ndarray] | None, units: Sequence[str] = ()) -> str:
    """The grid in words: its size and the step of each input."""
    if axes is None:
        return "the given samples"
    units = list(units) if len(units) == len(axes) else ["rad"] * len(axes)
    steps = [(f"{float(a[1] - a[0]):.4g} m" if u == "m" else f"{math.degrees(float(a[1] - a[0])):.4g}°")
             if len(a) > 1 else "one value" for a, u in zip(axes, units)]
    each = f"every {steps[0]}" if len(set(steps)) == 1 else "every " + " × ".join(steps)
    return f"the {' × '.join(str(len(a)) for a in axes)} grid ({each})"


def region_lines(scene: Scene, axes: Sequence[np.ndarray]) -> list[str]:
    """The assemblable region of a two-input scene over the grid ``axes`` as a text image: one
    row per value of the second input (highest on top), one column per value of the first;
    ``#`` assemblable, ``s`` assemblable but singular, ``.`` not assemblable."""
    if len(scene.inputs) != 2 or len(axes) != 2:
        raise SolverError(f"--region maps two inputs; {scene.name} has {len(scene.inputs)}")
    q1, q2 = scene.inputs
    ok = assemblable(scene, axes)
    mesh = np.stack([m.ravel() for m in np.meshgrid(*axes, indexing="ij")], axis=-1)
    singular = np.asarray(scene.with_outputs().solve(mesh, mask=True).singular).reshape(ok.shape)
    lines = [
        f"scene {scene.name}: assemblable region over {len(axes[0])} × {len(axes[1])} samples of ({q1}, {q2}): "
        f"{int(ok.sum())} of {ok.size} assemblable ({CELLS['ok']} assemblable, {CELLS['singular']} singular, "
        f"{CELLS['no']} not)",
        f"  {q2} (rows, top = {math.degrees(axes[1][-1]):.1f}°, bottom = {math.degrees(axes[1][0]):.1f}°); "
        f"{q1} (columns, {math.degrees(axes[0][0]):.1f}° … {math.degrees(axes[0][-1]):.1f}°)",
    ]
    for j in range(len(axes[1]) - 1, -1, -1):
        row = "".join(
            CELLS["no"] if not ok[i, j] else CELLS["singular"] if singular[i, j] else CELLS["ok"]
            for i in range(len(axes[0]))
        )
        lines.append(f"  {math.degrees(axes[1][j]):8.2f}° {row}")
    return lines


@quiet_pipe
def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    try:
        if args.csv and args.csv != "-":
            check_output(args.csv, "--csv")
        scene = load_scene(args.scene)
        samples, axes = samples_of(scene, args)
        if args.region:
            if axes is None:
                raise SolverError("--region maps a grid: use --count and --range, not --samples")
            print("\n".join(region_lines(scene, axes)))
            return 0
        omega = per_input_values(scene, args.omega, option="--omega", default=1.0, limit=OMEGA_MAX)
        epsilon = per_input_values(scene, args.epsilon, option="--epsilon", default=0.0, limit=EPSILON_MAX)
        k = scene.solve(samples, omega=omega, epsilon=epsilon, mask=args.mask)
        if args.csv:
            singular = np.flatnonzero(np.asarray(k.singular & k.valid))
            if singular.size:
                loads = ", efforts and loads" if scene.has_forces else ""
                print(f"linkage-solve: note: {singular.size} singular sample(s), first "
                      f"{_sample(scene, k.phi[singular[0]])}: derivatives{loads} there are nan (docs/inputs.md)",
                      file=sys.stderr)
            if args.csv == "-":
                write_csv(scene, k, sys.stdout, derivatives=args.derivatives)
            else:
                with open(args.csv, "w", encoding="utf-8", newline="") as fh:
                    write_csv(scene, k, fh, derivatives=args.derivatives)
        else:
            grid = _sampling(axes, scene.input_units)
            forces = force_section(scene, k, sampling=f"read off {grid}",
                                   default_speed=not args.omega and not args.epsilon)
            print(summary(scene, k, sampling=grid, sections=[forces]))
    except BrokenPipeError:
        raise  # the reader went away (`| head`): quiet_pipe ends quietly
    except (SolverError, ValueError, OSError) as exc:
        return error_line("linkage-solve", exc)
    return 0
