"""Template scenes: a scene file in which some numbers are design variables, ``{free: [lo, hi]}``.

A free value stands where a number may stand and is named by its place in the file:
``fixed.O[0]`` (a fixed point's coordinate, one by one), ``groups[1].length`` (a crank),
``groups[1].lengths[0]`` (a dyad's link), ``groups[2].distance`` / ``groups[2].angle`` (an
attached point), ``groups[3].guide.angle`` / ``groups[3].guide.offset`` (a slider's guide),
``groups[4].lengths[2]``, ``groups[4].sides[0]``, ``groups[4].shape.F[1]`` (a triad's binary link,
ternary link side, shape point coordinate; its mode θ₀ stays given; a slider triad's too, and its
guide's ``guide.angle`` / ``guide.offset``), in the scene's units.
Everything else of the file is an ordinary scene, validated on load with every free value at the
middle of its range.

Two evaluations of one file:

* :meth:`Template.scene` — one design: the free values written into the file's data and the
  whole file loaded as any scene is (every check of the loader applies);
* :meth:`Template.population` — C designs at once: each group's ``from_entry`` reads the same
  entry with every free number an array of C values (shape (C, 1)), so the groups' parameters
  carry one more leading axis and the plan solves candidates × samples in one pass.
"""

from __future__ import annotations

import math
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from .._fields import MISSING, Entry, Units, read_units, show, suggest
from .._loader import SceneData, _joints, _rigid_pairs, parse_scene
from .._yaml import line_of, load_yaml
from ..errors import SceneError
from ..forces import ForceModel
from ..forces.parse import parse_forces
from ..groups import GROUP_TYPES, RRR, Group
from ..plan import Plan, build_plan, order_groups
from ..scene import Scene, find_scene

__all__ = ["Free", "Template", "load_template", "FREE_PLACES"]

#: Where a group may have free values, by group type: the keys (dotted within the group, with
#: ``[i]`` for an item of a list) and what each is.
FREE_PLACES: dict[str, dict[str, str]] = {
    "crank": {"length": "length"},
    "rrr": {"lengths[0]": "length", "lengths[1]": "length"},
    "attached": {"distance": "length", "angle": "angle"},
    "rrp": {"length": "length", "guide.angle": "angle", "guide.offset": "signed"},
    "triad": {"lengths[0]": "length", "lengths[1]": "length", "lengths[2]": "length",
              "sides[0]": "length", "sides[1]": "length", "sides[2]": "length"},
    "slider_triad": {"lengths[0]": "length", "lengths[1]": "length", "guide.angle": "angle",
                     "guide.offset": "signed", "sides[0]": "length", "sides[1]": "length", "sides[2]": "length"},
}


@dataclass(frozen=True)
class Free:
    """One design variable: its place in the file, its range (scene units) and what it is."""

    place: str
    lo: float
    hi: float
    kind: str  # "length" (positive), "signed" (a coordinate or offset) or "angle"
    path: tuple[Any, ...]  # keys from the file's top to the value


def _is_free(value: Any) -> bool:
    return isinstance(value, Mapping) and "free" in value


def _place(path: Sequence[Any]) -> str:
    out = ""
    for key in path:
        out += f"[{key}]" if isinstance(key, int) else (f".{key}" if out else str(key))
    return out


def _walk(data: Any, path: tuple[Any, ...] = ()) -> Iterable[tuple[tuple[Any, ...], Any, Any]]:
    """Every free marker: (path, its container, the key in it)."""
    items: Iterable[tuple[Any, Any]]
    if isinstance(data, Mapping):
        items = data.items()
    elif isinstance(data, list):
        items = enumerate(data)
    else:
        return
    for key, value in items:
        if _is_free(value):
            yield (*path, key), data, key
        else:
            yield from _walk(value, (*path, key))


def _kind_of(path: tuple[Any, ...], data: Mapping[str, Any]) -> str | None:
    """What the free value at ``path`` is, or None where a number cannot vary."""
    if len(path) == 3 and path[0] == "fixed" and path[2] in (0, 1):
        return "signed"
    if len(path) >= 3 and path[0] == "groups" and isinstance(path[1], int):
        groups = data.get("groups")
        group = groups[path[1]] if isinstance(groups, list) and path[1] < len(groups) else None
        kind = group.get("type") if isinstance(group, Mapping) else None
        if kind in ("triad", "slider_triad") and len(path) == 5 and path[2] == "shape" and path[4] in (0, 1):
            return "signed"  # groups[i].shape.D[0]: a ternary link's local point, x or y
        return FREE_PLACES.get(kind, {}).get(_place(path[2:])) if isinstance(kind, str) else None
    return None


def _read_free(value: Mapping[str, Any], place: str, kind: str, file: str | None, line: int | None) -> Free:
    def fail(message: str) -> SceneError:
        return SceneError(message, file=file, entry=place, line=line)

    if set(value) != {"free"}:
        extra = sorted(str(k) for k in value if k != "free")
        raise fail(f"a free value is {{free: [lo, hi]}} alone; unknown field(s): {', '.join(extra)}")
    bounds = value["free"]
    if not isinstance(bounds, list) or len(bounds) != 2:
        raise fail(f"free must be [lo, hi], got {show(bounds)}")
    for b in bounds:
        if isinstance(b, bool) or not isinstance(b, (int, float)) or not math.isfinite(b):
            raise fail(f"free must be [lo, hi] with finite numbers, got {show(bounds)}")
    lo, hi = float(bounds[0]), float(bounds[1])
    if lo > hi:
        raise fail(f"free range [{lo:g}, {hi:g}] has lo > hi")
    if kind == "length" and lo <= 0.0:
        raise fail(f"a length's free range must be positive, got [{lo:g}, {hi:g}]")
    return Free(place, lo, hi, kind, ())


def _known_type(data: Mapping[str, Any], index: int, file: str | None) -> None:
    """The loader's own refusal of an unknown group type, before "cannot vary" would mislead."""
    groups = data.get("groups")
    group = groups[index] if isinstance(groups, list) and index < len(groups) else None
    kind = group.get("type") if isinstance(group, Mapping) else None
    if isinstance(kind, str) and kind not in GROUP_TYPES:
        near = suggest(kind, GROUP_TYPES)
        hint = f" (did you mean '{near[0]}'?)" if near else ""
        raise SceneError(f"unknown group type '{kind}'{hint}; known types: {', '.join(sorted(GROUP_TYPES))}",
                         file=file, entry=f"groups[{index}].type", line=line_of(group, "type"))


class _ArrayEntry(Entry):
    """An entry whose free numbers are arrays of C candidates' values, shape (C, 1): the
    groups' ``from_entry`` build groups whose parameters broadcast against (C, S) samples.
    (Ranges were checked once, on the template's bounds.)"""

    def as_number(self, value: Any, key: str) -> Any:
        return value if isinstance(value, np.ndarray) else super().as_number(value, key)

    def length_value(self, value: Any, key: str, units: Units, *, positive: bool = True) -> Any:
        if isinstance(value, np.ndarray):
            return value * units.length
        return super().length_value(value, key, units, positive=positive)

    def angle(self, key: str, units: Units, default: Any = MISSING) -> Any:
        value = self.raw(key, default)
        if isinstance(value, np.ndarray):
            return value * units.angle
        return super().angle(key, units, default)


def _set(data: Any, path: tuple[Any, ...], value: Any) -> None:
    for key in path[:-1]:
        data = data[key]
    data[path[-1]] = value


class Template:
    """A scene file with free values; see the module docstring."""

    def __init__(self, data: Any, *, file: str | None = None) -> None:
        if not isinstance(data, Mapping):
            raise SceneError("a template is a scene file: a mapping of sections (docs/scenes.md)", file=file)
        self.file = file
        self.data = data
        frees: list[Free] = []
        for path, container, key in _walk(data):
            place = _place(path)
            line = line_of(container, key)
            kind = _kind_of(path, data)
            if kind is None and path[0] == "groups" and isinstance(path[1], int) and len(path) > 2:
                _known_type(data, path[1], file)
            if kind is None:
                raise SceneError(
                    "a free value in a place that cannot vary (free values: fixed points' coordinates, "
                    "lengths, an attached point's distance and angle, a guide's angle and offset, a triad's "
                    "lengths, sides and shape)",
                    file=file, entry=place, line=line,
                )
            frees.append(replace(_read_free(container[key], place, kind, file, line), path=path))
        if not frees:
            raise SceneError("a template needs at least one {free: [lo, hi]} value", file=file)
        self.free: tuple[Free, ...] = tuple(frees)
        self.lo = np.array([f.lo for f in frees])
        self.hi = np.array([f.hi for f in frees])
        self.units: Units = read_units(Entry(data, file=file, where=""))
        self.template_scene: Scene = self.scene(0.5 * (self.lo + self.hi), design=False)  # the rest of the file checked

    @property
    def periods(self) -> np.ndarray:
        """Per free value, its period in scene units where it is an angle free over a whole turn
        (the polish lets it wrap instead of stopping at a bound), else inf."""
        turn = 2.0 * math.pi / self.units.angle
        return np.array([turn if f.kind == "angle" and f.hi - f.lo >= turn * (1.0 - 1e-12) else np.inf
                         for f in self.free])

    @property
    def places(self) -> tuple[str, ...]:
        return tuple(f.place for f in self.free)

    @property
    def design_name(self) -> str:
        """The scene name of a design: the template's with ``_synth`` (a saved design is not the template)."""
        name = self.data.get("scene") if isinstance(self.data.get("scene"), str) else None
        return f"{name or Path(self.file or 'template').stem}_synth"

    def label(self, free: Free) -> str:
        """What a free value is in the mechanism's words: ``dyad A–B`` for ``groups[1].lengths[0]``,
        ``O x`` for ``fixed.O[0]`` (the place alone names it by position only)."""
        path = free.path
        if path[0] == "fixed":
            return f"{path[1]} {'xy'[path[2]]}"
        group = self.data["groups"][path[1]]
        name = str(group.get("name", f"groups[{path[1]}]"))
        point = group.get("point", "?")
        key = _place(path[2:])
        if group.get("type") in ("triad", "slider_triad"):
            slider = group.get("type") == "slider_triad"  # ends [B, C] to points E, F (D is on the guide)
            ends, pts = group.get("ends") or ["?"] * 3, group.get("points") or ["?"] * 3
            if key.startswith("lengths["):
                return f"{name} {ends[path[3]]}–{pts[path[3] + int(slider)]}"
            if key.startswith("sides["):
                return f"{name} {pts[path[3]]}–{pts[(path[3] + 1) % 3]}"
            if key.startswith("shape."):
                return f"{name} {path[3]} {'xy'[path[4]]} (ternary link's frame)"
        if key == "length" and group.get("type") == "crank":
            return f"{name} {group.get('center', '?')}–{point}"
        if key == "length":
            return f"{name} {group.get('end', '?')}–{point}"
        if key.startswith("lengths["):
            ends = group.get("ends") or ["?", "?"]
            return f"{name} {ends[path[3]]}–{point}"
        if key == "distance":
            return f"{name} {group.get('base', '?')}–{point}"
        if key == "angle":
            return f"{name} angle of {point}"
        return f"{name} {key.replace('.', ' ')}"

    def values_of(self, x: Sequence[float] | np.ndarray) -> dict[str, float]:
        return {f.place: float(v) for f, v in zip(self.free, x)}

    def filled(self, x: Sequence[float] | np.ndarray, *, design: bool = True) -> Any:
        """The file's data with the free values set to ``x`` (scene units); a ``design`` is named
        :attr:`design_name`."""
        data = _plain(self.data)
        for f, v in zip(self.free, x):
            _set(data, f.path, float(v))
        if design:
            data["scene"] = self.design_name
        return data

    def scene_data(self, x: Sequence[float] | np.ndarray, *, design: bool = True) -> SceneData:
        return parse_scene(self.filled(x, design=design), file=self.file,
                           default_name=Path(self.file or "template").stem)

    def scene(self, x: Sequence[float] | np.ndarray, *, design: bool = True) -> Scene:
        """The loaded scene of one design (every free value set, every loader check applied)."""
        return Scene(self.scene_data(x, design=design))

    # -- populations ----------------------------------------------------------------------------
    def _parts(self, x: np.ndarray) -> tuple[Entry, dict[str, Any], list[Group]]:
        """The file read with every free number a (C, 1) array: its top entry, fixed points, groups."""
        x = np.asarray(x, float)
        data = _plain(self.data)
        for i, f in enumerate(self.free):
            _set(data, f.path, x[:, i : i + 1])
        top = _ArrayEntry(data, file=self.file, where="")
        units = self.units
        fixed: dict[str, Any] = {}
        for name, xy in data["fixed"].items():
            if any(isinstance(v, np.ndarray) for v in xy):
                fixed[str(name)] = (np.asarray(xy[0], float) + 1j * np.asarray(xy[1], float)) * units.length
            else:
                fixed[str(name)] = self.template_scene._data.fixed[str(name)]
        groups: list[Group] = []
        for i, raw in enumerate(data.get("groups") or []):
            e = top.child(f"groups[{i}]", raw)
            groups.append(GROUP_TYPES[raw["type"]].from_entry(e, units, fixed))
        tdata = self.template_scene._data
        n_listed = len(groups)
        sections = [g for g in tdata.groups[n_listed:] if g.kind != "joint"]  # contours: constants
        groups = [replace(g, feed=None) if isinstance(g, RRR) else g for g in [*groups, *sections]]
        groups.extend(_joints(top, _rigid_pairs(groups), units, tdata.dim))
        return top, fixed, groups

    def population(self, x: np.ndarray, targets: Sequence[str], *, forces: bool = False) -> tuple[Plan, Any]:
        """The plan of ``len(x)`` designs at once (every free number a (C, 1) array), and with
        ``forces`` the force layer of those designs (their bodies' frames from their own
        lengths; None when the template names no bodies or loads)."""
        top, fixed, groups = self._parts(x)
        model = None
        if forces and self.template_scene.forces is not None:
            spec = parse_forces(top, self.units, fixed, groups)
            model = None if spec is None else ForceModel(spec, self.template_scene.inputs)
            targets = (*targets, *(() if model is None else model.targets))
        ordered = order_groups(groups, fixed, file=self.file)
        return build_plan(ordered, fixed, targets), model


def _plain(data: Any) -> Any:
    """Plain dicts and lists (the YAML reader's line-keeping containers copied without lines)."""
    if isinstance(data, Mapping):
        return {k: _plain(v) for k, v in data.items()}
    if isinstance(data, list):
        return [_plain(v) for v in data]
    return data


def load_template(template: str | os.PathLike[str] | Template | Mapping[str, Any]) -> Template:
    """A template from a path (or a shipped scene's name), from parsed YAML data, or as given."""
    if isinstance(template, Template):
        return template
    if isinstance(template, Mapping):
        return Template(template)
    path = find_scene(template)
    return Template(load_yaml(path), file=str(path))
