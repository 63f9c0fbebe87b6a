"""The rerun view of a run: the moving mechanism beside time-series plots.

Everything is logged on the ``sim_time`` timeline (run time, s) as whole-run columns
(``send_columns``); what does not move (fixed pivots, the path of each published point over a
cycle, the legend) is logged static. The data come in as a
:class:`~linkage_ros.record.rundata.RunData` of arrays, built either from the engine's frames
(:class:`~linkage_ros.record.rundata.RunBuilder`) or from the messages of a recorded MCAP file
(:mod:`linkage_ros.record.replay`), so both give the same view.

Entity layout::

    mechanism/links/<link>          LineStrips2D/3D per tick
    mechanism/links/<A>/{barrel,rod}  an actuator's cylinder: its barrel (thick) and rod, per tick
    mechanism/points                Points2D/3D per tick, labelled with the point names
    mechanism/fixed                 static, larger, labelled
    mechanism/paths/<P>             static path of each published point over one cycle
    mechanism/velocity/<P>          Arrows per tick, v · scale (scale in the legend and label)
    mechanism/acceleration/<P>      Arrows per tick, a · scale
    mechanism/loads/<K>             scenes with forces: Arrows per tick at the pins (:mod:`.forces`)
    mechanism/legend                static TextDocument: the arrow scales, the scene
    plots/input/{phi,omega,epsilon} Scalars (one input)
    plots/input/<kind>/<Q>          Scalars per input Q of a several-input scene (kind = phi | omega | epsilon)
    plots/joints/<kind>/<J>         Scalars, kind = position | velocity | acceleration
    plots/effort/<Q>                scenes with forces: Scalars, the effort of input Q (:mod:`.forces`)
    plots/energy/<kind>             dynamic runs: Scalars, the energies and works (:mod:`.energy`)
    plots/energy_balance            dynamic runs: Scalars, the energy balance's error
    plots/friction/<name>           scenes with friction: Scalars (W), total and per element (:mod:`.friction`)
    plots/efficiency                scenes with friction: Scalars, the instantaneous efficiency

A 2-D view draws its y axis downwards (image coordinates; rerun ignores view coordinates in 2-D
views), so each drawn entity of a planar scene carries a static mirror ``Transform3D`` (y → −y,
:data:`Y_UP`): the mechanism appears y up, as in the scene file, and hovering shows the true
coordinates.
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from ..arrows import arrow_scale, nice_scale
from ._drawing import (
    ACCELERATION_COLOR,
    ARROW_WIDTH,
    DRAW_ORDER,
    FIXED_COLOR,
    LINK_COLOR,
    LINK_RADIUS,
    PATH_COLOR,
    PATH_WIDTH,
    PIVOT_SIZE,
    POINT_COLOR,
    POINT_SIZE,
    SERIES_COLOUR_NAMES,
    VELOCITY_COLOR,
    log_series,
    plot_view,
    position_of,
)
from .energy import energy_views, log_energy
from .forces import effort_views, forces_legend, load_rule, log_forces
from .friction import friction_views, log_friction
from .rundata import Array, RunData
from .viewer import viewer_environment, viewer_executable

__all__ = [
    "APPLICATION_ID",
    "TIMELINE",
    "arrow_scale",
    "blueprint",
    "nice_scale",
    "plot_columns",
    "plot_column_count",
    "log_run",
    "write_rrd",
]

APPLICATION_ID = "linkage_ros"
TIMELINE = "sim_time"
LEGEND_CHARS_PER_PX = 0.155
"""Characters of legend text per logical pixel of the mechanism column's width."""
LEGEND_LINE_PX, LEGEND_HEAD_PX, WINDOW_PX = 16.0, 40.0, (1280.0, 740.0)
"""The legend's line height, its title bar plus padding, and the default window's layout area
(width, height below the top bar), logical px: the legend panel is sized to show its text."""
KINDS = ("position", "velocity", "acceleration")
UNIT_TITLES = {
    "rad": ("joint angles (rad)", "joint ω (rad/s)", "joint ε (rad/s²)"),
    "m": ("joint positions (m)", "joint v (m/s)", "joint a (m/s²)"),
}
"""Plot titles by the unit of a joint's position: angles and lengths are never on one axis (short:
a plot's title bar shows about 18 characters at the default window)."""
LEGEND_ROWS = 6
"""Most series in one plot: at the default window (1280 × 800) a plot, three to a column, shows a
legend of this many names in full (rerun draws the legend inside the plot and cuts what does not
fit); more joints go to more plots, side by side."""
PLOTS_SHARE = (2, 1)
"""Width of the mechanism column : width of each column of plots."""
Y_UP = (1.0, -1.0, 1.0)
"""Scale of the mirror that shows a planar mechanism y up in rerun's y-down 2-D view."""
DRAWN_2D = ("links", "points", "fixed", "paths", "velocity", "acceleration", "loads")
"""The children of ``mechanism`` that carry it."""
VIEW_MARGIN = 0.15
"""Margin around the drawing in the 2-D view, in units of its extent: room for most arrows (a
long one, a quarter of the extent, may reach past it)."""
EYE_OFFSET = (0.5, -0.7, 0.45)
"""3-D camera position from the middle of the drawing, in units of its extent."""

#: An actuator's barrel: darker and this many times as thick as a link (its rod is a link's width).
BARREL_COLOR = (40, 80, 140)
BARREL_WIDTH = 2.5

def _fmt(x: float) -> str:
    return f"{x:g}"


def plot_columns(data: RunData) -> list[list[tuple[str, list[str]]]]:
    """The plots, column by column, as ``(title, [entity paths of its series])``: the inputs'
    φ, ω, ε (one plot each), then the other joints' positions, velocities, accelerations, one
    column per unit of the joints (angles in rad, slides in m: :data:`UNIT_TITLES`), with at most
    :data:`LEGEND_ROWS` joints a plot (more joints: more columns), so that each legend shows
    every series name and each axis one unit."""
    plural = "inputs" if data.phi.ndim == 2 else "input"
    inputs = []
    kinds = {data.joint_units.get(q or data.input_joint, "rad") for _, q, _ in data.input_series()}
    for kind, symbol, unit in (("phi", "φ", "rad"), ("omega", "ω", "rad/s"), ("epsilon", "ε", "rad/s²")):
        paths = [f"plots/input/{kind}/{q}" if q else f"plots/input/{kind}"
                 for k, q, _ in data.input_series() if k == kind]
        if kinds == {"m"}:  # actuators' strokes
            symbol, unit = _STROKE[kind]
        elif "m" in kinds:
            unit = f"{unit} | {_STROKE[kind][1]}"
        inputs.append((f"{plural} {symbol} ({unit})", paths))
    # an input's coordinate, rate and acceleration are its φ, ω, ε, plotted apart in the first
    # column: beside the other joints its ever-growing angle would flatten their swings (issue 24),
    # and a second copy of its ω and ε would only take room from the drawing
    driven = set(data.inputs or (data.input_joint,))
    by_unit: dict[str, list[str]] = {}
    for j in data.joints:
        if j not in driven:
            by_unit.setdefault(data.joint_units.get(j, "rad"), []).append(j)
    columns = [inputs]
    order = list(UNIT_TITLES)
    for unit, names in sorted(by_unit.items(), key=lambda kv: order.index(kv[0]) if kv[0] in order else len(order)):
        titles = UNIT_TITLES.get(unit) or tuple(f"joint {kind}s ({unit})" for kind in KINDS)
        for i in range(0, len(names), LEGEND_ROWS):
            chunk = names[i: i + LEGEND_ROWS]
            columns.append([(title, [f"plots/joints/{kind}/{j}" for j in chunk])
                            for kind, title in zip(KINDS, titles)])
    return columns


def plot_column_count(data: RunData) -> int:
    """Columns of plots beside the mechanism: :func:`plot_columns`' and, for a dynamic run, its
    energy column, for a scene with friction its friction column (the legend's width, and so its
    height, depends on all of them)."""
    return len(plot_columns(data)) + (1 if data.energy else 0) + (1 if data.friction else 0)


def legend_share(text: str, columns: int) -> tuple[float, float]:
    """``row_shares`` of the mechanism view and its legend below it, so that the legend shows
    all of ``text`` at the default window when the plots take ``columns`` columns."""
    width = WINDOW_PX[0] * PLOTS_SHARE[0] / (PLOTS_SHARE[0] + PLOTS_SHARE[1] * columns)
    per_line = max(20, int(LEGEND_CHARS_PER_PX * width))
    lines = sum(max(1, math.ceil(len(par) / per_line)) for par in text.strip().split("\n"))
    legend = min(0.45 * WINDOW_PX[1], LEGEND_HEAD_PX + LEGEND_LINE_PX * lines)
    return WINDOW_PX[1] - legend, legend


def blueprint(data: RunData) -> Any:
    """Mechanism view (2-D, or 3-D for spatial scenes) and its legend beside the plots."""
    import rerun.blueprint as rrb

    name = f"{data.scene} — mechanism"
    view: Any
    if data.dim == 3:
        view = rrb.Spatial3DView(origin="mechanism", name=name, eye_controls=_eye(data))
    else:
        view = rrb.Spatial2DView(origin="mechanism", name=name, visual_bounds=_bounds(data))
    layout = plot_columns(data)
    n_columns = plot_column_count(data)
    mechanism = rrb.Vertical(
        view, rrb.TextDocumentView(origin="mechanism/legend", name="legend"),
        row_shares=list(legend_share(legend_text(data), n_columns)))
    values = {f"plots/input/{kind}" + (f"/{q}" if q else ""): v for kind, q, v in data.input_series()}
    for kind, i in (("position", 0), ("velocity", 1), ("acceleration", 2)):
        values.update({f"plots/joints/{kind}/{j}": data.plotted_joint(j)[i] for j in data.joints})
    columns = []
    for c, column in enumerate(layout):
        views = [plot_view(paths[0] if len(paths) == 1 else paths[0].rsplit("/", 1)[0], title,
                       *(values[p] for p in paths), contents=[f"/{p}" for p in paths])
                 for title, paths in column if paths]
        columns.append(rrb.Vertical(*views, *(effort_views(data) if c == 0 else [])))
    if data.energy:  # a dynamic run: a column of its energy plots (.energy)
        columns.append(rrb.Vertical(*energy_views(data)))
    if data.friction:  # a scene with friction: its losses and efficiency (.friction)
        columns.append(rrb.Vertical(*friction_views(data)))
    plots = rrb.Horizontal(*columns)
    return rrb.Blueprint(
        rrb.Horizontal(mechanism, plots, column_shares=[PLOTS_SHARE[0], PLOTS_SHARE[1] * n_columns]),
        rrb.TimePanel(state="collapsed"),
        collapse_panels=True,
    )


def _bounds(data: RunData) -> Any:
    """The 2-D view's bounds: every point, pivot and path of the run with a margin of
    :data:`VIEW_MARGIN` of the extent for the arrows, in the mirrored (y-down) view coordinates,
    so that a short legend panel or a wide mechanism does not push a pivot off the view."""
    import rerun.blueprint as rrb

    pts = np.concatenate([np.zeros((0, 2))] + [p.reshape(-1, 2) for p in data.positions.values()]
                         + [np.asarray(p, dtype=float).reshape(-1, 2) for p in data.fixed.values()]
                         + [p.reshape(-1, 2) for p in data.paths.values()])
    pts = pts[np.isfinite(pts).all(axis=1)]
    if not pts.size:
        return None
    margin = VIEW_MARGIN * data.extent()
    (x0, y0), (x1, y1) = pts.min(axis=0) - margin, pts.max(axis=0) + margin
    return rrb.VisualBounds2D(x_range=(float(x0), float(x1)), y_range=(float(Y_UP[1] * y1), float(Y_UP[1] * y0)))


def _eye(data: RunData) -> Any:
    """A 3-D camera looking at the middle of the drawing from above one corner, z up."""
    import rerun.blueprint as rrb

    pts = np.concatenate([np.zeros((0, 3))] + [p.reshape(-1, 3) for p in data.positions.values()]
                         + [np.asarray(p, dtype=float).reshape(-1, 3)
                            for p in data.fixed.values()])
    if not pts.size:
        return None
    centre = 0.5 * (pts.min(axis=0) + pts.max(axis=0))
    eye = centre + data.extent() * np.array(EYE_OFFSET)
    return rrb.EyeControls3D(position=eye, look_target=centre, eye_up=(0.0, 0.0, 1.0))


def _archetypes(dim: int) -> tuple[Any, Any, Any]:
    import rerun as rr

    if dim == 3:
        return rr.Points3D, rr.LineStrips3D, rr.Arrows3D
    return rr.Points2D, rr.LineStrips2D, rr.Arrows2D


def log_run(rec: Any, data: RunData) -> dict[str, float]:
    """Log ``data`` into the recording stream ``rec``; returns the arrow scales used."""
    import rerun as rr

    points_t, strips_t, arrows_t = _archetypes(data.dim)
    n = data.n

    def order(layer: str) -> dict[str, float]:
        return {"draw_order": DRAW_ORDER[layer]} if data.dim == 2 else {}

    times = rr.TimeColumn(TIMELINE, duration=data.t)
    extent = data.extent()
    radius = LINK_RADIUS * extent
    v_scale = arrow_scale(data.velocities, extent)
    a_scale = arrow_scale(data.accelerations, extent)

    # -- static: y up (2-D), fixed pivots, paths, legend ---------------------------------------
    if data.dim == 2:
        for child in DRAWN_2D:
            rec.log(f"mechanism/{child}", rr.Transform3D(scale=Y_UP), static=True)
    if data.fixed:
        rec.log("mechanism/fixed", points_t(
            np.array(list(data.fixed.values())).reshape(-1, data.dim),
            labels=list(data.fixed), radii=PIVOT_SIZE * radius, colors=FIXED_COLOR,
            show_labels=True, **order("points")), static=True)
    for name, path in data.paths.items():
        if len(path) >= 2:
            rec.log(f"mechanism/paths/{name}", strips_t(
                [path], radii=PATH_WIDTH * radius, colors=PATH_COLOR, **order("paths")),
                static=True)
    legend = legend_text(data)
    rec.log("mechanism/legend", rr.TextDocument(legend, media_type="text/markdown"), static=True)
    if n == 0:
        return {"velocity": v_scale, "acceleration": a_scale}

    # -- per tick: links, cylinders, moving points, arrows -----------------------------------
    drawn = {(a, c) for _, a, c, _ in _drawable(data)}  # a cylinder's line is its barrel and rod
    for link, names in data.links:
        if tuple(names) in drawn:
            continue
        strip = np.stack([position_of(data, p) for p in names], axis=1)  # (N, k, dim)
        rec.log(f"mechanism/links/{link}", strips_t.from_fields(
            radii=radius, colors=LINK_COLOR, labels=[link], show_labels=False, **order("links")),
            static=True)
        rec.send_columns(f"mechanism/links/{link}", indexes=[times],
                         columns=strips_t.columns(strips=strip))
    for name, part, strip, width in cylinder_strips(data):
        entity = f"mechanism/links/{name}/{part}"
        rec.log(entity, strips_t.from_fields(radii=width * radius, colors=LINK_COLOR if part == "rod" else
                                             BARREL_COLOR, labels=[f"{name} {part}"], show_labels=False,
                                             **order("links")), static=True)
        rec.send_columns(entity, indexes=[times], columns=strips_t.columns(strips=strip))
    moving = [p for p in data.positions if p not in data.fixed]
    if moving:
        stacked = np.stack([data.positions[p] for p in moving], axis=1).reshape(-1, data.dim)
        rec.log("mechanism/points", points_t.from_fields(
            labels=moving, radii=POINT_SIZE * radius, colors=POINT_COLOR, show_labels=True,
            **order("points")), static=True)
        rec.send_columns("mechanism/points", indexes=[times],
                         columns=points_t.columns(positions=stacked).partition([len(moving)] * n))
    for kind, vectors, scale, color in (
        ("velocity", data.velocities, v_scale, VELOCITY_COLOR),
        ("acceleration", data.accelerations, a_scale, ACCELERATION_COLOR),
    ):
        unit = "s" if kind == "velocity" else "s²"
        for name, vec in vectors.items():
            entity = f"mechanism/{kind}/{name}"
            label = f"{'v' if kind == 'velocity' else 'a'}_{name} × {_fmt(scale)} {unit}"
            rec.log(entity, arrows_t.from_fields(radii=ARROW_WIDTH * radius, colors=color,
                                                 labels=[label], show_labels=False,
                                                 **order("arrows")), static=True)
            rec.send_columns(entity, indexes=[times], columns=arrows_t.columns(
                origins=data.positions[name], vectors=vec * scale))

    # -- time series -----------------------------------------------------------------------
    units = {"phi": "rad", "omega": "rad/s", "epsilon": "rad/s²"}
    joints = list(data.joints)
    for name, q, values in data.input_series():
        i = joints.index(q or data.input_joint) if (q or data.input_joint) in joints else 0  # the joint's colour
        symbol, unit = _greek(name), units[name]
        if data.joint_units.get(q or data.input_joint) == "m":  # an actuator's stroke: s, ṡ, s̈ in m
            symbol, unit = _STROKE[name]
        if q:  # several inputs: one series per input, e.g. plots/input/phi/q1 "φ q1 (rad)"
            log_series(rec, f"plots/input/{name}/{q}", f"{symbol} {q} ({unit})", times, values, i)
        else:
            log_series(rec, f"plots/input/{name}", f"{symbol} ({unit})", times, values, i)
    for i, joint in enumerate(data.joints):
        p, v, a = data.plotted_joint(joint)
        for kind, values in (("position", p), ("velocity", v), ("acceleration", a)):
            log_series(rec, f"plots/joints/{kind}/{joint}", joint, times, values, i)
    if data.energy:  # a dynamic run: the energies and the balance's error (.energy)
        log_energy(rec, data, times)
    if data.friction:  # a scene with friction: its losses and efficiency (.friction)
        log_friction(rec, data, times)
    if data.loads or data.efforts:  # scenes with forces: arrows at the pins, efforts (.forces)
        rule = log_forces(rec, data, times, radius=radius)
        knee = {"load_knee": rule.knee} if math.isfinite(rule.knee) else {}
        knee |= {"load_decade": rule.decade} if rule.decade is not None else {}
        return {"velocity": v_scale, "acceleration": a_scale, "load": rule.scale, **knee}
    return {"velocity": v_scale, "acceleration": a_scale}


def legend_text(data: RunData) -> str:
    """The legend under the mechanism: the arrow scales (and the load arrows' rule), the colours,
    the ticks, the run's note."""
    n, extent = data.n, data.extent()
    v_scale, a_scale = arrow_scale(data.velocities, extent), arrow_scale(data.accelerations, extent)
    legend = (
        f"**{data.scene}**: velocity arrows (green) **v × {_fmt(v_scale)} s**, "
        f"acceleration arrows (orange) **a × {_fmt(a_scale)} s²** (m/s, m/s² drawn as m); "
        f"grey: path of each published point over one cycle; red: fixed pivots. "
        f"{n} ticks, t = {_fmt(float(data.t[0]) if n else 0.0)} … "
        f"{_fmt(float(data.t[-1]) if n else 0.0)} s.\n"
    )
    # the plots' key, in words as well (a plot's own legend can be hidden or cut by the viewer)
    key = ", ".join(f"{j} {SERIES_COLOUR_NAMES[i % len(SERIES_COLOUR_NAMES)]}" for i, j in enumerate(data.joints))
    legend += f"Plots: one colour per joint, the inputs and efforts in their joint's: {key}.\n"
    if data.loads:  # scenes with forces: the pin-load arrows (.forces)
        legend += forces_legend(data, load_rule(data)) + "\n"
    if data.note:
        legend += f"\n{data.note}\n"
    return legend


#: The input plots of an actuator's stroke: symbol and unit per kind.
_STROKE = {"phi": ("s", "m"), "omega": ("ṡ", "m/s"), "epsilon": ("s̈", "m/s²")}


def _greek(name: str) -> str:
    return {"phi": "φ", "omega": "ω", "epsilon": "ε"}.get(name, name)


def cylinder_strips(data: RunData) -> list[tuple[str, str, Array, float]]:
    """Each actuator's barrel (from its base A along A→C, its closed length long, thick) and rod
    (from the eye C back the same length, thin) per tick: ``(name, part, (N, 2, dim), width)``."""
    out = []
    for name, base, eye, closed in _drawable(data):
        a, c = position_of(data, base), position_of(data, eye)
        d = c - a
        unit = d / np.maximum(np.linalg.norm(d, axis=1, keepdims=True), np.finfo(float).tiny)
        out.append((name, "barrel", np.stack([a, a + closed * unit], axis=1), BARREL_WIDTH))
        out.append((name, "rod", np.stack([c - closed * unit, c], axis=1), 1.0))
    return out


def _drawable(data: RunData) -> list[tuple[str, str, str, float]]:
    """The cylinders whose base and eye the run knows (a replay knows the points its markers drew)."""
    known = set(data.positions) | set(data.fixed)
    return [c for c in data.cylinders if c[1] in known and c[2] in known]


def write_rrd(data: RunData, path: str | os.PathLike[str] | None = None, *,
              spawn: bool = False, recording_id: str | None = None) -> dict[str, float]:
    """Write the view of ``data`` to ``path`` (.rrd, with its blueprint) and/or show it in a
    spawned viewer. Returns the arrow scales. Raises RuntimeError when no viewer can be spawned
    (the file is written all the same)."""
    import rerun as rr
    from rerun.sinks import spawn as spawn_viewer

    if path is None and not spawn:
        raise ValueError("write_rrd needs a path or spawn=True")
    rec = rr.RecordingStream(APPLICATION_ID, recording_id=recording_id)
    bp = blueprint(data)
    sinks: list[Any] = []
    if path is not None:
        os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        sinks.append(rr.FileSink(str(path)))
    failure = ""
    if spawn:
        # the spawned viewer inherits this process's environment: give it a runtime folder, so
        # that it does not print "error: XDG_RUNTIME_DIR is invalid or not set" (.viewer)
        if os.name == "posix":
            os.environ["XDG_RUNTIME_DIR"] = viewer_environment()["XDG_RUNTIME_DIR"]
        try:
            spawn_viewer(connect=False, executable_path=viewer_executable(), recording=rec)
            sinks.append(rr.GrpcSink())
        except RuntimeError as exc:
            failure = str(exc).strip().splitlines()[0]
    if sinks:
        rec.set_sinks(*sinks, default_blueprint=bp)
        rec.send_recording_name(f"{data.scene}")
        scales = log_run(rec, data)
        rec.flush()
        rec.disconnect()
    if failure:
        raise RuntimeError(f"cannot start the rerun viewer: {failure}")
    return scales
