"""Structure: a mechanism as drawn (points, links, ground, inputs, slides, actuators at one pose)
→ mobility → Assur decomposition → the same groups as a written scene.

Stable API (docs/scenes.md, "The drawn form"; the model importers build on it):

``scene_dict_from_drawing(scene: Mapping, *, source: str | None = None) -> dict``
    ``scene`` is a whole scene mapping with a ``drawing:`` section (and ``units``, ``outputs``,
    optionally ``joints``, ``bodies``, ``gravity``, ``loads``, ``motor`` …, naming drawn links);
    returns the equivalent *group* scene mapping (``fixed``, ``groups``, the rest passed on),
    which ``solver._loader.parse_scene`` loads like any scene file. ``source`` names the file
    in every SceneError. The loader calls it for a file with ``drawing:``, so a drawn scene is
    a scene: everything downstream (forces, dynamics, synthesis, the compiled instant, URDF, the
    node) sees the same groups.
``find_structure(scene: Mapping, *, source: str | None = None) -> Structure``
    The analysis alone: ``.mobility`` (Grübler–Kutzbach count), ``.steps`` (the groups in the
    order found: kind, name, links placed, points provided, fields, mode, conditioning at the
    drawn pose), ``.ordered`` (as emitted), ``.inputs_drawn`` (each input's value at the drawn
    pose, SI), ``.drawing`` (the validated drawing).
``emit(scene, structure) -> dict``
    The group scene of a structure already found.

The drawing (solver.structure.drawing):

```yaml
drawing:
  points: {NAME: [x, y], ...}           # the scene's length unit
  ground: [NAME, ...]                   # the frame's points
  links: {LINK: [NAME, NAME, ...], ...} # each link's points (≥ 2); first two = its frame
  inputs: [LINK, {link: LINK, joint: q}, {link: LINK, follows: q, ratio: r, offset: θ₀}]
  slides: {SLIDE: {point: B, on: ground | LINK, along: [G1, G2], joint?: s}}
  actuators: {ACT: {between: [E, F], stroke: [closed, open], joint?: s}}
```

An input link is pinned to the ground at its first point; its angle (first → second point, from
+x) is the input. A coupled input (``follows``; MJCF ``<joint>`` equality, URDF ``<mimic>``)
removes a freedom and is emitted as a ``coupled_crank`` group ``{center, point, length, joint,
follows, ratio, offset}`` (angle = ratio·φ_follows + offset; offset in the angle unit): that group
kind is the importers' to add; until it exists such a scene is refused by the loader by type.
Every fault is one SceneError line naming what to change. Deterministic: the same drawing gives
the same groups, names and order every time. A triad (class 3: a ternary link on three binary
links) is found after the dyads (``triad_step``), its mode read off the pose, and so is a triad
with one of its points on a ground slide instead of a third binary link (``slider_triad_step``); a
group of class 4 or more, or another class-3 group, is refused naming its links.
"""

from __future__ import annotations

from .decompose import Stall, Step
from .drawing import DRAWING_KEYS, GROUND, Drawing
from .emit import Structure, emit, find_structure, scene_dict_from_drawing
from .graph import Mobility

__all__ = [
    "DRAWING_KEYS",
    "GROUND",
    "Drawing",
    "Mobility",
    "Stall",
    "Step",
    "Structure",
    "emit",
    "find_structure",
    "scene_dict_from_drawing",
]
