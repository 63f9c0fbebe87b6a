"""bench/node_dynamic.py's summary, untimed: the ratio per round, the worst delivered, the verdict."""

from __future__ import annotations

import pytest

from bench.node_dynamic import summary


def row(kinematic: float, dynamic: float, delivered: float = 1.0) -> dict[str, dict[str, float]]:
    return {"kinematic": {"cpu": kinematic, "delivered": 1.0}, "dynamic": {"cpu": dynamic, "delivered": delivered}}


def test_the_summary_gives_the_median_ratio_the_worst_delivered_and_the_verdict() -> None:
    lines = summary([row(0.20, 0.24), row(0.25, 0.30, 0.995), row(0.30, 0.45)])
    assert lines[0].startswith("kinematic CPU 25.0 [20.0–30.0] %, dynamic CPU 30.0 [24.0–45.0] %, "
                               "dynamic/kinematic 1.20 [1.20–1.50]; delivered: dynamic ≥ 99.50 %")
    assert lines[1].startswith("RESULT PASS: dynamic/kinematic CPU median 1.20 (target <= 1.3)")
    assert summary([row(0.2, 0.3)])[1].startswith("RESULT FAIL: dynamic/kinematic CPU median 1.50")
    assert summary([row(0.2, 0.2, 0.98)])[1].startswith("RESULT FAIL")


def test_the_node_s_own_count_is_read_from_diagnostics_after_the_lag() -> None:
    import math
    from types import SimpleNamespace as NS

    from bench.node_dynamic import LAG_NS, Diagnostics, scenes_summary

    def message(stamp_ns: int, status: str, share: str) -> NS:
        values = [NS(key="status", value=status), NS(key="tick_share", value=share),
                  NS(key="compute_factor", value="3.5")]
        return NS(header=NS(stamp=NS(sec=stamp_ns // 10**9, nanosec=stamp_ns % 10**9)),
                  status=[NS(level=b"\x01" if status == "behind" else b"\x00", values=values)])

    seen = Diagnostics()
    start = 100 * 10**9
    seen(message(start + 10**9, "behind", "0.5000"))  # the warm-up's second: not counted
    seen(message(start + LAG_NS, "ok", "0.9990"))
    seen(message(start + LAG_NS + 10**9, "behind", "0.9500"))
    seen(message(start + LAG_NS + 2 * 10**9, "ok", "nan"))
    got = seen.between(start, start + LAG_NS + 2 * 10**9)
    assert got == pytest.approx({"diagnostics": 2.0, "behind": 1.0, "tick_share": 0.95, "tick_share_mean": 0.9745,
                   "compute_factor": 3.5})
    assert math.isnan(seen.between(start, start + 10)["tick_share"])
    rows = {"engine": [{"delivered": 0.995, "cpu": 0.8, "tick_share": 0.999}],
            "tipper": [{"delivered": 0.989, "cpu": 0.4, "tick_share": math.nan}]}
    lines = scenes_summary(rows)
    assert lines[0] == ("engine: delivered 99.50 % [99.50–99.50], CPU 80.0 % of a core, "
                        "node's own tick_share ≥ 99.90 %")
    assert lines[1] == "tipper: delivered 98.90 % [98.90–98.90], CPU 40.0 % of a core"
    assert lines[2].startswith("RESULT FAIL: every scene delivered >= 98.90 %")


def test_the_listener_s_latency_order_and_gaps() -> None:
    from bench.node_dynamic import latency_figures, scenes_summary

    ms = 1_000_000
    stamps = [0, ms, 2 * ms, 2 * ms, 5 * ms, 6 * ms]  # a repeat, then a gap of 3 periods
    received = [s + 300_000 for s in stamps]
    received[4] += 4 * ms
    got = latency_figures(stamps, received, 0, 6 * ms, 1000.0)  # the last stamp outside the window
    assert got["latency_min"] == pytest.approx(0.3) and got["latency_max"] == pytest.approx(4.3)
    assert got["latency_p50"] == pytest.approx(0.3) and got["max_gap"] == pytest.approx(3.0)
    assert got["min_gap"] == pytest.approx(1.0)
    assert got["increasing"] == 0.0  # the repeated stamp
    assert latency_figures(stamps[:3], received[:3], 0, 6 * ms, 1000.0)["increasing"] == 1.0
    rows = {"engine": [{"delivered": 0.995, "cpu": 0.8, "latency_p50": 0.4, "latency_p99": 2.5, "latency_max": 9.0}]}
    assert scenes_summary(rows)[0] == ("engine: delivered 99.50 % [99.50–99.50], CPU 80.0 % of a core, stamp to "
                                       "receipt p50 0.40 ms, p99 ≤ 2.50 ms, max 9.0 ms")
