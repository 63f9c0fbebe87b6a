"""Time integration of the input angle φ(t) at publishing rates, over one simulated hour.

The law: φ(0) = 0, ω(0) = 2π rad/s, ε piecewise constant, switching every quarter hour through
``EPSILONS``. Methods, each evaluated at the ticks t_n = n / rate:

* exact piecewise (linkage_ros.motion.Motion): φ from the start of the segment, error-free sums;
* closed form, plain float: φ_s + ω_s τ + ½ ε τ² with ordinary rounding (what Motion improves on);
* explicit Euler: φ += ω dt, ω += ε dt, tick after tick;
* classical RK4 on (φ' = ω, ω' = ε), tick after tick.

Euler and RK4 are run vectorised with ``np.cumsum`` (a sequential accumulation: bit for bit the
same sums as a loop that adds one tick at a time); their cost per tick is timed separately as the
scalar Python step a node would run. The reference is mpmath at 50 digits at the exact rational
times n / rate, sampled twice a ``sample_every`` seconds (at whole seconds and a third of a second
later, which is not a binary fraction).
"""

from __future__ import annotations

import math
import statistics
import time
from dataclasses import dataclass

import numpy as np
from mpmath import mp, mpf

__all__ = ["EPSILONS", "RATES", "Row", "run"]

RATES = (10, 100, 1000, 10000)
OMEGA0 = 2.0 * math.pi
EPSILONS = (2e-3, -1e-3, 1.5e-3, -2e-3)
SEGMENT_S = 900.0
CHUNK = 1 << 20


@dataclass(frozen=True)
class Row:
    method: str
    rate: int
    ticks: int
    phi_error: float  # rad, max over the samples
    omega_error: float  # rad/s
    tick_s: float  # seconds per tick, scalar Python


def _epsilon_at(t: np.ndarray | float) -> np.ndarray:
    index = np.minimum((np.asarray(t) // SEGMENT_S).astype(int), len(EPSILONS) - 1)
    return np.asarray(EPSILONS)[index]


def _exact(n: int, rate: int) -> tuple[mpf, mpf]:
    """(φ, ω) at t = n / rate exactly, in mpmath."""
    t = mpf(n) / rate
    phi, omega, start = mpf(0), mpf(OMEGA0), mpf(0)
    for k, eps in enumerate(map(mpf, EPSILONS)):
        end = mpf(SEGMENT_S) * (k + 1)
        last = k == len(EPSILONS) - 1
        tau = (t if (t <= end or last) else end) - start
        if t <= end or last:
            return phi + omega * tau + eps * tau * tau / 2, omega + eps * tau
        phi, omega, start = phi + omega * tau + eps * tau * tau / 2, omega + eps * tau, end
    raise AssertionError("unreachable")


def _samples(rate: int, duration: float, every: float) -> np.ndarray:
    whole = np.arange(0, int(duration) + 1, int(every)) * rate
    return np.unique(np.concatenate([whole, whole + rate // 3]))


def _stepped(rate: int, ticks: int, samples: np.ndarray, rk4: bool) -> tuple[np.ndarray, np.ndarray]:
    """φ, ω at the sample ticks for Euler or RK4, accumulated chunk by chunk."""
    dt = 1.0 / rate
    half = dt / 2.0
    phi, omega = 0.0, OMEGA0
    out_phi, out_omega = np.empty(len(samples)), np.empty(len(samples))
    for lo in range(0, ticks + 1, CHUNK):
        hi = min(lo + CHUNK, ticks + 1)
        n = np.arange(lo, hi)
        eps = _epsilon_at(n / rate)
        if rk4:
            d_omega = dt / 6.0 * (eps + 2.0 * eps + 2.0 * eps + eps)
        else:
            d_omega = eps * dt
        w = np.cumsum(np.concatenate(([omega], d_omega)))  # ω at ticks lo … hi
        wn = w[:-1]
        if rk4:
            mid = wn + half * eps
            d_phi = dt / 6.0 * (wn + 2.0 * mid + 2.0 * mid + (wn + dt * eps))
        else:
            d_phi = wn * dt
        p = np.cumsum(np.concatenate(([phi], d_phi)))
        inside = (samples >= lo) & (samples < hi)
        out_phi[inside] = p[samples[inside] - lo]
        out_omega[inside] = w[samples[inside] - lo]
        phi, omega = p[-1], w[-1]
    return out_phi, out_omega


def _motion():  # type: ignore[no-untyped-def]
    from linkage_ros.motion import Motion

    motion = Motion(phi0=0.0, omega=OMEGA0, epsilon=EPSILONS[0], t0=0.0)
    for k, eps in enumerate(EPSILONS[1:], start=1):
        motion.set_epsilon(SEGMENT_S * k, eps)
    return motion


def _closed_form(t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Plain-float closed form from each segment start (segment starts chained in float)."""
    starts = [(0.0, 0.0, OMEGA0)]
    for eps in EPSILONS[:-1]:
        t0, p0, w0 = starts[-1]
        tau = SEGMENT_S
        starts.append((t0 + tau, p0 + w0 * tau + 0.5 * eps * tau * tau, w0 + eps * tau))
    index = np.minimum((t // SEGMENT_S).astype(int), len(EPSILONS) - 1)
    t0, p0, w0 = (np.array([s[i] for s in starts])[index] for i in range(3))
    eps = np.asarray(EPSILONS)[index]
    tau = t - t0
    return p0 + w0 * tau + 0.5 * eps * tau * tau, w0 + eps * tau


def _tick_cost(method: str, rate: int, count: int) -> float:
    dt = 1.0 / rate
    if method == "Euler":
        phi, omega, eps = 0.0, OMEGA0, EPSILONS[0]
        start = time.perf_counter()
        for _ in range(count):
            phi += omega * dt
            omega += eps * dt
        return (time.perf_counter() - start) / count
    if method == "RK4":
        phi, omega, eps, half = 0.0, OMEGA0, EPSILONS[0], dt / 2.0
        start = time.perf_counter()
        for _ in range(count):
            mid = omega + half * eps
            phi += dt / 6.0 * (omega + 2.0 * mid + 2.0 * mid + (omega + dt * eps))
            omega += dt / 6.0 * (eps + 2.0 * eps + 2.0 * eps + eps)
        return (time.perf_counter() - start) / count
    if method == "exact piecewise (Motion)":
        state = _motion().state
        start = time.perf_counter()
        for n in range(count):
            state(n / rate)
        return (time.perf_counter() - start) / count
    phi0, omega0, eps = 0.0, OMEGA0, EPSILONS[0]  # the plain closed form in Python floats
    start = time.perf_counter()
    for n in range(count):
        tau = n / rate
        phi = phi0 + omega0 * tau + 0.5 * eps * tau * tau
    del phi
    return (time.perf_counter() - start) / count


def run(*, duration: float = 3600.0, sample_every: float = 1.0, tick_count: int = 50_000) -> list[Row]:
    """Every method at every rate in :data:`RATES`."""
    rows: list[Row] = []
    costs: dict[str, float] = {}
    try:
        _motion()
        methods = ["exact piecewise (Motion)", "closed form, plain float", "Euler", "RK4"]
    except ImportError:
        methods = ["closed form, plain float", "Euler", "RK4"]
    for rate in RATES:
        ticks = int(round(duration * rate))
        samples = _samples(rate, duration, sample_every)
        samples = samples[samples <= ticks]
        with mp.workdps(50):
            exact = [_exact(int(n), rate) for n in samples]
        ref_phi = np.array([float(p) for p, _ in exact])
        ref_err = [(p - mpf(float(p)), w - mpf(float(w))) for p, w in exact]  # residual beyond double
        ref_omega = np.array([float(w) for _, w in exact])
        times = samples / rate
        for method in methods:
            if method == "exact piecewise (Motion)":
                phi, omega, _ = _motion().states(times)
            elif method == "closed form, plain float":
                phi, omega = _closed_form(times)
            else:
                phi, omega = _stepped(rate, ticks, samples, rk4=method == "RK4")
            with mp.workdps(50):
                phi_err = max(abs(mpf(float(a)) - mpf(float(b)) - r[0]) for a, b, r in zip(phi, ref_phi, ref_err))
                omega_err = max(abs(mpf(float(a)) - mpf(float(b)) - r[1]) for a, b, r in zip(omega, ref_omega, ref_err))
            if method not in costs:  # the cost of a tick does not depend on the rate
                count = tick_count if "closed" not in method else tick_count // 10
                costs[method] = statistics.median(_tick_cost(method, rate, count) for _ in range(5))
            rows.append(Row(method, rate, ticks, float(phi_err), float(omega_err), costs[method]))
    return rows
