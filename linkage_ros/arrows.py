"""How long an arrow is drawn: the one scale rule of the rerun view and the node's markers.

A drawing's velocity, acceleration and load arrows share one idea: a round scale (1, 2 or 5 ×
10^k) that draws a *long* vector — the :data:`ARROW_PERCENTILE`-th percentile of the lengths, so
that a few spikes near a singular position do not shrink every other arrow — at about
:data:`ARROW_FRACTION` of the mechanism's extent. The load arrows add a knee on top of it
(:class:`linkage_ros.forces.LoadArrows`). No ROS and no rerun here: the lowest layer of the
drawings, read by :mod:`linkage_ros.forces` (the node) and :mod:`linkage_ros.record` (the view).
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

__all__ = ["ARROW_FRACTION", "ARROW_PERCENTILE", "NICE_STEPS", "arrow_scale", "nice_scale"]

ARROW_FRACTION = 0.25
"""A long velocity (acceleration, load) arrow is about this fraction of the mechanism's extent."""
ARROW_PERCENTILE = 95.0
"""Which length counts as long: this percentile of all the lengths of a run."""
NICE_STEPS = (1.0, 2.0, 5.0)


def nice_scale(raw: float) -> float:
    """The round number (1, 2 or 5 × 10^k) at or below ``raw`` > 0."""
    exp = math.floor(math.log10(raw))
    mant = raw / 10.0**exp
    step = max(s for s in NICE_STEPS if s <= mant * (1 + 1e-12))
    return step * 10.0**exp


def arrow_scale(vectors: Mapping[str, NDArray[np.float64]], extent: float) -> float:
    """A round scale (1, 2 or 5 × 10^k, in s or s²) that draws a long vector — the
    ``ARROW_PERCENTILE``-th percentile of the lengths, so that a few spikes near a singular
    position do not shrink every other arrow — at about ``ARROW_FRACTION`` of ``extent``;
    1 when every vector is zero."""
    lengths = [np.linalg.norm(v, axis=1) for v in vectors.values() if v.size]
    finite = np.concatenate(lengths) if lengths else np.zeros(0)
    finite = finite[np.isfinite(finite)]
    longest = float(np.percentile(finite, ARROW_PERCENTILE)) if finite.size else 0.0
    if longest <= 0.0:
        return 1.0
    return nice_scale(ARROW_FRACTION * extent / longest)
