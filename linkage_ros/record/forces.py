"""Forces in the recorded view: arrows at the pins and the input efforts over time.

Scenes with ``bodies``, ``gravity`` or ``loads`` (docs/forces.md) carry, beside the kinematics of
a :class:`~linkage_ros.record.rundata.RunData`, the effort of every input (``efforts``) and the
load of every pin (``loads``: the force on one named body from the other, world frame, and for
a prismatic pair the couple; docs/ros.md "Forces"). :mod:`.rerun` draws them with the functions
here; :func:`forces_from_mcap` reads the same arrays back from a recording.

Entity layout (beside :mod:`.rerun`'s)::

    mechanism/loads/<K>      Arrows per tick at the point of pin load K: along the force, its
                             length by the run's rule (the rule in the legend), wider than the
                             links (named ``R_K``, :func:`load_label`, on hover)
    mechanism/loads/<K>/label  Points per tick: the label ``R_K`` beyond the arrow's tip
                             (:func:`label_positions`)
    plots/effort/<Q>         Scalars: the effort of input Q (N·m for a crank, N for a slider)

The rule is the node's (:func:`linkage_ros.forces.load_arrows`, docs/ros.md "Forces"): a round
scale (1, 2 or 5 × 10^k m/N) that draws a long load (the 95th percentile of all pin loads of the
run, at most 1.5 × their median) at about a quarter of the mechanism's extent; when the largest
load would then be longer than half the extent, loads above a knee (drawn at a quarter of the
extent) grow by one knee length per tenfold, or less so that the peak is drawn half the extent
long (the engine: 5e-4 m/N up to 131 N, then +0.031 m per ×10: its 15.6 kN peak 0.13 m long).
"""

from __future__ import annotations

import json
from collections.abc import Callable, Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from ..forces import KIND_PIN, TOPIC_PREFIX, LoadArrows, load_arrows
from ._drawing import DRAW_ORDER, log_series, plot_view, position_of
from .rundata import RunData

__all__ = [
    "EFFORT_ORIGIN",
    "LOADS_ENTITY",
    "LOAD_COLOR",
    "effort_views",
    "forces_from_mcap",
    "forces_legend",
    "forces_metadata",
    "force_sections",
    "label_positions",
    "load_label",
    "load_rule",
    "log_forces",
]

LOADS_ENTITY = "mechanism/loads"
EFFORT_ORIGIN = "plots/effort"
LOAD_COLOR = (200, 70, 210)
"""Magenta: apart from the links (blue), pivots (red), velocity (green), acceleration (orange)."""
LOAD_ARROW_WIDTH = 1.4
"""A load arrow's radius in link radii: wider than the links, so that an arrow along a link (a
connecting rod's pin loads lie on the rod) covers it in its own colour instead of running
inside it as a thin stripe (the velocity and acceleration arrows are 0.5)."""


LABEL_GAP, LABEL_REACH, LABEL_CHAR = 10.0, 20.0, 2.5
"""A load's label is centred beyond its arrow's tip: ``LABEL_GAP`` link radii past it, plus
``LABEL_CHAR`` per character of the label times the arrow's horizontal part (a label is wider
than tall), and at least ``LABEL_REACH`` link radii from the pin (:func:`label_positions`). At
the default window a link radius is 1–2 px and a character about 6 px."""


def load_label(key: str) -> str:
    """The label drawn at a load's arrow: ``R_A`` for the pin A, ``R_B_slide`` for the slide at B."""
    return f"R_{key}"


Array = NDArray[np.float64]


def label_positions(origins: Array, vectors: Array, radius: float, turn: float, *, chars: int = 3) -> Array:
    """(N, dim) anchors of a load's label of ``chars`` characters: along its arrow, beyond the
    tip (:data:`LABEL_GAP`, :data:`LABEL_CHAR`) and never nearer the pin than
    :data:`LABEL_REACH` link radii, so that the label clears the arrow and the pin's own name;
    where the arrow vanishes, in the direction ``turn`` (rad). The viewer draws an arrow's own
    label at its middle, where the labels of two short arrows at one pin (the engine's ``R_B``
    and ``R_B_slide``) and the pin's name fall on each other."""
    o = np.asarray(origins, dtype=np.float64)
    v = np.asarray(vectors, dtype=np.float64)[:, :2]
    length = np.hypot(v[:, 0], v[:, 1])
    away = np.empty_like(v)
    away[:] = (np.cos(turn), np.sin(turn))
    np.divide(v, length[:, None], out=away, where=length[:, None] > 1e-9 * radius)
    gap = (LABEL_GAP + LABEL_CHAR * chars * np.abs(away[:, 0])) * radius
    out = np.array(o, dtype=np.float64, copy=True)
    out[:, :2] += away * np.maximum(length + gap, LABEL_REACH * radius)[:, None]
    return out


def load_rule(data: RunData) -> LoadArrows:
    """How long the load arrows of ``data`` are drawn (scale 1 when the run has no loads or all
    are zero)."""
    return load_arrows({k: v[:, :2] for k, v in data.loads.items()}, data.extent())


def arrow_vectors(rule: LoadArrows, forces: Array, dim: int) -> Array:
    """(N, dim) drawn arrows of (N, 2+) forces: along each force, of :meth:`LoadArrows.length`."""
    f = np.asarray(forces, dtype=np.float64)[:, :2]
    out = np.zeros((f.shape[0], dim))
    out[:, :2] = f * rule.factor(np.hypot(f[:, 0], f[:, 1]))[:, None]
    return out


def log_forces(rec: Any, data: RunData, times: Any, *, radius: float) -> LoadArrows:
    """Log the load arrows and the effort series of ``data`` into ``rec`` (nothing when the run
    has no forces); returns the arrows' rule."""
    import rerun as rr

    rule = load_rule(data)
    if not data.n:
        return rule
    arrows: Any = rr.Arrows3D if data.dim == 3 else rr.Arrows2D
    points: Any = rr.Points3D if data.dim == 3 else rr.Points2D
    order: dict[str, Any] = {"draw_order": DRAW_ORDER["arrows"]} if data.dim == 2 else {}
    at_pin: dict[str, int] = {}
    for key, values in data.loads.items():
        entity = f"{LOADS_ENTITY}/{key}"
        point = data.load_pins.get(key, (key,))[0]
        if point not in data.positions and point not in data.fixed:
            continue
        vectors = arrow_vectors(rule, values, data.dim)
        origins = position_of(data, point)
        rec.log(entity, arrows.from_fields(radii=LOAD_ARROW_WIDTH * radius, colors=LOAD_COLOR,
                                           labels=[load_label(key)], show_labels=False, **order), static=True)
        rec.send_columns(entity, indexes=[times], columns=arrows.columns(origins=origins, vectors=vectors))
        # the label as a point of its own beyond the tip (the viewer puts an arrow's at its middle)
        turn = 0.25 * np.pi + 0.5 * np.pi * at_pin.setdefault(point, 0)  # a vanished arrow: NE, NW, …
        at_pin[point] += 1
        rec.log(f"{entity}/label", points.from_fields(radii=0.5 * radius, colors=LOAD_COLOR, labels=[load_label(key)],
                                                      show_labels=True, **order), static=True)
        rec.send_columns(f"{entity}/label", indexes=[times], columns=points.columns(
            positions=label_positions(origins, vectors, radius, turn, chars=len(load_label(key)))))
    joints = list(data.joints)
    for i, (joint, values) in enumerate(data.efforts.items()):
        unit = data.effort_units.get(joint, "N·m")
        colour = joints.index(joint) if joint in joints else i  # the input joint's colour
        log_series(rec, f"{EFFORT_ORIGIN}/{joint}", f"Q {joint} ({unit})", times, values, colour)
    return rule


def effort_views(data: RunData) -> list[Any]:
    """The blueprint's plot of the input efforts (empty without forces)."""
    if not data.efforts:
        return []
    units = sorted(set(data.effort_units.get(j, "N·m") for j in data.efforts))
    plural = "inputs'" if len(data.efforts) > 1 else "input"
    return [plot_view(EFFORT_ORIGIN, f"{plural} effort ({' | '.join(units)})", *data.efforts.values(),
                  contents=[f"/{EFFORT_ORIGIN}/{q}" for q in data.efforts])]


def forces_legend(data: RunData, rule: LoadArrows) -> str:
    """The legend's sentence about the load arrows and their rule ("" without loads)."""
    if not data.loads:
        return ""
    each = ", ".join(f"{key} on {on} from {by}" if on else key
                     for key, (_, on, by) in ((k, data.load_pins.get(k, (k, "", ""))) for k in data.loads))
    return f"Magenta: pin loads **R {rule.describe()}**: {each}. "


def force_sections(scene: Any, data: RunData) -> list[Any]:
    """The summary section of a run's forces (:func:`solver.forces.report.force_section`: peak and
    RMS efforts, peak input power, peak pin and slide loads, read off the run's ticks), for
    ``summary_lines(..., sections=...)``; none without forces or ticks. The ticks' input states are
    solved once more, vectorised (the run keeps the efforts and loads, not a solver result)."""
    if not getattr(scene, "has_forces", False) or not data.n:
        return []
    from solver.forces.report import force_section

    k = scene.solve(data.phi, omega=data.omega, epsilon=data.epsilon, mask=True)
    step = float(data.t[1] - data.t[0]) if data.n > 1 else 0.0
    return [force_section(scene, k, sampling=f"read off {data.n} ticks, every {step:g} s", times=data.t)]


# ---------------------------------------------------------------------------------- replay
def forces_metadata(engine: Any) -> dict[str, str]:
    """The metadata keys a recording of a scene with forces adds (none without forces):
    ``loads`` (``[key, kind, point, body, other, topic]`` per load) and ``effort_units``."""
    if not getattr(engine, "forces", False):
        return {}
    return {"loads": json.dumps([list(p) for p in engine.load_pairs]),
            "effort_units": json.dumps(dict(engine.effort_units))}


def forces_from_mcap(
    ts: Any,
    meta: Mapping[str, str],
    topics: Mapping[str, str],
    rows: Callable[[str], list[bytes]],
    types: Mapping[str, str],
    joint_kinematics: tuple[str, list[bytes], Sequence[str]],
) -> dict[str, Any]:
    """The :class:`RunData` fields ``efforts``, ``loads``, ``load_pins``, ``effort_units`` of a
    recording: the loads from its ``pin_loads/<name>`` and ``slide_loads/<name>`` topics
    (``topics``: relative name → recorded name; ``rows(rel)``: their messages at the run's
    ticks; ``types``: recorded name → type), the inputs' efforts from ``joint_kinematics``'
    effort (its type, messages and joint names; the inputs from the metadata, else the joints
    whose effort is not zero at every tick). Empty for a recording without forces."""
    from .cdr import extract

    pairs = [(str(p[0]), (str(p[2]), str(p[3]), str(p[4])), str(p[5])) for p in json.loads(meta.get("loads", "[]"))]
    if not pairs:  # no metadata: the keys from the topic names, the bodies unknown
        pairs = [(name if kind == TOPIC_PREFIX[KIND_PIN] else f"{name}_slide", (name, "", ""), rel)
                 for rel in sorted(topics) for kind, _, name in [rel.partition("/")]
                 if kind in TOPIC_PREFIX.values()]
    wrench = [("wrench", "force", "x"), ("wrench", "force", "y"), ("wrench", "torque", "z")]
    loads = {key: extract(ts, types[topics[rel]], rows(rel), lambda _m: wrench)
             for key, _, rel in pairs if rel in topics}
    out: dict[str, Any] = {"loads": loads, "load_pins": {key: pin for key, pin, _ in pairs if key in loads},
                           "efforts": {}, "effort_units": {}}
    typename, messages, names = joint_kinematics
    inputs = [str(q) for q in json.loads(meta.get("inputs", "[]"))] or [meta.get("input_joint", "")]
    if not (loads and messages):
        return out
    first = ts.deserialize_cdr(messages[0], typename)
    if not first.points or len(first.points[0].effort) != len(names):
        return out
    values = extract(ts, typename, messages, lambda _m: [("points", 0, "effort", i) for i in range(len(names))])
    units = json.loads(meta.get("effort_units", "{}"))
    if not any(inputs):  # no metadata: the joints that carry an effort are the inputs
        inputs = [n for i, n in enumerate(names) if np.any(values[:, i] != 0.0)]
    for q in inputs:
        if q in names:
            out["efforts"][q] = values[:, list(names).index(q)].copy()
            out["effort_units"][q] = str(units.get(q, "N·m"))
    return out
