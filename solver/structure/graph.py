"""A drawing as a graph of bodies and pairs: connectivity and the Grübler–Kutzbach count.

Bodies: the ground, every drawn link, a block per slide, a barrel and a rod per actuator.
Pairs (one freedom each, j₁): at every point, a pin for each body beyond the first that carries
it (a pin joining k bodies counts as k − 1 pins); a slide per slide (block on its line) and per
actuator (rod in barrel). A drawing has no pin-in-slot pairs (j₂ = 0).

    F = 3(n − 1) − 2·j₁ − j₂

A coupled input removes one freedom (its angle follows another input's); F must equal the
number of inputs, couplings included, for the inputs to drive the mechanism.
"""

from __future__ import annotations

from dataclasses import dataclass

from .drawing import GROUND, Drawing

__all__ = ["Mobility", "mobility", "body_points", "check_connected"]


@dataclass(frozen=True)
class Mobility:
    """The count of a drawing: n bodies (ground included), j₁ one-freedom pairs, j₂ two-freedom
    pairs, F, and the inputs (couplings included) it must equal."""

    bodies: int
    j1: int
    j2: int
    inputs: int
    coupled: int

    @property
    def count(self) -> int:
        return 3 * (self.bodies - 1) - 2 * self.j1 - self.j2

    def text(self) -> str:
        """``F = 3(n − 1) − 2j₁ − j₂ = 3·3 − 2·4 − 0 = 1``."""
        return (f"F = 3(n − 1) − 2j₁ − j₂ = 3·{self.bodies - 1} − 2·{self.j1} − {self.j2} = {self.count}")


def body_points(drawing: Drawing) -> dict[str, tuple[str, ...]]:
    """Every body and the points it carries (its pins): ground, links, ``SLIDE.block``,
    ``ACTUATOR.barrel`` and ``ACTUATOR.rod``."""
    out: dict[str, tuple[str, ...]] = {GROUND: drawing.ground}
    out.update(drawing.links)
    for s in drawing.slides.values():
        out[f"{s.name}.block"] = (s.point,)
    for a in drawing.actuators.values():
        out[f"{a.name}.barrel"] = (a.between[0],)
        out[f"{a.name}.rod"] = (a.between[1],)
    return out


def mobility(drawing: Drawing) -> Mobility:
    """The Grübler–Kutzbach count of the drawing (module docstring)."""
    bodies = body_points(drawing)
    holders: dict[str, int] = {}
    for pts in bodies.values():
        for q in pts:
            holders[q] = holders.get(q, 0) + 1
    pins = sum(k - 1 for k in holders.values() if k > 0)
    j1 = pins + len(drawing.slides) + len(drawing.actuators)
    inputs = len(drawing.inputs) + len(drawing.actuators)
    coupled = sum(1 for i in drawing.inputs if i.follows is not None)
    return Mobility(len(bodies), j1, 0, inputs, coupled)


def check_connected(drawing: Drawing) -> None:
    """Every body is joined to the ground through pins and slides: else one SceneError line
    naming the parts that hang free."""
    bodies = body_points(drawing)
    parent = {b: b for b in bodies}

    def find(b: str) -> str:
        while parent[b] != b:
            parent[b] = parent[parent[b]]
            b = parent[b]
        return b

    def join(a: str, b: str) -> None:
        ra, rb = find(a), find(b)
        if ra != rb:
            parent[max(ra, rb)] = min(ra, rb)

    at: dict[str, str] = {}
    for b, pts in bodies.items():
        for q in pts:
            if q in at:
                join(at[q], b)
            else:
                at[q] = b
    for s in drawing.slides.values():
        join(f"{s.name}.block", s.on)
    for a in drawing.actuators.values():
        join(f"{a.name}.barrel", f"{a.name}.rod")
    root = find(GROUND)
    parts: dict[str, list[str]] = {}
    for b in bodies:
        r = find(b)
        if r != root:
            parts.setdefault(r, []).append(b.split(".")[0])
    if parts:
        shown = "; ".join(", ".join(dict.fromkeys(p)) for p in parts.values())
        raise drawing.error(
            f"disconnected parts: {shown} share no pin or slide with the ground's part; pin them to it "
            "(a point in both links) or drop them",
            "links",
        )
