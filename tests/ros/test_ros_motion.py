"""The time law: exact from each segment's start, continuous across segment changes."""

from __future__ import annotations

import math
from fractions import Fraction

import numpy as np
import pytest

from linkage_ros.motion import SEGMENT_HOLD, SEGMENT_REVERSE, Motion

EPS = np.finfo(float).eps
#: φ after 10⁷ ticks at 1 kHz must stay this close to the closed form (issue 6).
TOL_LONG_RUN = 1e-9
#: Continuity across a segment change: a few ulps of the values involved.
TOL_CONT = 64 * EPS
TICKS = 10**7
RATE_HZ = 1000


def exact_phi(phi0: float, omega: float, epsilon: float, t: Fraction) -> Fraction:
    """The closed form in rational arithmetic (inputs are exact binary fractions)."""
    return Fraction(phi0) + Fraction(omega) * t + Fraction(epsilon) * t * t / 2


@pytest.mark.parametrize("epsilon", [0.0, 3.0e-6, -2.5e-6])
def test_phi_after_ten_million_ticks_matches_the_closed_form(epsilon: float) -> None:
    phi0, omega = 0.3, 2 * math.pi * 0.731
    motion = Motion(phi0=phi0, omega=omega, epsilon=epsilon)
    rng = np.random.default_rng(6)
    ks = np.unique(np.concatenate([rng.integers(0, TICKS + 1, 2000), [0, 1, TICKS - 1, TICKS]]))
    # Tick times as the node makes them: integer nanoseconds since the start, divided once.
    times = np.array([(int(k) * 1_000_000) / 1e9 for k in ks])
    phi, w, e = motion.states(times)
    worst = 0.0
    for k, p in zip(ks.tolist(), phi.tolist()):
        worst = max(worst, abs(float(exact_phi(phi0, omega, epsilon, Fraction(k, RATE_HZ)) - Fraction(p))))
    assert worst < TOL_LONG_RUN, f"max |φ − closed form| = {worst:.3g} rad"
    assert np.all(e == epsilon)
    assert w[-1] == pytest.approx(omega + epsilon * TICKS / RATE_HZ, rel=4 * EPS)


def test_scalar_and_vectorised_states_agree_bit_for_bit() -> None:
    motion = Motion(phi0=-1.25, omega=0.7, epsilon=0.05)
    motion.set_omega(3.0, -2.0)
    motion.set_epsilon(7.5, 0.4)
    times = np.linspace(-1.0, 20.0, 997)
    phi, omega, eps = motion.states(times)
    for i, t in enumerate(times.tolist()):
        assert motion.state(t) == (phi[i], omega[i], eps[i])


def test_setting_omega_keeps_phi_continuous_and_starts_a_segment() -> None:
    motion = Motion(phi0=0.5, omega=1.0, epsilon=0.2)
    t = 2.5
    before = motion.state(t)
    segment = motion.set_omega(t, -3.0)
    after = motion.state(t)
    assert after[0] == pytest.approx(before[0], abs=TOL_CONT)
    assert after[1] == -3.0
    assert after[2] == 0.2  # epsilon kept
    assert segment.t0 == t and len(motion.segments) == 2
    # Afterwards the law is the closed form from the new segment's start.
    assert motion.state(t + 2.0)[0] == pytest.approx(before[0] - 3.0 * 2.0 + 0.5 * 0.2 * 4.0, abs=TOL_CONT)


def test_setting_epsilon_keeps_phi_and_omega_continuous() -> None:
    motion = Motion(phi0=0.0, omega=2.0, epsilon=-0.5)
    t = 1.75
    phi, omega, _ = motion.state(t)
    motion.set_epsilon(t, 4.0)
    phi2, omega2, eps2 = motion.state(t)
    assert (phi2, omega2, eps2) == pytest.approx((phi, omega, 4.0), abs=TOL_CONT)
    dt = 0.5
    assert motion.state(t + dt)[1] == pytest.approx(omega + 4.0 * dt, abs=TOL_CONT)


def test_reverse_mirrors_the_law_with_phi_and_speed_continuous() -> None:
    motion = Motion(phi0=0.1, omega=1.5, epsilon=0.3)
    t = 2.0
    phi, omega, eps = motion.state(t)
    segment = motion.reverse(t)
    assert segment.tag == SEGMENT_REVERSE
    assert motion.state(t) == pytest.approx((phi, -omega, -eps), abs=TOL_CONT)
    unreversed = Motion(phi0=0.1, omega=1.5, epsilon=0.3)
    for dt in (0.1, 1.0, 3.0):
        mirrored = 2 * phi - unreversed.state(t + dt)[0]
        assert motion.state(t + dt)[0] == pytest.approx(mirrored, abs=TOL_CONT * 16)


def test_hold_freezes_phi_until_the_next_change() -> None:
    motion = Motion(phi0=0.0, omega=1.0)
    motion.hold(1.0)
    assert motion.state(5.0) == (1.0, 0.0, 0.0)
    assert motion.segment_at(5.0).tag == SEGMENT_HOLD
    motion.set_omega(6.0, 2.0)
    assert motion.state(6.5)[0] == pytest.approx(2.0, abs=TOL_CONT)


def test_a_new_segment_discards_the_segments_after_it() -> None:
    motion = Motion(phi0=0.0, omega=1.0)
    motion.set_omega(5.0, 2.0)
    motion.set_omega(3.0, -1.0)
    assert [s.t0 for s in motion.segments] == [0.0, 3.0]
    assert motion.state(4.0)[0] == pytest.approx(3.0 - 1.0, abs=TOL_CONT)


def test_times_before_the_first_segment_extrapolate_it() -> None:
    motion = Motion(phi0=1.0, omega=2.0, epsilon=0.0, t0=10.0)
    assert motion.state(9.0)[0] == pytest.approx(-1.0, abs=TOL_CONT)


def test_crossing_finds_when_phi_reaches_a_value() -> None:
    motion = Motion(phi0=0.0, omega=1.0, epsilon=0.5)
    # φ(t) = t + t²/4 = 3 at t = 2.
    assert motion.crossing(3.0, 0.0, 5.0) == pytest.approx(2.0, abs=TOL_CONT)
    assert motion.crossing(3.0, 2.5, 5.0) is None
    assert Motion(phi0=0.0, omega=0.0).crossing(1.0, 0.0, 10.0) is None


def test_snapshot_and_restore_undo_a_tentative_change() -> None:
    motion = Motion(phi0=0.0, omega=1.0)
    saved = motion.snapshot()
    motion.reverse(1.0)
    motion.restore(saved)
    assert motion.segments == saved
    with pytest.raises(ValueError, match="at least one segment"):
        motion.restore(())


@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_non_finite_values_are_refused(bad: float) -> None:
    with pytest.raises(ValueError, match="must be a finite number"):
        Motion(omega=bad)
    motion = Motion()
    with pytest.raises(ValueError, match="epsilon must be a finite number"):
        motion.set_epsilon(1.0, bad)
    with pytest.raises(ValueError, match="omega must be a finite number"):
        motion.set_omega(1.0, bad)
