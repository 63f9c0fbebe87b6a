"""bench/node_dynamic.py's summary, untimed: the ratio per round, the worst delivered, the verdict."""

from __future__ import annotations

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
