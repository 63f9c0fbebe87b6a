"""Summary lines of a sweep's forces, in SI, for people (``linkage-solve``, ``linkage-run``).

From a solve over samples of the input(s) — one turn of φ, or a run's ticks — the lines give,
per input, the peak and RMS effort (N·m for a crank, N for an actuator's cylinder) and the peak
input power Σ Q·ω (W), and per pin the peak load |R| (N), per slide the peak normal force and couple. Each value at a
sample is exact (closed form, solver.forces); a peak or an RMS over the cycle is *read off the
samples* — the line says how many and at what step — since between samples nothing is
evaluated. Samples at singular positions (NaN, ``k.singular``) are left out and counted.

``force_lines(scene, k)`` gives the lines; ``force_section(scene, k)`` the same as a section of
:func:`solver.summary.summary_lines` (``sections=[force_section(scene, k)]``).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..tolerances import ZERO_TO_ROUNDING

__all__ = ["force_lines", "force_section"]


def _step(k: Any, sampling: str | None, units: tuple[str, ...] = ()) -> str:
    if sampling is not None:
        return sampling
    phi = np.asarray(k.phi, float)
    n = phi.shape[0] if phi.ndim else 1
    if phi.ndim == 1 and n > 2:
        d = np.diff(phi)
        if np.allclose(d, d[0], rtol=1e-9, atol=0.0):
            step = f"{abs(d[0]):.3g} m" if units == ("m",) else f"{math.degrees(abs(d[0])):.3g}°"
            return f"read off {n} samples, step {step}"
    return f"read off {n} samples"


def _value(v: float, unit: str) -> str:
    """An input's value: an angle in degrees within the turn, a stroke (``unit`` "m") in m."""
    return f"{v:.4f} m" if unit == "m" else f"{math.degrees(v) % 360.0:.2f}°"


def _at(k: Any, i: int, inputs: tuple[str, ...], times: Any = None, units: tuple[str, ...] = ()) -> str:
    """Where sample ``i`` lies: its input angle(s) or stroke(s), after its time ``t`` when the
    samples are a run's ticks (as the kinematic lines of a run's summary say it)."""
    phi = np.asarray(k.phi, float)
    units = units if len(units) == len(inputs) else ("rad",) * len(inputs)
    if phi.ndim == 2:
        where = "(" + ", ".join(f"{q} = {_value(v, u)}" for q, v, u in zip(inputs, phi[i], units)) + ")"
    else:
        where = f"{'s' if units[0] == 'm' else 'φ'} = {_value(float(phi[i]), units[0])}"
    if times is None:
        return where
    return f"t = {float(times[i]):.6g} s ({where.strip('()')})"


def _g(x: float) -> str:
    return f"{x:.6g}"


def force_lines(scene: Any, k: Any, *, sampling: str | None = None, times: Any = None) -> list[str]:
    """The force summary of the sweep ``k`` of ``scene`` (none for a scene without forces);
    ``times``: the samples' times (a run's ticks), said with each peak's angle."""
    if not getattr(scene, "has_forces", False) or np.ndim(k.phi) == 0 or np.shape(k.phi)[0] == 0:
        return []
    inputs = tuple(scene.inputs)
    units = scene.joint_units
    kinds = tuple(units.get(q, "rad") for q in inputs)
    how = _step(k, sampling, kinds)
    efforts = {q: np.asarray(k.effort(q), float) for q in inputs}
    ok = np.ones(efforts[inputs[0]].shape, bool)
    for v in efforts.values():
        ok &= np.isfinite(v)
    lines = [f"forces (SI; each sample exact, peaks and RMS {how})"]
    if not ok.all():
        valid = np.broadcast_to(np.asarray(k.valid, bool), ok.shape)
        singular, gone = int((~ok & valid).sum()), int((~valid).sum())
        if singular:
            lines.append(f"  {singular} singular sample(s) left out (unbounded loads: k.singular)")
        if gone:
            lines.append(f"  {gone} sample(s) not assemblable left out")
    if not ok.any():
        return lines
    idx = np.flatnonzero(ok)
    omega = np.asarray(k.omega, float)
    power = np.zeros(ok.shape)
    scale = 0.0  # Σ max|Q|·max|ω|: what the power is made of, for "zero to rounding"
    for i, q in enumerate(inputs):
        unit = "N" if units.get(q) == "m" else "N·m"
        v = efforts[q][ok]
        j = int(idx[np.argmax(np.abs(v))])
        rms = math.sqrt(float(np.mean(v * v)))
        lines.append(f"  effort {q}: peak |Q| = {_g(abs(efforts[q][j]))} {unit} at {_at(k, j, inputs, times, kinds)} "
                     f"(Q = {_g(efforts[q][j])}), RMS {_g(rms)} {unit}")
        w = np.broadcast_to(omega if omega.ndim <= 1 else omega[:, i], ok.shape)
        power = power + efforts[q] * w
        scale += float(np.abs(v).max()) * float(np.abs(w[ok]).max())
    j = int(idx[np.argmax(np.abs(power[ok]))])
    if power[j] == 0.0:
        lines.append("  input power Σ Q·ω: zero")
    elif abs(power[j]) <= ZERO_TO_ROUNDING * scale:  # (Σ Q·ω cancelling to rounding)
        lines.append(f"  input power Σ Q·ω: zero to rounding (at most {abs(power[j]):.2g} W)")
    else:
        lines.append(f"  input power Σ Q·ω: peak |P| = {_g(abs(power[j]))} W at {_at(k, j, inputs, times, kinds)}")
    for pin in scene.pins:
        r = np.asarray(k.reaction(pin.point, on=pin.body, by=pin.other), float)
        mag = np.hypot(r[..., 0], r[..., 1])[ok]
        j = int(idx[np.argmax(mag)])
        where = _at(k, j, inputs, times, kinds)
        lines.append(f"  pin {pin.point} ({pin.body}–{pin.other}): peak load {_g(float(mag.max()))} N at {where}")
    for s in scene.slides:
        pair = k.slide_reaction(s.body)
        mag = np.hypot(pair.force[..., 0], pair.force[..., 1])[ok]
        couple = np.abs(np.broadcast_to(pair.couple, ok.shape))[ok]
        j = int(idx[np.argmax(mag)])
        lines.append(f"  slide {s.point} ({s.body} on {s.guide}): peak normal force {_g(float(mag.max()))} N at "
                     f"{_at(k, j, inputs, times, kinds)}, peak couple {_g(float(couple.max()))} N·m")
    return lines


def force_section(scene: Any, k: Any, *, sampling: str | None = None,
                  times: Any = None) -> Callable[[Any], list[str]]:
    """:func:`force_lines` as a section of :func:`solver.summary.summary_lines`."""
    return lambda _sweep: force_lines(scene, k, sampling=sampling, times=times)
