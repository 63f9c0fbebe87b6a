"""What every drawing of a run shares: sizes, colours, draw order, and the plots' helpers.

The lowest layer of the rerun view: :mod:`.rerun` (the mechanism, the kinematics plots, the
blueprint) and :mod:`.forces` (the load arrows, the effort plot) both draw with these, so neither
imports the other's helpers. Sizes are relative to the link radius, itself a fraction of the
drawing's extent; colours are (r, g, b) 0–255.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np

from .rundata import Array, RunData

__all__ = [
    "ACCELERATION_COLOR",
    "ARROW_WIDTH",
    "DRAW_ORDER",
    "FIXED_COLOR",
    "LINK_COLOR",
    "LINK_RADIUS",
    "PATH_COLOR",
    "POINT_COLOR",
    "SERIES_COLOUR_NAMES",
    "SERIES_PALETTE",
    "VELOCITY_COLOR",
    "log_series",
    "plot_range",
    "plot_view",
    "position_of",
]

PLOT_MARGIN = 0.05
"""Fraction of the data range added above and below in each plot."""
LABELLED_STEPS = 7
"""Most grid steps of one power of ten in a plot's y range: the viewer numbers only grid lines
at powers of ten far enough apart (at the default window, a plot three or four to a column
numbers lines ~25 px apart, not always 20 px, never 8 px); a range of more steps is widened to
the next power of ten, so that two numbered lines always show (a range of −70 … 88 is shown as
−100 … 100, not with a lone "0")."""
FLAT_SPAN = 1e-9
"""A series whose range is below this fraction of its magnitude (or of 1) is rounding noise
around a constant (five_bar's distal angles at equal inputs: 1e-15 rad/s²) and plotted as flat."""
# Sizes relative to the link radius, itself a fraction of the drawing's extent.
LINK_RADIUS = 0.004
POINT_SIZE, PIVOT_SIZE, PATH_WIDTH, ARROW_WIDTH = 1.4, 1.7, 0.35, 0.5
DRAW_ORDER = {"paths": 5.0, "links": 10.0, "arrows": 20.0, "points": 30.0}
"""2-D stacking: arrows above the links they start on, joints on top."""

LINK_COLOR = (70, 130, 200)
POINT_COLOR = (235, 235, 235)
FIXED_COLOR = (230, 90, 60)
PATH_COLOR = (150, 150, 150)
VELOCITY_COLOR = (60, 200, 90)
ACCELERATION_COLOR = (230, 170, 40)
SERIES_PALETTE = (
    (228, 26, 28), (55, 126, 184), (77, 175, 74), (152, 78, 163), (255, 127, 0),
    (200, 200, 50), (166, 86, 40), (247, 129, 191), (120, 120, 120),
)
SERIES_COLOUR_NAMES = ("red", "blue", "green", "purple", "orange", "yellow", "brown", "pink", "grey")
"""The palette's colours by name, for the legend's key: each joint's colour in every plot."""


def plot_range(*series: Array) -> tuple[float, float]:
    """Y range of a plot (explicit, so the plots do not depend on how much data the viewer had
    loaded when it fitted them): every finite value, widened to multiples of a power of ten
    (:data:`LABELLED_STEPS`) so that at least two grid lines carry a number, then a 5 % margin.
    A series constant up to rounding (:data:`FLAT_SPAN`) is shown as constant."""
    parts = [np.asarray(s, dtype=float).reshape(-1) for s in series] or [np.zeros(1)]
    values = np.concatenate(parts)
    values = values[np.isfinite(values)]
    lo, hi = (float(values.min()), float(values.max())) if values.size else (0.0, 0.0)
    if hi - lo <= FLAT_SPAN * max(1.0, abs(lo), abs(hi)):
        mid = 0.5 * (lo + hi)
        lo, hi = mid - max(1.0, abs(mid)), mid + max(1.0, abs(mid))
    step = 10.0 ** math.floor(math.log10(hi - lo))
    if math.ceil(hi / step) - math.floor(lo / step) > LABELLED_STEPS:
        step *= 10.0
    lo, hi = math.floor(lo / step) * step, math.ceil(hi / step) * step
    pad = PLOT_MARGIN * (hi - lo)
    return lo - pad, hi + pad


def plot_view(origin: str, name: str, *series: Array, contents: Sequence[str] = ("$origin/**",)) -> Any:
    import rerun.blueprint as rrb

    return rrb.TimeSeriesView(origin=origin, name=name, contents=list(contents),
                              axis_y=rrb.ScalarAxis(range=plot_range(*series)),
                              plot_legend=rrb.PlotLegend(visible=True))


def position_of(data: RunData, name: str) -> Array:
    """(N, dim) positions of point ``name`` over the run (a fixed pivot repeated)."""
    if name in data.positions:
        return data.positions[name]
    return np.broadcast_to(np.asarray(data.fixed[name], dtype=float), (data.n, data.dim))


def log_series(rec: Any, path: str, label: str, times: Any, values: Array, index: int) -> None:
    """One plotted series at ``path``, named ``label``, in palette colour ``index``."""
    import rerun as rr

    color = SERIES_PALETTE[index % len(SERIES_PALETTE)]
    rec.log(path, rr.SeriesLines(names=label, widths=1.5, colors=color), static=True)
    rec.send_columns(path, indexes=[times], columns=rr.Scalars.columns(scalars=values))
