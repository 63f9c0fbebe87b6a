"""See and keep a scene's structure: ``linkage-solve FILE --structure`` and ``linkage-import``.

``linkage-solve FILE --structure``
    the decomposition: the groups in plan order with their modes and lengths, the mobility
    count (Grübler–Kutzbach) against the inputs, and for a drawn scene each group's
    conditioning and each input's value at the drawn pose.
``linkage-import FILE -o scene.yaml``
    a drawn scene written as its equivalent group scene (it loads and solves bit-identically);
    an MJCF or URDF model as its imported scene (docs/models.md).
``linkage-import SCENE --drawing [--phi V[,V…]] [--deg] -o drawn.yaml``
    any group scene written as a drawing at the given inputs (rad, or deg with ``--deg``; an
    actuator's stroke in m; default 0 for a crank, the middle of an actuator's stroke).
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ._cmdline import PHI_MAX, Parser, bounded, check_output, error_line, write_out
from ._loader import read_yaml
from .errors import SceneError, SolverError
from .forces.structure import StructureFault, derive_structure
from .groups import RRP, RRR, Actuator, Attached, CoupledCrank, Crank, Group, JointExpression, Slotted
from .models import MODEL_SUFFIXES
from .scene import Scene, find_scene, load_scene
from .structure import find_structure, scene_dict_from_drawing
from .structure.export import drawing_from_groups

__all__ = ["structure_lines", "drawing_of_scene", "group_scene_of_drawing", "dump_scene", "import_main",
           "structure_main", "positions_at"]


def _deg(x: float) -> str:
    return f"{math.degrees(x):.4f}°"


def _m(x: float) -> str:
    return f"{x:.6g} m"


def _convention(g: Crank) -> str:
    """A crank's angle in terms of its joint, where it is not the joint itself (imported models)."""
    if g.plain:
        return ""
    return f": angle of {g.center}→{g.point} = {_deg(g.offset)} {'+' if g.sign > 0 else '−'} {g.joint}"


def group_line(g: Group) -> str:
    """One group in words, SI lengths and degrees."""
    head = f"{g.kind} '{g.name}'"
    if isinstance(g, CoupledCrank):
        return (f"{head}: {g.point} turns about {g.center}, length {_m(g.length)}; joint '{g.joint}' follows "
                f"'{g.source}': {g.joint} = {g.shift:.6g} + {g.ratio:.6g}·{g.source}{_convention(g)}")
    if isinstance(g, Crank):
        return (f"{head}: {g.point} turns about {g.center}, length {_m(g.length)}; input '{g.joint}' "
                f"({'its angle' if g.plain else 'in its model' + chr(39) + 's convention'}{_convention(g)})")
    if isinstance(g, Actuator):
        lo, hi = g.stroke
        return (f"{head}: {g.point} at {_m(g.length)} from {g.pivot} and the stroke |{g.base}{g.point}| from "
                f"{g.base}, M = {g.mode:+d}; input '{g.joint}' in [{lo:.6g}, {hi:.6g}] m")
    if isinstance(g, RRR):
        more = ", through change points (continuous)" if g.continuous else ""
        return (f"{head}: {g.point} from ends [{g.ends[0]}, {g.ends[1]}], lengths [{_m(g.lengths[0])}, "
                f"{_m(g.lengths[1])}], M = {g.mode:+d}{more}")
    if isinstance(g, RRP):
        e, o = complex(g.direction), complex(g.origin)
        joint = f"; joint '{g.joint}'" if g.joint else ""
        return (f"{head}: {g.point} at {_m(g.length)} from {g.end} on the guide through ({o.real:.6g}, "
                f"{o.imag:.6g}) m at {_deg(math.atan2(e.imag, e.real))}, M = {g.mode:+d}{joint}")
    if isinstance(g, Slotted):
        pts = ", ".join(f"{n} at {_m(d)}" for n, d in g.points)
        return f"{head}: the link turns about {g.pivot} through {g.through}; {pts} from {g.pivot}"
    if isinstance(g, Attached):
        return (f"{head}: {g.point} at {_m(g.distance)} from {g.base}, {_deg(g.angle)} from "
                f"{g.along[0]}→{g.along[1]}")
    return head


def _mobility(scene: Scene) -> str:
    groups = [g for g in scene.ordered if not isinstance(g, JointExpression)]
    try:
        st = derive_structure(groups, scene._data.fixed)
    except StructureFault:
        return f"mobility: {len(scene.inputs)} input(s) (no planar link structure: spherical or vector-loop scene)"
    n = len(st.links) + 1
    acts = sum(1 for g in groups if isinstance(g, Actuator))
    n += acts  # a cylinder is a barrel and a rod: one more body, and one more pair (the slide)
    j1 = len(st.pins) + len(st.slides) + acts
    coupled = sum(1 for g in groups if isinstance(g, CoupledCrank))  # a coupled input takes a freedom
    count = 3 * (n - 1) - 2 * j1 - coupled
    more = f" − {coupled} coupled" if coupled else ""
    return (f"mobility F = 3(n − 1) − 2j₁ − j₂{' − k' if coupled else ''} = 3·{n - 1} − 2·{j1} − 0{more} = {count}, "
            f"inputs {len(scene.inputs)} ({', '.join(scene.inputs)})")


def structure_lines(path: str | Path) -> list[str]:
    """The structure of a scene file (drawn or group), as printed by ``linkage-solve --structure``."""
    file = find_scene(path)
    scene = load_scene(file)
    lines = [f"structure of {scene.name} ({file}): {_mobility(scene)}"]
    model = getattr(scene, "model", None)
    if model is not None:  # an imported MJCF or URDF: where its plane lies (docs/models.md)
        lines.append(f"  {model.kind} at {model.pose}; plane: {model.plane.describe()}")
    raw = read_yaml(file) if model is None else None
    drawn: dict[str, Any] = {}
    if isinstance(raw, Mapping) and "drawing" in raw:
        st = find_structure(raw, source=str(file))
        values = st.inputs_drawn
        at = ", ".join(
            f"{j} = " + (_m(values[j]) if s.kind == "actuator" else _deg(values[j]))
            for s in st.drivers
            for j in (s.fields["joint"],)
        )
        lines.append(f"  as drawn: {at}")
        drawn = {s.name: s for s in st.steps}
    lines.append("  groups in plan order:")
    for i, g in enumerate((g for g in scene.ordered if not isinstance(g, JointExpression)), 1):
        text = group_line(g)
        step = drawn.get(g.name)
        if step is not None and step.conditioning is not None:
            text += f" (conditioning {step.conditioning:.3g} as drawn)"
        lines.append(f"  {i:>3}. {text}")
    reads = [g for g in scene.ordered if isinstance(g, JointExpression)]
    if reads:
        lines.append("  read-outs: " + ", ".join(f"{g.name} ({g.expression} {', '.join(g.points)})" for g in reads))
    return lines


def positions_at(scene: Scene, values: Sequence[float]) -> dict[str, complex]:
    """Every point of ``scene`` at the inputs ``values`` (SI), as complex numbers."""
    full = scene.everything()
    k = len(scene.inputs)
    if len(values) != k:
        raise SolverError(f"{scene.name} has {k} input(s) ({', '.join(scene.inputs)}): give {k} value(s), "
                          f"got {len(values)}")
    phi = np.array([list(values)]) if k > 1 else np.array(values, float)
    sol = full.solve(phi)
    out: dict[str, complex] = {}
    for p in full.point_names:
        xy = np.asarray(sol.point(p).position, float).reshape(-1)
        out[p] = complex(xy[0], xy[1])
    return out


def default_inputs(scene: Scene) -> list[float]:
    """0 for an angle, the middle of an actuator's stroke."""
    return [0.0 if r is None else 0.5 * (r[0] + r[1]) for r in scene.input_ranges]


def drawing_of_scene(path: str | Path, values: Sequence[float] | None = None) -> dict[str, Any]:
    """A group scene file as a drawn scene mapping at the inputs ``values`` (SI)."""
    file = find_scene(path)
    raw = read_yaml(file)
    if isinstance(raw, Mapping) and "drawing" in raw:  # drawn again at other inputs: from its group form
        raw = scene_dict_from_drawing(raw, source=str(file))
    scene = load_scene(file)
    if scene.dim != 2:
        raise SceneError("a spatial scene has no drawn form (a drawing is planar)", file=str(file))
    if any(key in raw for key in ("vector_model",)):
        raise SceneError("a vector-loop scene (seed 004) has no drawn form: write it as groups first", file=str(file))
    vals = default_inputs(scene) if values is None else list(values)
    return drawing_from_groups(raw, scene.ordered, scene._data.fixed, positions_at(scene, vals), file=str(file),
                               input_order=scene.inputs)


def group_scene_of_drawing(path: str | Path) -> dict[str, Any]:
    """A drawn scene file as its equivalent group scene mapping (a robot model file, MJCF or URDF,
    as its imported scene: solver.models, docs/models.md)."""
    file = find_scene(path)
    if file.suffix.lower() in MODEL_SUFFIXES:
        from .models import model_scene_data

        return model_scene_data(file)[0]
    raw = read_yaml(file)
    if not (isinstance(raw, Mapping) and "drawing" in raw):
        raise SceneError("has no drawing: section (write a group scene as a drawing with --drawing)", file=str(file))
    return scene_dict_from_drawing(raw, source=str(file))


def _plain(value: Any) -> Any:
    """YAML-file mappings and lists as plain dicts and lists; numbers as Python floats."""
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.floating, np.integer)):
        return value.item()
    return value


class _Dumper(yaml.SafeDumper):
    """Block style at the top, flow style for the leaves (a point, a group entry's lists)."""


def dump_scene(data: Mapping[str, Any]) -> str:
    """A scene mapping as YAML text: floats written with repr (they read back to the same bits)."""
    return yaml.dump(_plain(data), Dumper=_Dumper, sort_keys=False, default_flow_style=None, allow_unicode=True,
                     width=120)


def _parser() -> argparse.ArgumentParser:
    p = Parser(prog="linkage-import", description="Write a drawn scene as groups, or a group scene as a drawing.")
    p.add_argument("scene", help="scene file, or the name of a shipped scene")
    p.add_argument("-o", "--output", required=True, metavar="FILE", help="the scene file to write (- for stdout)")
    p.add_argument("--drawing", action="store_true", help="write the group scene SCENE as a drawing")
    p.add_argument("--phi", metavar="V[,V...]", help="--drawing: the input value(s) to draw it at (rad, or deg with "
                   "--deg; an actuator's stroke in m); default 0, or the middle of a stroke")
    p.add_argument("--deg", action="store_true", help="--phi in degrees")
    return p


def import_main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(sys.argv[1:] if argv is None else list(argv))
    try:
        if args.output != "-":
            check_output(args.output, "--output")
        if args.drawing:
            values = None
            if args.phi is not None:
                try:
                    values = [bounded(PHI_MAX)(v) for v in args.phi.split(",") if v.strip()]
                except argparse.ArgumentTypeError as exc:
                    raise SolverError(f"--phi {args.phi!r}: {exc}") from None
                if args.deg:
                    scene = load_scene(args.scene)
                    values = [math.radians(v) if u == "rad" else v for v, u in zip(values, scene.input_units)]
            data = drawing_of_scene(args.scene, values)
        else:
            if args.phi is not None or args.deg:
                raise SolverError("--phi and --deg go with --drawing (a drawing holds its own pose)")
            data = group_scene_of_drawing(args.scene)
        text = dump_scene(data)
        write_out(text, args.output)
    except BrokenPipeError:
        raise  # the reader went away (`| head`): quiet_pipe ends quietly
    except (SolverError, ValueError, OSError) as exc:
        return error_line("linkage-import", exc)
    return 0


def structure_main(scene: str) -> int:
    """``linkage-solve SCENE --structure``."""
    try:
        print("\n".join(structure_lines(scene)))
    except BrokenPipeError:
        raise  # the reader went away (`| head`): quiet_pipe ends quietly
    except (SolverError, ValueError, OSError) as exc:
        return error_line("linkage-solve", exc)
    return 0


if __name__ == "__main__":
    sys.exit(import_main())
