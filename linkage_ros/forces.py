"""What the node publishes of a scene's forces, read off the solver's result (no ROS here).

A scene with ``bodies``, ``gravity`` or ``loads`` (docs/forces.md) has, at every instant, an
effort per input joint (``k.effort(joint)``: N·m about +z for a crank, N along the guide for a
slider input) and a load at every pair of bodies: the solver's pins (revolute pairs) and slides
(prismatic pairs). The engine puts them into each :class:`~linkage_ros.frame.Frame`:

* ``frame.efforts``: input joint → effort (float);
* ``frame.loads``: load key → ``(Fx, Fy, M)``: the force (N, world frame) on the pair's first
  body from the other, and the couple (N·m about +z) — zero for a pin, the guide's couple on the
  block for a slide (taken at the block's point).

Topics: ``pin_loads/<name>`` and ``slide_loads/<name>``, where the name is the pair's point; where
several pins share a point, each but the first adds its body's name (``<P>_<body>``, dots turned
into underscores). A load's *key* (in ``frame.loads``, the rerun entities) is that name for a pin
and ``<name>_slide`` for a slide, so that a block's pin and its slide at one point stay apart.
:class:`LoadPair` lists them with their bodies.
A scene without forces has none of this: the frames' ``efforts`` and ``loads`` are empty and
every message is as before.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "KIND_PIN",
    "KIND_SLIDE",
    "TOPIC_PREFIX",
    "LoadPair",
    "effort_units",
    "force_layout",
    "forces_row",
    "frame_forces",
    "has_forces",
    "load_pairs",
    "run_forces",
    "sampled_loads",
]

KIND_PIN = "pin"
KIND_SLIDE = "slide"
#: The first part of the load topics, by kind of pair.
TOPIC_PREFIX = {KIND_PIN: "pin_loads", KIND_SLIDE: "slide_loads"}
_UNSAFE = re.compile(r"[^A-Za-z0-9_]")


class LoadPair(NamedTuple):
    """One published load: the force on ``body`` from ``other`` at ``point`` (``kind`` pin or
    slide; for a slide ``other`` is the guide: ``ground`` or a slotted link), on ``topic``."""

    key: str
    kind: str
    point: str
    body: str
    other: str
    topic: str


def force_layout(scene: Any, inputs: Sequence[str]) -> tuple[bool, tuple[LoadPair, ...], dict[str, str]]:
    """``(has_forces, load_pairs, effort_units)`` of ``scene`` with input joints ``inputs``."""
    forces = has_forces(scene)
    return forces, load_pairs(scene), effort_units(scene, inputs) if forces else {}


def has_forces(scene: Any) -> bool:
    """Whether ``scene`` has bodies, gravity or loads (else no effort and no load is published)."""
    return bool(getattr(scene, "has_forces", False))


def load_pairs(scene: Any) -> tuple[LoadPair, ...]:
    """The scene's pins, then its slides, with their keys (empty without forces)."""
    if not has_forces(scene):
        return ()
    out: list[LoadPair] = []
    for kind, pairs in ((KIND_PIN, scene.pins), (KIND_SLIDE, scene.slides)):
        taken: set[str] = set()
        for pair in pairs:
            other = pair.other if kind == KIND_PIN else pair.guide
            name = pair.point if pair.point not in taken else _UNSAFE.sub("_", f"{pair.point}_{pair.body}")
            taken.add(name)
            key = name if kind == KIND_PIN else f"{name}_slide"
            out.append(LoadPair(key, kind, pair.point, pair.body, other, f"{TOPIC_PREFIX[kind]}/{name}"))
    return tuple(out)


def effort_units(scene: Any, inputs: Sequence[str]) -> dict[str, str]:
    """Each input's effort unit: N·m for an angle, N for a slide."""
    units = getattr(scene, "joint_units", {})
    return {q: "N" if units.get(q, "rad") == "m" else "N·m" for q in inputs}


def _pair_load(k: Any, pair: LoadPair) -> tuple[Any, Any, Any]:
    """(Fx, Fy, M) of one pair from a solved result (floats, or (N,) arrays)."""
    if pair.kind == KIND_PIN:
        force = k.reaction(pair.point, on=pair.body, by=pair.other)
        return force[..., 0], force[..., 1], 0.0
    slide = k.slide_reaction(pair.body)
    return slide.force[..., 0], slide.force[..., 1], slide.couple


def frame_forces(k: Any, inputs: Sequence[str], pairs: Sequence[LoadPair]
                 ) -> tuple[dict[str, float], dict[str, tuple[float, float, float]]]:
    """Efforts and loads of a one-instant solve, as Python floats."""
    efforts = {q: float(k.effort(q)) for q in inputs}
    loads = {}
    for pair in pairs:
        fx, fy, m = _pair_load(k, pair)
        loads[pair.key] = (float(fx), float(fy), float(m))
    return efforts, loads


def run_forces(k: Any, inputs: Sequence[str], pairs: Sequence[LoadPair]
               ) -> tuple[dict[str, NDArray[np.float64]], dict[str, NDArray[np.float64]]]:
    """Efforts ((N,) each) and loads ((N, 3) each: Fx, Fy, M) of a vectorised solve."""
    efforts = {q: np.asarray(k.effort(q), dtype=np.float64).reshape(-1) for q in inputs}
    loads = {}
    for pair in pairs:
        columns = np.broadcast_arrays(*(np.asarray(c, dtype=np.float64) for c in _pair_load(k, pair)))
        loads[pair.key] = np.stack([c.reshape(-1) for c in columns], axis=1)
    return efforts, loads


def forces_row(forces: tuple[Mapping[str, Any], Mapping[str, Any]], i: Any
               ) -> tuple[dict[str, float], dict[str, tuple[float, float, float]]]:
    """Sample ``i`` of :func:`run_forces`' efforts and loads, as Python floats."""
    efforts, loads = forces
    return ({q: float(v[i]) for q, v in efforts.items()},
            {key: (float(v[i, 0]), float(v[i, 1]), float(v[i, 2])) for key, v in loads.items()})


def sampled_loads(k: Any, inputs: Sequence[str], pairs: Sequence[LoadPair]) -> dict[str, NDArray[np.float64]]:
    """(Fx, Fy) of every load of a masked vectorised solve, at its valid, finite samples only."""
    valid = np.asarray(k.valid, dtype=bool)
    _, loads = run_forces(k, inputs, pairs)
    return {key: np.ascontiguousarray(v[valid & np.isfinite(v).all(axis=1), :2]) for key, v in loads.items()}
