"""Five-bars and other multi-input scenes built from dicts (no files) for tests/multi."""

from __future__ import annotations

import copy
from typing import Any

import yaml

import solver
from solver._loader import parse_scene

__all__ = ["FIVE_BAR", "build", "five_bar", "edited"]

FIVE_BAR: dict[str, Any] = yaml.safe_load(
    """
scene: five_bar_test
units: {length: m, angle: rad}
fixed: {O1: [0, 0], O2: [0.2, 0]}
groups:
  - {type: crank, name: left_crank, center: O1, point: A1, length: 0.15, joint: q1}
  - {type: crank, name: right_crank, center: O2, point: A2, length: 0.15, joint: q2}
  - {type: rrr, name: distal, ends: [A1, A2], point: P, lengths: [0.25, 0.25], M: -1}
joints:
  left_distal: {angle: [A1, P]}
  right_distal: {angle: [A2, P]}
outputs: {points: [P], joints: [q1, q2, left_distal, right_distal]}
"""
)


def build(data: dict[str, Any], *, file: str | None = None) -> solver.Scene:
    return solver.Scene(parse_scene(data, file=file))


def edited(edit: Any, base: dict[str, Any] = FIVE_BAR) -> dict[str, Any]:
    data = copy.deepcopy(base)
    edit(data)
    return data


def five_bar(
    *, crank: float = 0.15, distal: float = 0.25, base: float = 0.2, mode: int = -1, points: tuple[str, ...] = ("P",)
) -> solver.Scene:
    data = copy.deepcopy(FIVE_BAR)
    data["fixed"]["O2"] = [base, 0.0]
    data["groups"][0]["length"] = crank
    data["groups"][1]["length"] = crank
    data["groups"][2]["lengths"] = [distal, distal]
    data["groups"][2]["M"] = mode
    data["outputs"]["points"] = list(points)
    return build(data)
