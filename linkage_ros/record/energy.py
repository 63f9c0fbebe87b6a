"""The energy plots of a dynamic run (``linkage-run --dynamics``, issue 22) in the rerun view.

A :class:`~linkage_ros.record.rundata.RunData` of a dynamic run carries ``energy``: per tick the
kinetic energy ½q̇ᵀM(q)q̇, the potentials of gravity and of the springs, the work done by the
drive and by the other loads (dampers, forces, torques, tables) since the start, and the energy
balance's error T + V − W_drive − W_other minus its start value
(:meth:`solver.dynamics.Trajectory.energy`). :mod:`.rerun` logs them with :func:`log_energy` and
lays them out with :func:`energy_views` (one column of two plots); a kinematic run has none.

Entity layout (beside :mod:`.rerun`'s)::

    plots/energy/<kind>      Scalars (J): kinetic, gravity, springs, work_drive, work_other, work_friction
                             (those that are not zero over the whole run; kinetic always)
    plots/energy_balance     Scalars (J): the balance's error (zero to the integrator's tolerance)
"""

from __future__ import annotations

from typing import Any

import numpy as np

from ._drawing import log_series, plot_view
from .rundata import Array, RunData

__all__ = ["BALANCE_ENTITY", "ENERGY_ORIGIN", "ENERGY_SERIES", "energy_series", "energy_views", "log_energy"]

ENERGY_ORIGIN = "plots/energy"
BALANCE_ENTITY = "plots/energy_balance"
#: The energy plot's series: key of ``RunData.energy`` → its label.
ENERGY_SERIES = {
    "kinetic": "kinetic T",
    "gravity": "potential (gravity)",
    "springs": "potential (springs)",
    "work_drive": "work of the drive",
    "work_other": "work of the other loads",
    "work_friction": "work of the friction",
}


def energy_series(data: RunData) -> dict[str, Array]:
    """The energy plot's series of ``data``: the kinetic energy, and each other kind that is not
    zero at every tick (a scene without springs plots none)."""
    return {key: data.energy[key] for key in ENERGY_SERIES
            if key in data.energy and (key == "kinetic" or np.any(data.energy[key] != 0.0))}


def log_energy(rec: Any, data: RunData, times: Any) -> None:
    """Log the energy series and the balance's error of ``data`` (nothing for a kinematic run)."""
    if not data.energy or not data.n:
        return
    for i, (key, values) in enumerate(energy_series(data).items()):
        log_series(rec, f"{ENERGY_ORIGIN}/{key}", f"{ENERGY_SERIES[key]} (J)", times, values, i)
    if "balance" in data.energy:
        log_series(rec, BALANCE_ENTITY, "Δ(T + V − W) (J)", times, data.energy["balance"], 0)


def energy_views(data: RunData) -> list[Any]:
    """The blueprint's energy plots: the energies and works, then the balance's error; none for a
    kinematic run."""
    if not data.energy:
        return []
    series = energy_series(data)
    views = [plot_view(ENERGY_ORIGIN, "energy (J)", *series.values(),
                   contents=[f"/{ENERGY_ORIGIN}/{key}" for key in series])]
    if "balance" in data.energy:
        views.append(plot_view(BALANCE_ENTITY, "balance error (J)", data.energy["balance"],
                           contents=[f"/{BALANCE_ENTITY}"]))
    return views
