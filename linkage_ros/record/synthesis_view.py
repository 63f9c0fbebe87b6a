"""The rerun view of a synthesis (solver.synthesize, docs/synthesis.md).

Entity layout::

    synthesis/targets               static Points2D, labelled t0, t1, …
    synthesis/curve                 static LineStrips2D: the best design's traced curve over the range
    synthesis/others/<i>            static, thinner: the other distinct designs' curves (cognates too)
    synthesis/fixed                 static Points2D: the best design's fixed points
    synthesis/links/<link>          LineStrips2D on the ``phi_step`` timeline: the mechanism moving
                                    along its curve (one step per sample of the range)
    synthesis/point                 Points2D on ``phi_step``: the traced point
    convergence/best                Scalars on the ``generation`` timeline: log10 of the search's best
                                    figure (RMS miss over the targets' size; infeasible ≥ 2)

Static data logged static, series with ``send_columns``, the layout in a blueprint (the mechanism
beside the convergence plot); each drawn entity carries the static mirror that draws y up
(:data:`~linkage_ros.record.rerun.Y_UP`), as the run view does.
"""

from __future__ import annotations

import math
import os
from typing import Any

import numpy as np

from .rerun import FIXED_COLOR, LINK_COLOR, PATH_COLOR, POINT_COLOR, Y_UP

__all__ = ["write_synthesis_rrd", "synthesis_blueprint", "log_synthesis", "STEPS"]

APPLICATION_ID = "linkage_ros_synthesis"
#: samples of the input range the mechanism is shown at
STEPS = 180
TARGET_COLOR = (240, 200, 40)
CURVE_COLOR = (90, 200, 120)


def synthesis_blueprint() -> Any:
    import rerun.blueprint as rrb

    return rrb.Blueprint(
        rrb.Horizontal(
            rrb.Spatial2DView(origin="synthesis", name="targets, curve and mechanism"),
            rrb.TimeSeriesView(origin="convergence", name="convergence (log10 best figure)"),
            column_shares=[2, 1],
        ),
        rrb.TimePanel(state="collapsed"),
        collapse_panels=True,
    )


def _xy(k: Any, name: str) -> np.ndarray:
    return np.asarray(k.point(name).position, float)


def log_synthesis(rec: Any, res: Any) -> None:
    """Log a :class:`~solver.synthesis.SynthesisResult` into the recording stream ``rec``."""
    import rerun as rr

    goal, best = res.goal, res.best
    for child in ("targets", "curve", "others", "fixed", "links", "point"):
        rec.log(f"synthesis/{child}", rr.Transform3D(scale=Y_UP), static=True)
    scene = best.scene.everything()
    lo = float(goal.sweep[0])
    hi = lo + 2 * math.pi if goal.full_turn else float(goal.sweep[-1])
    phi = np.linspace(lo, hi, STEPS)
    k = scene.with_outputs(forces=False).solve(phi, mask=True)
    size = max(float(np.ptp(goal.targets[:, 0]) + np.ptp(goal.targets[:, 1])), 1e-3)
    radius = 0.004 * size
    if goal.kind != "function":
        rec.log("synthesis/targets", rr.Points2D(goal.targets[:, :2], radii=3 * radius, colors=TARGET_COLOR,
                                                 labels=[f"t{i}" for i in range(len(goal.targets))],
                                                 show_labels=True), static=True)
        curve = best.curve[np.isfinite(best.curve)]
        rec.log("synthesis/curve", rr.LineStrips2D([np.c_[curve.real, curve.imag]], radii=radius,
                                                   colors=CURVE_COLOR), static=True)
        for i, d in enumerate(res.solutions[1:], 1):
            c = d.curve[np.isfinite(d.curve)]
            rec.log(f"synthesis/others/{i}", rr.LineStrips2D([np.c_[c.real, c.imag]], radii=0.4 * radius,
                                                             colors=PATH_COLOR), static=True)
    fixed = scene.fixed_points
    rec.log("synthesis/fixed", rr.Points2D(np.array(list(fixed.values())), radii=2 * radius, colors=FIXED_COLOR,
                                           labels=list(fixed), show_labels=True), static=True)
    steps = rr.TimeColumn("phi_step", sequence=np.arange(STEPS))
    for link in scene.links:
        strip = np.stack([_xy(k, p) for p in link.points], axis=1)  # (STEPS, k, 2)
        rec.log(f"synthesis/links/{link.name}", rr.LineStrips2D.from_fields(radii=radius, colors=LINK_COLOR),
                static=True)
        rec.send_columns(f"synthesis/links/{link.name}", indexes=[steps],
                         columns=rr.LineStrips2D.columns(strips=strip))
    if goal.point is not None:
        rec.log("synthesis/point", rr.Points2D.from_fields(radii=2 * radius, colors=POINT_COLOR), static=True)
        rec.send_columns("synthesis/point", indexes=[steps], columns=rr.Points2D.columns(positions=_xy(k, goal.point)))
    history = np.asarray(res.history, float)
    if history.size:
        generations = rr.TimeColumn("generation", sequence=np.arange(history.size))
        rec.log("convergence/best", rr.SeriesLines(names="log10 best figure", widths=1.5), static=True)
        rec.send_columns("convergence/best", indexes=[generations],
                         columns=rr.Scalars.columns(scalars=np.log10(np.maximum(history, 1e-300))))
    summary = res.summary()
    rec.log("synthesis/summary", rr.TextDocument(f"```\n{summary}\n```", media_type="text/markdown"), static=True)


def write_synthesis_rrd(res: Any, path: str | os.PathLike[str]) -> None:
    """Write the view of ``res`` (with its blueprint) to ``path`` (.rrd)."""
    import rerun as rr

    rec = rr.RecordingStream(APPLICATION_ID)
    os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
    rec.set_sinks(rr.FileSink(str(path)), default_blueprint=synthesis_blueprint())
    log_synthesis(rec, res)
    rec.flush()
    rec.disconnect()
