"""Summary lines of a sweep's forces, in SI, for people (``linkage-solve``, ``linkage-run``).

From a solve over samples of the input(s) — one turn of φ, or a run's ticks — the lines give, per
input, the peak and RMS effort (N·m for a crank, N for an actuator's cylinder) and the peak input
power Σ Q·ω (W), and per pin the peak load |R| (N), per slide the peak and RMS normal force, how
often it changes the side of the guide it presses on, and the couple where there is one (a block
whose load acts at its pin has none). Each value at a sample is exact (closed form, solver.forces);
a peak or an RMS over the cycle is *read off the samples* — the line says how many and at what step
— since between samples nothing is evaluated. Samples at singular positions (NaN, ``k.singular``)
are left out and counted.

The heading says at which ω and ε the forces hold: the bodies' inertia makes them depend on the
motion (without mass or inertia they are the same at every speed). ``default_speed``: the caller
chose ω and ε for the user (linkage-solve without ``--omega``, 1 rad/s): a line says so and how to
ask for statics or an operating speed, and the input power (then the effort's numbers again, in W)
is left out.

``force_lines(scene, k)`` gives the lines; ``force_section(scene, k)`` the same as a section of
:func:`solver.summary.summary_lines` (``sections=[force_section(scene, k)]``)."""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

import numpy as np

from ..tolerances import ZERO_TO_ROUNDING
from .friction_report import friction_lines, friction_names

__all__ = ["force_lines", "force_section", "motion_of_forces"]


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


def _rates(values: Any, ok: np.ndarray, inputs: tuple[str, ...]) -> str | None:
    """``= 1`` or ``q1 = 1, q2 = 2`` when each input's rate is one value over the samples, else None."""
    v = np.asarray(values, float)
    columns = [np.broadcast_to(v if v.ndim <= 1 else v[:, i], ok.shape)[ok] for i in range(len(inputs))]
    if any(c.size and np.ptp(c) != 0.0 for c in columns):
        return None
    first = [float(c[0]) if c.size else 0.0 for c in columns]
    return f"= {_g(first[0])}" if len(inputs) == 1 else ", ".join(f"{q} = {_g(x)}" for q, x in zip(inputs, first))


def _has_inertia(scene: Any) -> bool:
    """Whether a body has mass or inertia (else the forces do not depend on ω and ε)."""
    return any(b.mass > 0.0 or b.inertia > 0.0 for b in scene.bodies)


def motion_of_forces(scene: Any, k: Any, ok: np.ndarray) -> str:
    """At which motion the forces hold: ``at ω = 1 rad/s, ε = 0 rad/s², with the bodies' inertia``
    (or ``at each sample's ω and ε`` for a run that speeds up; or, when no body has mass or
    inertia, that they are the same at every speed)."""
    inputs = tuple(scene.inputs)
    if not _has_inertia(scene):
        return "the same at every speed: no body has mass or inertia"
    w, e = _rates(k.omega, ok, inputs), _rates(k.epsilon, ok, inputs)
    units = tuple(getattr(scene, "input_units", ())) or ("rad",) * len(inputs)
    if w is None or e is None:
        rates = "ṡ and s̈" if set(units) == {"m"} else "ω and ε" if "m" not in units else "rates"
        return f"at each sample's {rates}, with the bodies' inertia"
    if len(set(units)) == 1:  # one unit for every input: ω, ε in rad/s, rad/s²; ṡ, s̈ in m/s, m/s²
        rate, accel = ("ṡ", "s̈") if units[0] == "m" else ("ω", "ε")
        return f"at {rate} {w} {units[0]}/s, {accel} {e} {units[0]}/s², with the bodies' inertia"
    per = [(f"{q} {a.split('= ')[1]} {u}/s", f"{q} {b.split('= ')[1]} {u}/s²")
           for q, u, a, b in zip(inputs, units, w.split(", "), e.split(", "))]
    return (f"at rates {', '.join(a for a, _ in per)}; accelerations {', '.join(b for _, b in per)}, with the "
            "bodies' inertia")


def _one_turn(k: Any) -> bool:
    """Whether the samples are one whole turn of one input at equal steps (the last sample's
    neighbour is then the first)."""
    phi = np.asarray(k.phi, float)
    if phi.ndim != 1 or phi.shape[0] < 3:
        return False
    d = np.diff(phi)
    return bool(np.allclose(d, d[0], rtol=1e-9, atol=0.0) and math.isclose(abs(d[0]) * phi.shape[0], 2 * math.pi))


def _side_changes(force: np.ndarray, *, cyclic: bool) -> int:
    """How often a slide's normal force (N, 2) changes the side of the guide it presses on: the
    force reverses between neighbouring samples (it stays normal to the guide, which turns less
    than a quarter turn between samples); zero forces are skipped. ``cyclic``: the last sample's
    neighbour is the first."""
    f = force[np.hypot(force[:, 0], force[:, 1]) > 0.0]
    if len(f) < 2:
        return 0
    if cyclic:
        f = np.concatenate([f, f[:1]])
    return int(np.count_nonzero(np.einsum("ij,ij->i", f[1:], f[:-1]) < 0.0))


def _power_line(power: np.ndarray, ok: np.ndarray, idx: np.ndarray, scale: float, at: Callable[[int], str],
                label: str = "Σ Q·ω") -> str:
    """The input power line: its peak, or zero (to rounding of ``scale``: Σ max|Q|·max|ω|).
    ``label``: Σ Q·ω of angles, Σ Q·ṡ of actuators' strokes, Σ Q·q̇ of both."""
    j = int(idx[np.argmax(np.abs(power[ok]))])
    if power[j] == 0.0:
        return f"  input power {label}: zero"
    if abs(power[j]) <= ZERO_TO_ROUNDING * scale:  # (Σ Q·ω cancelling to rounding)
        return f"  input power {label}: zero to rounding (at most {abs(power[j]):.2g} W)"
    return f"  input power {label}: peak |P| = {_g(abs(power[j]))} W at {at(j)}"


def force_lines(scene: Any, k: Any, *, sampling: str | None = None, times: Any = None,
                default_speed: bool = False) -> list[str]:
    """The force summary of the sweep ``k`` of ``scene`` (none for a scene without forces);
    ``times``: the samples' times (a run's ticks), said with each peak's angle;
    ``default_speed``: ω and ε were not the user's (see the module's docstring)."""
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
    lines = [f"forces (SI), {motion_of_forces(scene, k, ok)} (each sample exact, peaks and RMS {how})"]
    if default_speed and _has_inertia(scene):
        lines.append("  (that speed is the default, not an operating one: --omega W --epsilon E for the "
                     "machine's, --omega 0 for statics)")
    if not ok.all():
        valid = np.broadcast_to(np.asarray(k.valid, bool), ok.shape)
        locked = np.broadcast_to(np.asarray(k.locked, bool), ok.shape) if friction_names(scene) else False
        singular, gone = int((~ok & valid & ~locked).sum()), int((~valid).sum())
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
    if not default_speed:  # (Σ Q·ω at the default 1 rad/s: the effort's numbers again)
        kinds_of = {units.get(q) == "m" for q in inputs}
        label = "Σ Q·q̇" if len(kinds_of) > 1 else "Σ Q·ṡ" if kinds_of == {True} else "Σ Q·ω"
        lines.append(_power_line(power, ok, idx, scale, lambda j: _at(k, j, inputs, times, kinds), label))
    for pin in scene.pins:
        r = np.asarray(k.reaction(pin.point, on=pin.body, by=pin.other), float)
        mag = np.hypot(r[..., 0], r[..., 1])[ok]
        j = int(idx[np.argmax(mag)])
        where = _at(k, j, inputs, times, kinds)
        lines.append(f"  pin {pin.point} ({pin.body}–{pin.other}): peak load {_g(float(mag.max()))} N at {where}")
    cyclic = _one_turn(k) and times is None and bool(ok.all())
    for s in scene.slides:
        pair = k.slide_reaction(s.body)
        mag = np.hypot(pair.force[..., 0], pair.force[..., 1])[ok]
        couple = np.abs(np.broadcast_to(pair.couple, ok.shape))[ok]
        j = int(idx[np.argmax(mag)])
        rms = math.sqrt(float(np.mean(mag * mag)))
        changes = _side_changes(np.asarray(pair.force, float).reshape(-1, 2)[ok], cyclic=cyclic)
        side = ("presses on one side of the guide throughout" if not changes else
                f"changes the side of the guide it presses on {changes} time{'s' if changes > 1 else ''}"
                + (" a turn" if cyclic else ""))
        text = (f"  slide {s.point} ({s.body} on {s.guide}): peak normal force {_g(float(mag.max()))} N at "
                f"{_at(k, j, inputs, times, kinds)}, RMS {_g(rms)} N; {side}")
        if couple.max() > 0.0:  # a block whose load acts at its pin has none: nothing to print
            c = int(idx[np.argmax(couple)])
            text += f"; peak couple {_g(float(couple.max()))} N·m at {_at(k, c, inputs, times, kinds)}"
        lines.append(text)
    lines += friction_lines(scene, k, ok, lambda j: _at(k, j, inputs, times, kinds), turn=cyclic)
    return lines


def force_section(scene: Any, k: Any, *, sampling: str | None = None, times: Any = None,
                  default_speed: bool = False) -> Callable[[Any], list[str]]:
    """:func:`force_lines` as a section of :func:`solver.summary.summary_lines`."""
    return lambda _sweep: force_lines(scene, k, sampling=sampling, times=times, default_speed=default_speed)
