"""The log–log figure of docs/speed-vs-error.png: time per position against maximum error."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

__all__ = ["FLOOR", "MARKERS", "plot"]

FLOOR = 1e-17  # errors below this are drawn at it (log axes)
MARKERS = {"position": "o", "velocity": "s", "acceleration": "^"}


def plot(report: Any, path: Path) -> None:
    fig, (left, right) = plt.subplots(1, 2, figsize=(14, 6.5), gridspec_kw={"width_ratios": [3, 2]})
    rows = [r for r in report.results if r.scene == "four_bar"]
    methods = list(dict.fromkeys(r.method for r in rows))
    cmap = plt.get_cmap("tab20")
    for i, method in enumerate(methods):
        r = next(x for x in rows if x.method == method)
        colour = cmap(i % 20)
        for q, err in r.errors.items():
            left.scatter(
                max(err, FLOOR) if math.isfinite(err) else 1e3,
                r.seconds * 1e6,
                marker=MARKERS[q],
                color=colour,
                s=60 if r.family == "ours" else 36,
                edgecolors="black",
                linewidths=0.4,
                label=method if q == "position" else None,
                zorder=3,
            )
    for q, m in MARKERS.items():
        left.scatter([], [], marker=m, color="white", edgecolors="black", label=q)
    left.set(
        xscale="log",
        yscale="log",
        xlabel="maximum error over one turn (positions × scale⁻¹; analogs relative)",
        ylabel="time per position (µs)",
        title="Four-bar: time per position against maximum error",
    )
    left.grid(True, which="major", alpha=0.3)
    left.legend(fontsize=7, loc="upper right", ncol=2)
    if report.integration:
        colours = {
            "exact piecewise (Motion)": "tab:green",
            "closed form, plain float": "tab:olive",
            "Euler": "tab:red",
            "RK4": "tab:blue",
        }
        for method, shade in colours.items():
            pts = [r for r in report.integration if r["method"] == method]
            if not pts:
                continue
            xs = [max(r["phi_error"], FLOOR) for r in pts]
            ys = [r["tick_s"] * 1e6 for r in pts]
            right.plot(xs, ys, "-o", color=shade, label=method, alpha=0.8)
            for x, y, r in zip(xs, ys, pts, strict=True) if method in ("Euler", "RK4") else ():
                right.annotate(f"{r['rate']:g} Hz", (x, y), fontsize=7, xytext=(3, 3), textcoords="offset points")
        right.set(
            xscale="log",
            yscale="log",
            xlabel=f"max |φ error| over {report.config.duration:g} s (rad)",
            ylabel="time per tick (µs, Python)",
            title="φ(t) with piecewise ε: error against cost",
        )
        right.grid(True, which="major", alpha=0.3)
        right.legend(fontsize=8)
    m = report.machine
    fig.suptitle(f"{m['cpu']}, {m['cores']} cores, Python {m['python']}, numpy {m['numpy']}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
