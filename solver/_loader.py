"""YAML → validated scene parts: units, fixed points, groups, joints and outputs."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from ._fields import ANGLE_UNITS, LENGTH_UNITS, Entry, Units
from .errors import SceneError
from .groups import GROUP_TYPES, JOINT_KINDS, RRR, Crank, Group, JointExpression
from .groups.rrr import CrankFeed

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


def read_yaml(path: Path) -> Any:
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SceneError(f"cannot read the scene file: {exc.strerror or exc}", file=str(path)) from exc
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        raise SceneError(f"not valid YAML: {exc}", file=str(path)) from exc


def parse_scene(data: Any, *, file: str | None, default_name: str = "scene") -> SceneData:
    top = Entry(data, file=file, where="")
    name = top.name("scene", default_name)
    provenance = str(top.raw("provenance", "")).strip()
    top.raw("description", "")
    units = _units(top)
    fixed, dim = _fixed(top, units)
    groups: list[Group] = []
    for i, raw in enumerate(top.raw("groups", [])):
        groups.append(_group(top.child(f"groups[{i}]", raw), units, fixed))
    for key, parse in SECTION_PARSERS.items():
        if key in top.data:
            groups.extend(parse(top.child(key, top.raw(key)), units, fixed))
    groups = _feed_dyads(groups, fixed)
    groups.extend(_joints(top, _rigid_pairs(groups)))
    _check_names(top, fixed, groups, dim)
    inputs = [g for g in groups if g.drives]
    if len(inputs) != 1:
        raise top.error(f"a scene needs exactly one input (a crank), found {len(inputs)}", "groups")
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
    top.done()
    return SceneData(name, file, provenance, dim, fixed, tuple(groups), input_joint, out_points, out_joints)


def _units(top: Entry) -> Units:
    u = top.child("units", top.raw("units"))
    length, angle = u.name("length"), u.name("angle")
    if length not in LENGTH_UNITS:
        raise u.error(f"unknown length unit '{length}'; use one of {sorted(LENGTH_UNITS)}", "length")
    if angle not in ANGLE_UNITS:
        raise u.error(f"unknown angle unit '{angle}'; use one of {sorted(ANGLE_UNITS)}", "angle")
    u.done()
    return Units(LENGTH_UNITS[length], ANGLE_UNITS[angle])


def _fixed(top: Entry, units: Units) -> tuple[dict[str, Any], int]:
    raw = top.raw("fixed")
    f = top.child("fixed", raw)
    fixed: dict[str, Any] = {}
    dims = set()
    for key in f.data:
        value = f.raw(key)
        ok = isinstance(value, (list, tuple)) and len(value) in (2, 3)
        if ok:
            ok = all(isinstance(v, (int, float)) and not isinstance(v, bool) and np.isfinite(v) for v in value)
        if not ok:
            raise f.error(f"must be [x, y] or [x, y, z] in {top.data.get('units')}, got {value!r}", str(key))
        xyz = [float(v) * units.length for v in value]
        dims.add(len(xyz))
        fixed[str(key)] = complex(xyz[0], xyz[1]) if len(xyz) == 2 else np.array(xyz)
    if not fixed:
        raise f.error("name at least one fixed point")
    if len(dims) != 1:
        raise f.error("mixes planar [x, y] and spatial [x, y, z] points")
    return fixed, dims.pop()


def _group(e: Entry, units: Units, fixed: Mapping[str, Any]) -> Group:
    kind = e.name("type")
    cls = GROUP_TYPES.get(kind)
    if cls is None:
        raise e.error(f"unknown group type '{kind}'; known types: {', '.join(sorted(GROUP_TYPES))}", "type")
    group = cls.from_entry(e, units, fixed)
    e.done()
    return group


def _feed_dyads(groups: list[Group], fixed: Mapping[str, Any]) -> list[Group]:
    """Tell an RRR dyad driven directly by the crank against a fixed pivot its crank's geometry."""
    cranks = {g.point: g for g in groups if isinstance(g, Crank)}
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


def _joints(top: Entry, rigid: Mapping[frozenset[str], float]) -> list[Group]:
    j = top.child("joints", top.raw("joints", {}))
    out: list[Group] = []
    for name in j.data:
        spec = j.child(str(name), j.raw(name))
        kinds = [k for k in spec.data if k in JOINT_KINDS]
        if len(kinds) != 1 or len(spec.data) != 1:
            raise spec.error(f"must be one of {{{', '.join(f'{k}: …' for k in JOINT_KINDS)}}}, got {dict(spec.data)!r}")
        kind = kinds[0]
        count = JOINT_KINDS[kind]
        pts = spec.names(kind, count) if count > 1 else (spec.name(kind),)
        length = rigid.get(frozenset(pts)) if kind == "angle" else None
        out.append(JointExpression(name=str(name), expression=kind, points=pts, rigid_length=length))
    return out


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
