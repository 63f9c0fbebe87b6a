"""Friction's part of the force summary and of the CSV (docs/forces.md#friction).

Summary lines (after the pins and slides): the friction power's peak and mean, each element's
(a pin by its point, a slider block, an actuator's seal) mean loss, the instantaneous
efficiency's lowest value and where, the efficiency over the samples (1 − W_loss/W_in,
solver.forces.friction.cycle_efficiency: "over the turn" for one whole turn), and the
self-locking line when the mechanism locks somewhere. CSV columns: ``loss.NAME`` (W) per
element, ``friction.power`` (W), ``efficiency`` and ``locked`` (0/1).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from ..errors import SolverError
from .friction import cycle_efficiency

__all__ = ["friction_names", "friction_columns", "friction_table", "friction_lines"]


def friction_names(scene: Any) -> list[str]:
    """The names ``k.friction_loss`` takes: pin points, slider blocks, actuators (in that order)."""
    model = getattr(scene, "forces", None)
    f = None if model is None else model.friction
    if model is None or f is None:
        return []
    slides = model.spec.slides
    names = [e.point if e.kind == "pin" else slides[e.index].body for e in f.elements]
    names += [s.actuator for s in f.spec.seals]
    return list(dict.fromkeys(names))


def friction_columns(scene: Any) -> list[str]:
    names = friction_names(scene)
    if not names:
        return []
    return [f"loss.{n}" for n in names] + ["friction.power", "efficiency", "locked"]


def friction_table(scene: Any, k: Any) -> list[np.ndarray]:
    names = friction_names(scene)
    if not names:
        return []
    n = np.shape(k.valid)[0]

    def col(x: Any) -> np.ndarray:
        return np.broadcast_to(np.asarray(x, float), (n,))[:, None]

    return [col(k.friction_loss(m)) for m in names] + [col(k.friction_power), col(k.efficiency),
                                                       col(np.asarray(k.locked, float))]


def friction_lines(scene: Any, k: Any, ok: np.ndarray, at: Callable[[int], str], *, turn: bool) -> list[str]:
    """The summary lines (none without friction); ``ok``: the samples the other lines read;
    ``at(i)``: where sample i lies; ``turn``: the samples are one whole turn."""
    names = friction_names(scene)
    if not names:
        return []
    locked = np.broadcast_to(np.asarray(k.locked, bool), ok.shape)
    lines: list[str] = []
    good = ok & ~locked
    if good.any():
        idx = np.flatnonzero(good)
        power = np.asarray(k.friction_power, float)
        j = int(idx[np.argmax(power[good])])
        lines.append(f"  friction: peak loss {power[j]:.6g} W at {at(j)}, mean {float(np.mean(power[good])):.6g} W "
                     "(" + ", ".join(f"{m} {float(np.mean(np.asarray(k.friction_loss(m), float)[good])):.4g} W"
                                     for m in names) + ")")
        eta = np.asarray(k.efficiency, float)
        i = int(idx[np.argmin(eta[good])])
        text = f"  efficiency: lowest {eta[i]:.4g} at {at(i)}"
        try:
            over = cycle_efficiency(k) if good.all() else None
        except SolverError:
            over = None
        if over is not None:
            text += f"; over the {'turn' if turn else 'samples'} {over:.4g} (1 − friction work / input work)"
        lines.append(text)
    if locked.any():
        lines.append(f"  {k.locking_message}")
    return lines
