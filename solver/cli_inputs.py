"""``linkage-solve`` for a scene with several inputs (docs/inputs.md).

``linkage-solve SCENE`` dispatches here when the scene has k > 1 inputs. The samples are a grid
over the inputs (``--count N`` values of each over one turn, narrowed by ``--range``) or given
rows (``--samples``); motion laws are per input::

    linkage-solve five_bar --deg --range q1=40:140 --range q2=40:140 --count 11 \\
        --omega q1=2 --omega q2=-1.5 --epsilon q1=0.7 --epsilon q2=3 --csv -
    linkage-solve five_bar --region --count 36            # the assemblable region as a text image

The CSV has one column per input (named by it, rad), then per point ``P.x,P.y,P.vx,…,P.ay`` and
per joint ``J.q,J.dq,J.ddq`` (v = J·ω, a = J·ε + ωᵀHω), and with ``--derivatives`` the jacobian
``P.x.d_q1`` … and the hessian ``P.x.d2_q1_q2`` … (upper triangle) of every output.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence
from typing import TextIO

import numpy as np

from ._cmdline import EPSILON_MAX, OMEGA_MAX, PHI_MAX, Parser, bounded, check_output, count, one_line, quiet_pipe
from .errors import SolverError
from .kinematics import Kinematics
from .multi import assemblable
from .scene import Scene, load_scene

__all__ = ["csv_header", "is_multi_input", "main", "per_input_values", "region_lines", "samples_of"]

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
                   help="an input's range on the grid, both ends included (default one turn, end excluded)")
    p.add_argument("--samples", metavar="Q1,Q2;Q1,Q2;...", help="these rows of input values instead of a grid")
    p.add_argument("--deg", action="store_true", help="--range and --samples values are in degrees")
    p.add_argument("--omega", action="append", default=[], metavar="Q=W",
                   help="an input's angular velocity, rad/s (repeat per input; default 1)")
    p.add_argument("--epsilon", action="append", default=[], metavar="Q=E",
                   help="an input's angular acceleration, rad/s² (repeat per input; default 0)")
    p.add_argument("--csv", metavar="FILE|-", help="write the table as CSV (SI units, inputs in rad)")
    p.add_argument("--derivatives", action="store_true", help="add every output's jacobian and hessian to the CSV")
    p.add_argument("--mask", action="store_true", help="leave out the samples that cannot be assembled")
    p.add_argument("--region", action="store_true",
                   help="print the assemblable region of a two-input scene over the grid (a text image)")
    return p


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
    """``Q=V`` items to one value per input (``default`` for those not named)."""
    out = {q: default for q in scene.inputs}
    for item in items:
        name, sep, value = item.partition("=")
        if not sep or name not in out:
            raise SolverError(f"{option} {item!r}: give INPUT=VALUE with INPUT one of {', '.join(scene.inputs)}")
        try:
            out[name] = bounded(limit)(value)
        except argparse.ArgumentTypeError as exc:
            raise SolverError(f"{option} {item!r}: {exc}") from None
    return np.array([out[q] for q in scene.inputs])


def samples_of(scene: Scene, args: argparse.Namespace) -> tuple[np.ndarray, list[np.ndarray] | None]:
    """The (N, k) samples and, for a grid, its axes (one array per input, rad)."""
    unit = math.pi / 180.0 if args.deg else 1.0
    k = len(scene.inputs)
    if args.samples is not None:
        rows = [r for r in args.samples.split(";") if r.strip()]
        try:
            values = np.array([[bounded(PHI_MAX)(v) for v in r.split(",")] for r in rows], float) * unit
        except (argparse.ArgumentTypeError, ValueError) as exc:
            raise SolverError(f"--samples: rows of {k} comma-separated finite numbers, split by ';' ({exc})") from None
        if values.ndim != 2 or values.shape[1] != k:
            raise SolverError(f"--samples: each row needs {k} values ({', '.join(scene.inputs)})")
        return values, None
    if args.count**k > MAX_SAMPLES:
        raise SolverError(f"--count {args.count} gives {args.count}^{k} samples, more than {MAX_SAMPLES:,}")
    axes = {q: np.linspace(0.0, 2.0 * math.pi, args.count, endpoint=False) for q in scene.inputs}
    for item in args.range:
        name, sep, span = item.partition("=")
        lo, colon, hi = span.partition(":")
        if not sep or not colon or name not in axes:
            raise SolverError(f"--range {item!r}: give INPUT=LO:HI with INPUT one of {', '.join(scene.inputs)}")
        try:
            axes[name] = np.linspace(bounded(PHI_MAX)(lo) * unit, bounded(PHI_MAX)(hi) * unit, args.count)
        except argparse.ArgumentTypeError as exc:
            raise SolverError(f"--range {item!r}: {exc}") from None
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
    return cols


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
            m = k.point(p)
            for axis in range(scene.dim):
                cols += [m.jacobian[:, axis, :], m.hessian[:, axis][:, upper[0], upper[1]]]
        for j in scene.output_joints:
            m = k.joint(j)
            cols += [m.jacobian, m.hessian[:, upper[0], upper[1]]]
    return np.hstack(cols)


def write_csv(scene: Scene, k: Kinematics, out: TextIO, *, derivatives: bool = False) -> None:
    out.write(",".join(csv_header(scene, derivatives=derivatives)) + "\n")
    np.savetxt(out, _table(scene, k, derivatives)[k.valid], delimiter=",", fmt="%.17g")


def _sample(scene: Scene, row: np.ndarray) -> str:
    return "(" + ", ".join(f"{q} = {math.degrees(v):.2f}°" for q, v in zip(scene.inputs, row)) + ")"


def summary(scene: Scene, k: Kinematics) -> str:
    """Each output's range and the largest |v| and |a| with the sample where they occur."""
    valid = np.asarray(k.valid, bool)
    w = ", ".join(f"{q} = {x:g}" for q, x in zip(scene.inputs, k.omega[0])) if len(k.omega) else ""
    e = ", ".join(f"{q} = {x:g}" for q, x in zip(scene.inputs, k.epsilon[0])) if len(k.epsilon) else ""
    lines = [
        f"scene {scene.name}: {int(valid.sum())} of {len(valid)} samples of the inputs ({', '.join(scene.inputs)}) "
        f"assemblable; ω: {w} rad/s; ε: {e} rad/s²"
    ]
    if scene.provenance:
        lines.append(f"  ({scene.provenance.split('. ')[0].rstrip('.')}.)")
    ok = valid & ~np.asarray(k.singular, bool)
    for name in (*scene.output_points, *scene.output_joints):
        m = k.point(name) if name in scene.output_points else k.joint(name)
        unit = "m" if name in scene.output_points else scene.joint_units.get(name, "rad")
        pos = m.position[valid]
        if not len(pos):
            continue
        if pos.ndim == 2:
            span = ", ".join(f"{a} {pos[:, i].min():.6g} … {pos[:, i].max():.6g}" for i, a in enumerate(AXES))
            speed, accel = np.linalg.norm(m.velocity, axis=1), np.linalg.norm(m.acceleration, axis=1)
        else:
            span = f"{pos.min():.6g} … {pos.max():.6g}"
            speed, accel = np.abs(m.velocity), np.abs(m.acceleration)
        line = f"  {name}: {span} {unit}"
        if ok.any():
            iv, ia = (int(np.flatnonzero(ok)[np.argmax(x[ok])]) for x in (speed, accel))
            line += (f"; max |v| = {speed[iv]:.6g} {unit}/s at {_sample(scene, k.phi[iv])}, "
                     f"max |a| = {accel[ia]:.6g} {unit}/s² at {_sample(scene, k.phi[ia])}")
        lines.append(line)
    singular = np.flatnonzero(valid & np.asarray(k.singular, bool))
    shown = ", ".join(_sample(scene, k.phi[i]) for i in singular[:4])
    more = f" and {len(singular) - 4} more" if len(singular) > 4 else ""
    lines.append(f"  singular samples (derivatives NaN there): {len(singular)}{': ' + shown + more if shown else ''}")
    return "\n".join(lines)


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
                print(f"linkage-solve: note: {singular.size} singular sample(s), first "
                      f"{_sample(scene, k.phi[singular[0]])}: derivatives there are nan (docs/inputs.md)",
                      file=sys.stderr)
            if args.csv == "-":
                write_csv(scene, k, sys.stdout, derivatives=args.derivatives)
            else:
                with open(args.csv, "w", encoding="utf-8", newline="") as fh:
                    write_csv(scene, k, fh, derivatives=args.derivatives)
        else:
            print(summary(scene, k))
    except (SolverError, ValueError) as exc:
        print(f"linkage-solve: error: {one_line(str(exc))}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        raise
    except OSError as exc:
        print(f"linkage-solve: error: {one_line(exc.strerror or str(exc))}: {exc.filename or ''}", file=sys.stderr)
        return 2
    return 0
