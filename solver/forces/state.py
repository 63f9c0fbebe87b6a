"""The state of one reverse pass (route 2): each body's known wrench, and the results so far."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .._backend import Backend
from .frames import moment_of
from .structure import GROUND

__all__ = ["ForcePass"]


@dataclass
class ForcePass:
    """``wrench[link] = [F, M]``: the resultant force on a link (complex, N) and its moment
    about the world origin (N·m) of every load known so far — its own inertial, gravity and
    applied loads, then the reactions handed back by the groups solved after it, sign flipped.

    Results: ``pins[i]`` the force on ``structure.pins[i].body`` from its other side,
    ``slides[i]`` the (normal force, couple) on ``structure.slides[i].body`` from its guide,
    ``efforts[joint]`` each input's generalized force. A wrench's parts start as None (no load
    yet: no array pass for a zero).
    """

    values: Any
    xp: Backend
    wrench: dict[str, list[Any]]
    pins: list[Any] = field(default_factory=list)
    slides: list[Any] = field(default_factory=list)
    efforts: dict[str, Any] = field(default_factory=dict)

    def point(self, name: str) -> Any:
        return self.values[name].value

    def add(self, link: str, at: Any, force: Any) -> None:
        """Put ``force`` acting at the point ``at`` (complex) on ``link`` (ground: nothing)."""
        if link == GROUND:
            return
        w = self.wrench[link]
        w[0] = force if w[0] is None else w[0] + force
        moment = moment_of(at, force)
        w[1] = moment if w[1] is None else w[1] + moment

    def couple(self, link: str, torque: Any) -> None:
        """Put a pure torque (N·m about +z) on ``link``."""
        w = self.wrench[link]
        w[1] = torque if w[1] is None else w[1] + torque

    def about(self, link: str, at: Any) -> tuple[Any, Any]:
        """``link``'s known force and its moment about the point ``at``: (F, M − at × F)."""
        f, m = self.wrench[link]
        if f is None:
            return 0j, (0.0 if m is None else m)
        return f, moment_of(at, f) * -1.0 if m is None else m - moment_of(at, f)
