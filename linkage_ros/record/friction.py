"""The friction plots of a run of a scene with friction (issue 29) in the rerun view.

A :class:`~linkage_ros.record.rundata.RunData` of a scene with ``friction:`` carries
``friction``: per tick the power (W) friction dissipates, ``total`` first, then per element (a
pin by its point, a slider block, an actuator's seal) — the node's ``friction_power`` topic. The
view plots those losses, and the instantaneous efficiency of each tick from the run's efforts
(with friction), input rates and total loss: P = Σ Q·q̇, P₀ = P − total loss, η by the solver's
one formula (:func:`solver.forces.friction.efficiency`, as ``k.efficiency``). :mod:`.rerun` logs
them with :func:`log_friction` and lays them out with :func:`friction_views` (one column of two
plots); a scene without friction has none.

Entity layout (beside :mod:`.rerun`'s)::

    plots/friction/<name>    Scalars (W): total, then each element's loss
    plots/efficiency         Scalars: the instantaneous efficiency η
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._drawing import log_series, plot_view
from .rundata import Array, RunData

__all__ = ["EFFICIENCY_ENTITY", "FRICTION_ORIGIN", "friction_efficiency", "friction_from_mcap", "friction_views",
           "log_friction"]

FRICTION_ORIGIN = "plots/friction"
EFFICIENCY_ENTITY = "plots/efficiency"
_TOTAL = "total"


def friction_efficiency(data: RunData) -> Array:
    """(N,) instantaneous efficiency of each tick of ``data`` (empty without friction or efforts)."""
    from solver.forces.friction import efficiency

    if not data.friction or not data.efforts or _TOTAL not in data.friction:
        return np.zeros(0)
    omega = data.omega if data.omega.ndim == 2 else data.omega[:, None]
    names = data.inputs or tuple(data.efforts)
    power = sum(data.efforts[q] * omega[:, i] for i, q in enumerate(names) if q in data.efforts)
    return np.asarray(efficiency(power, power - data.friction[_TOTAL]), dtype=np.float64).reshape(-1)


def log_friction(rec: Any, data: RunData, times: Any) -> None:
    """Log the friction losses and the efficiency of ``data`` (nothing without friction)."""
    if not data.friction or not data.n:
        return
    for i, (name, values) in enumerate(data.friction.items()):
        label = "all friction (W)" if name == _TOTAL else f"{name} (W)"
        log_series(rec, f"{FRICTION_ORIGIN}/{name}", label, times, values, i)
    eta = friction_efficiency(data)
    if eta.size:
        log_series(rec, EFFICIENCY_ENTITY, "efficiency η", times, eta, 0)


def friction_views(data: RunData) -> list[Any]:
    """The blueprint's friction plots: the losses, then the efficiency; none without friction."""
    if not data.friction:
        return []
    views = [plot_view(FRICTION_ORIGIN, "friction losses (W)", *data.friction.values(),
                       contents=[f"/{FRICTION_ORIGIN}/{name}" for name in data.friction])]
    eta = friction_efficiency(data)
    if eta.size:
        views.append(plot_view(EFFICIENCY_ENTITY, "efficiency η", eta, contents=[f"/{EFFICIENCY_ENTITY}"]))
    return views


def friction_from_mcap(ts: Any, typename: str, rows: list[bytes]) -> dict[str, Array]:
    """``RunData.friction`` from a recording's ``friction_power`` messages at the run's ticks
    (``rows``, of type ``typename``): the entries named by the dimension's label (``W: total O
    A C B``)."""
    from .cdr import extract

    if not rows:
        return {}
    first = ts.deserialize_cdr(rows[0], typename)
    label = str(first.layout.dim[0].label) if first.layout.dim else ""
    names = label.removeprefix("W:").split()
    if len(names) != len(first.data):
        return {}
    values = extract(ts, typename, rows, lambda _m: [("data", i) for i in range(len(names))])
    return {name: values[:, i].copy() for i, name in enumerate(names)}
