"""YAML → validated scene parts: units, fixed points, groups, joints and outputs."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from ._fields import Entry, Units, read_units, show, suggest
from ._inputs import check_actuators, check_coupled, check_drivers
from ._yaml import load_yaml
from .errors import SceneError
from .forces.parse import FORCE_KEYS, parse_forces
from .groups import GROUP_TYPES, JOINT_KINDS, RRR, Crank, Group, JointExpression
from .groups.joints import URDF_JOINT_KINDS
from .groups.rrr import CrankFeed
from .structure import scene_dict_from_drawing

__all__ = ["SceneData", "parse_scene", "read_yaml", "SECTION_PARSERS"]

#: Extra top-level sections (e.g. ``contours:`` of the vector-loop form) and their parsers:
#: ``parse(entry, units, fixed) -> list[Group]``.
SECTION_PARSERS: dict[str, Any] = {}


@dataclass(frozen=True)
class SceneData:
    """Everything a scene file says, validated, in SI units."""

    name: str
    file: str | None
    provenance: str
    dim: int
    fixed: Mapping[str, Any]  # complex (planar) or ndarray(3)
    groups: tuple[Group, ...]  # scene order; dependency order is the plan's business
    input_joint: str
    output_points: tuple[str, ...]
    output_joints: tuple[str, ...]
    #: one-line descriptions of points and joints (``descriptions:``), for summaries and viewers
    descriptions: Mapping[str, str] = field(default_factory=dict)
    #: bodies, gravity and loads (solver.forces, docs/forces.md); None when the scene names none
    forces: Any = None


#: The top-level fields of a scene file; the sections in SECTION_PARSERS are known too.
TOP_FIELDS = [
    "scene", "provenance", "description", "descriptions", "units", "fixed", "groups", "joints", "outputs", *FORCE_KEYS
]

#: The fields of each group type, checked first so that a misspelt key is reported as such
#: (a group's ``from_entry`` reads them; its ``done()`` stays the exact check).
GROUP_FIELDS: dict[str, tuple[str, ...]] = {
    "crank": ("type", "name", "center", "point", "length", "joint", "offset", "sign", "follows"),
    "actuator": ("type", "name", "base", "point", "pivot", "length", "M", "joint", "stroke"),
    "attached": ("type", "name", "point", "base", "along", "distance", "angle"),
    "slotted": ("type", "name", "pivot", "through", "points"),
    "rrr": ("type", "name", "ends", "point", "lengths", "M", "through_change_points"),
    "rrp": ("type", "name", "end", "point", "length", "guide", "M", "joint"),
    "spherical_crank_slider": ("type", "name", "center", "point", "shaft", "cage", "alpha", "radius"),
}

#: Longest ``description`` text (one line).
DESCRIPTION_MAX = 200


def read_yaml(path: Path) -> Any:
    """The YAML document of a scene file, read safely (solver._yaml: size, depth, aliases,
    encoding and duplicate keys are checked)."""
    return load_yaml(path)


def parse_scene(data: Any, *, file: str | None, default_name: str = "scene") -> SceneData:
    """Validate a scene's data; a misspelt top-level key is reported before any other fault."""
    if data is None:
        raise SceneError("the file is empty: a scene is a mapping of sections (docs/scenes.md)", file=file)
    if isinstance(data, Mapping) and "drawing" in data:  # the drawn form (solver.structure)
        data = scene_dict_from_drawing(data, source=file)
    try:
        return _parse_scene(data, file=file, default_name=default_name)
    except SceneError:
        if isinstance(data, Mapping):
            Entry(data, file=file, where="").expect([*TOP_FIELDS, *SECTION_PARSERS])
        raise


def _parse_scene(data: Any, *, file: str | None, default_name: str = "scene") -> SceneData:
    top = Entry(data, file=file, where="")
    name = top.name("scene", default_name)
    provenance = _text(top, "provenance", 100_000)
    _text(top, "description", 100_000)
    units = read_units(top)
    fixed, dim = _fixed(top, units)
    groups: list[Group] = []
    raw_groups = top.raw("groups", [])
    if raw_groups is None:
        raise top.error("is empty: list the scene's structural groups (docs/scenes.md)", "groups")
    if not isinstance(raw_groups, list):
        raise top.error(f"must be a list of groups, got {show(raw_groups)}", "groups")
    if not raw_groups and not any(key in top.data for key in SECTION_PARSERS):
        raise top.error("name at least one group (a crank first: the input)", "groups")
    planar = all(isinstance(v, complex) for v in fixed.values())  # (once, not per group: a drawn
    # scene's many ground points made that quadratic)
    for i, raw in enumerate(raw_groups):
        groups.append(_group(top.child(f"groups[{i}]", raw), units, fixed, planar=planar))
    for key, parse in SECTION_PARSERS.items():
        if key in top.data:
            groups.extend(parse(top.child(key, top.raw(key)), units, fixed))
    groups = _feed_dyads(groups, fixed)
    groups.extend(_joints(top, _rigid_pairs(groups), units, dim))
    check_drivers(top, groups)  # several inputs: over-determined points, drivers (solver._inputs)
    check_coupled(top, groups)  # a crank turned by another input follows an input crank
    check_actuators(top, fixed, groups)  # driven lengths: pivots on links, single-input limits
    _check_names(top, fixed, groups, dim)
    _check_fixed_joints(top, fixed, groups)
    inputs = [g for g in groups if g.drives]
    if not inputs:
        raise top.error(
            "a scene needs exactly one input (a crank), found 0 (or one crank per input for several, docs/inputs.md)",
            "groups",
        )
    _check_moving(top, fixed, groups)
    input_joint = inputs[0].input_joint()
    assert input_joint is not None
    out = top.child("outputs", top.raw("outputs"))
    provided = {n for g in groups for n in g.provides()}
    joints = {n for g in groups for n in g.joints()}
    points = (set(fixed) | provided) - joints
    out_points = out.names("points", default=[])
    out_joints = out.names("joints", default=[])
    out.done()
    for p in out_points:
        if p not in points:
            raise out.error(f"unknown point '{p}'; points: {sorted(points)}", "points")
    for j in out_joints:
        if j not in joints:
            raise out.error(f"unknown joint '{j}'; joints: {sorted(joints)}", "joints")
    if not out_points and not out_joints:
        raise out.error("name at least one point or joint")
    descriptions = _descriptions(top, points | joints)
    forces = parse_forces(top, units, fixed, groups)
    top.done()
    return SceneData(
        name, file, provenance, dim, fixed, tuple(groups), input_joint, out_points, out_joints, descriptions, forces
    )


def _text(top: Entry, key: str, limit: int) -> str:
    value = top.raw(key, "")
    if value is None:
        return ""
    if not isinstance(value, str):
        raise top.error(f"must be text, got {show(value)}", key)
    if len(value) > limit:
        raise top.error(f"text of {len(value):,} characters: at most {limit:,}", key)
    return value.strip()


def _descriptions(top: Entry, names: set[str]) -> dict[str, str]:
    """``descriptions: {B: drum pin, finger: angle of the finger}``: one line per point or joint."""
    d = top.child("descriptions", top.raw("descriptions", {}) or {})
    out: dict[str, str] = {}
    for key in d.data:
        if key not in names:
            known = ", ".join(sorted(names)[:20])
            raise d.error(f"{show(key, 40)} is not a point or joint of the scene; known: {known}", str(key))
        text = d.raw(key)
        if not isinstance(text, str) or not text.strip():
            raise d.error(f"must be a one-line text, got {show(text)}", str(key))
        text = " ".join(text.split())
        if len(text) > DESCRIPTION_MAX:
            raise d.error(f"a description of {len(text)} characters: at most {DESCRIPTION_MAX}", str(key))
        out[str(key)] = text
    return out


def _fixed(top: Entry, units: Units) -> tuple[dict[str, Any], int]:
    raw = top.raw("fixed")
    f = top.child("fixed", raw)
    fixed: dict[str, Any] = {}
    dims = set()
    for key in f.data:
        value = f.raw(key)
        ok = isinstance(value, (list, tuple)) and len(value) in (2, 3)
        if ok:
            ok = all(isinstance(v, (int, float)) and not isinstance(v, bool) for v in value)
        if not ok:
            raise f.error(f"must be [x, y] or [x, y, z] in {show(top.data.get('units'))}, got {show(value)}", str(key))
        f.check_name(str(key), str(key))
        xyz = [f.length_value(f.as_number(v, str(key)), str(key), units, positive=False) for v in value]
        dims.add(len(xyz))
        fixed[str(key)] = complex(xyz[0], xyz[1]) if len(xyz) == 2 else np.array(xyz)
    if not fixed:
        raise f.error("name at least one fixed point")
    if len(dims) != 1:
        raise f.error("mixes planar [x, y] and spatial [x, y, z] points")
    return fixed, dims.pop()


def _group(e: Entry, units: Units, fixed: Mapping[str, Any], *, planar: bool | None = None) -> Group:
    kind = e.name("type")
    cls = GROUP_TYPES.get(kind)
    if cls is None:
        near = suggest(kind, GROUP_TYPES)
        hint = f" (did you mean '{near[0]}'?)" if near else ""
        raise e.error(f"unknown group type '{kind}'{hint}; known types: {', '.join(sorted(GROUP_TYPES))}", "type")
    if planar is None:
        planar = all(isinstance(v, complex) for v in fixed.values())
    if bool(getattr(cls, "spatial", False)) == planar:
        need, have = ("spatial [x, y, z]", "planar") if planar else ("planar [x, y]", "spatial")
        raise e.error(f"a {kind} group needs {need} fixed points; this scene's are {have}", "type")
    try:
        group = cls.from_entry(e, units, fixed)
    except SceneError:  # a misspelt key first: it is the likelier cause of a missing or odd field
        known = getattr(cls, "fields", None) or GROUP_FIELDS.get(kind)
        if known is not None:
            e.expect([*known, *e.used])
        raise
    e.done()
    return group


def _feed_dyads(groups: list[Group], fixed: Mapping[str, Any]) -> list[Group]:
    """Tell an RRR dyad driven directly by the crank against a fixed pivot its crank's geometry."""
    cranks = {g.point: g for g in groups if isinstance(g, Crank) and g.drives and g.plain}
    out: list[Group] = []
    for g in groups:
        if isinstance(g, RRR):
            a, c = g.ends
            crank, other = (cranks.get(a), c) if a in cranks else (cranks.get(c), a)
            if crank is not None and other in fixed and isinstance(fixed[other], complex):
                center = complex(fixed[crank.center])
                if fixed[other] != center:
                    g = replace(g, feed=CrankFeed.of(crank.point, center, crank.length, fixed[other]))
        out.append(g)
    return out


def _rigid_pairs(groups: list[Group]) -> dict[frozenset[str], float]:
    """Point pairs at a fixed distance on one body, whatever their order."""
    return {frozenset((p, q)): length for g in groups for p, q, length in g.rigid_pairs() if p != q}


def _joints(top: Entry, rigid: Mapping[frozenset[str], float], units: Units, dim: int) -> list[Group]:
    j = top.child("joints", top.raw("joints", {}))
    out: list[Group] = []
    for name in j.data:
        spec = j.child(str(name), j.raw(name))
        kinds = [k for k in spec.data if k in JOINT_KINDS or k in URDF_JOINT_KINDS]
        if len(kinds) != 1 or len(spec.data) != 1:
            known = (*JOINT_KINDS, *URDF_JOINT_KINDS)
            near = [m for k in spec.data if isinstance(k, str) and k not in known for m in suggest(k, known)[:1]]
            hint = f" (did you mean '{near[0]}'?)" if near else ""
            raise spec.error(f"must be one of {{{', '.join(f'{k}: …' for k in known)}}}, got {show(spec.data)}{hint}")
        kind = kinds[0]
        if kind in URDF_JOINT_KINDS:  # URDF-style: {revolute: {parent, child, ...}} / {prismatic: {...}}
            if dim != 2:
                raise spec.error(f"a {kind} joint needs a planar scene", kind)
            urdf = spec.child(kind, spec.raw(kind))
            out.append(JointExpression.from_urdf_entry(str(name), kind, urdf, units))
            continue
        count = JOINT_KINDS[kind]
        pts = spec.names(kind, count) if count > 1 else (spec.name(kind),)
        length = rigid.get(frozenset(pts)) if kind == "angle" else None
        out.append(JointExpression(name=str(name), expression=kind, points=pts, rigid_length=length))
    return out


def _check_fixed_joints(top: Entry, fixed: Mapping[str, Any], groups: list[Group]) -> None:
    """An angle or distance between two fixed points at one place has no direction: refused on load."""
    for g in groups:
        if isinstance(g, JointExpression) and g.expression in ("angle", "distance") and len(g.points) == 2:
            p, q = g.points
            if p in fixed and q in fixed and np.all(np.asarray(fixed[p]) == np.asarray(fixed[q])):
                what = f"{g.expression} of [{p}, {q}], two fixed points at one place"
                raise top.error(f"joint '{g.name}': {what}", "joints")


#: Groups that close a loop: between fixed points only, they would not move with the input.
_CLOSURES = ("rrr", "rrp", "slotted", "triad", "slider_triad")


def _check_moving(top: Entry, fixed: Mapping[str, Any], groups: list[Group]) -> None:
    """A dyad or slotted link that reads only fixed points is a rigid part of the frame, not a
    group of the mechanism: refused on load (give its point as a fixed point instead)."""
    for g in groups:
        needs = g.requires()
        if g.kind in _CLOSURES and needs and all(n in fixed for n in needs):
            made = ", ".join(n for n in g.provides() if n not in g.joints())
            raise top.error(
                f"{g.kind} '{g.name}' reads only fixed points ({', '.join(needs)}): it does not move with the "
                f"input; give {made or 'its point'} as {'fixed points' if ', ' in made else 'a fixed point'} instead",
                "groups",
            )


def _check_names(top: Entry, fixed: Mapping[str, Any], groups: list[Group], dim: int) -> None:
    seen: dict[str, str] = {n: "fixed" for n in fixed}
    names: set[str] = set()
    for g in groups:
        if g.name in names and g.kind != "joint":
            raise top.error(f"two groups are named '{g.name}'", "groups")
        names.add(g.name)
        for n in g.provides():
            if n in seen:
                raise top.error(f"'{n}' is defined twice: by {seen[n]} and by {g.kind} '{g.name}'", "groups")
            seen[n] = f"{g.kind} '{g.name}'"
        spatial = getattr(g, "spatial", False)
        if g.kind != "joint" and spatial != (dim == 3):
            need = "spatial [x, y, z]" if spatial else "planar [x, y]"
            raise top.error(f"{g.kind} '{g.name}' needs {need} fixed points", "fixed")
