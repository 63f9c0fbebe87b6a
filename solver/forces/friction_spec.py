"""``friction:`` of a scene file → :class:`FrictionSpec` (Coulomb friction, docs/forces.md#friction).

    friction:
      pins:      {O: {mu: 0.12, radius: 0.010}}   # a pin by its point: moment μ·r·|R| against the
                                                  #   relative rotation of the two bodies it joins
      all_pins:  {mu: 0.08, radius: 0.006}         # default for the pins not named
      slides:    {piston: {mu: 0.15}}              # a block by its body name: μ·|N| along the guide
      actuators: {lift: {force: 150.0}}            # a cylinder's seal friction (N) against its stroke rate

``mu`` is dimensionless (0 ≤ μ ≤ MU_MAX), ``radius`` a length in the scene's unit (kept in m),
``force`` in N. An actuator's cylinder eyes carry no pin friction (the cylinder is a massless
two-force member: a couple on it is not modelled); its seal friction is ``actuators``. Every
fault is one SceneError line naming the key (did-you-mean for a misspelt pin, block or actuator).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

from .._fields import Entry, Units, show, suggest
from .structure import Structure

__all__ = ["FrictionSpec", "PinFriction", "SlideFriction", "SealFriction", "parse_friction", "MU_MAX"]

#: Largest coefficient of friction accepted (far beyond any dry pair, ~1).
MU_MAX = 10.0
#: Largest seal force (N).
SEAL_MAX = 1e12


@dataclass(frozen=True)
class PinFriction:
    """Friction at the pin ``index`` of the structure (between ``body`` and ``other``, link names)."""

    index: int
    point: str
    body: str
    other: str
    mu: float
    radius: float  # m

    @property
    def circle(self) -> float:
        """The friction circle's radius μ·r (m)."""
        return self.mu * self.radius


@dataclass(frozen=True)
class SlideFriction:
    """Friction of the slide ``index`` (its block ``block``, link name)."""

    index: int
    block: str
    mu: float


@dataclass(frozen=True)
class SealFriction:
    """A cylinder's seal friction: ``force`` (N) against the stroke rate of ``joint``."""

    actuator: str
    joint: str
    force: float


@dataclass(frozen=True)
class FrictionSpec:
    pins: tuple[PinFriction, ...] = ()
    slides: tuple[SlideFriction, ...] = ()
    seals: tuple[SealFriction, ...] = field(default_factory=tuple)

    @property
    def empty(self) -> bool:
        return not (self.pins or self.slides or self.seals)


_KEYS = ("pins", "all_pins", "slides", "actuators")


def parse_friction(
    top: Entry, units: Units, structure: Structure, names: Mapping[str, str], actuators: Mapping[str, str]
) -> FrictionSpec | None:
    """The scene's ``friction`` (None without the key). ``names``: a link's default name → its body
    name; ``actuators``: an actuator group's name → its stroke joint."""
    if "friction" not in top.data:
        return None
    raw = top.raw("friction")
    if not isinstance(raw, Mapping) or not raw:
        raise top.error(f"must map {', '.join(_KEYS)} to their values (docs/forces.md#friction), got {show(raw)}",
                        "friction")
    f = top.child("friction", raw)
    f.expect(_KEYS)
    massless = structure.massless
    usable = [(i, p) for i, p in enumerate(structure.pins) if p.body not in massless and p.other not in massless]
    points = list(dict.fromkeys(p.point for _, p in usable))
    every = sorted({p.point for p in structure.pins})
    named: dict[str, tuple[float, float]] = {}
    for key, value in _mapping(f, "pins").items():
        point = str(key)
        e = f.child("pins", f.raw("pins")).child(point, value)
        if point not in points:
            if point in every:
                raise e.error(f"pin '{point}' is an actuator cylinder's eye: a cylinder is a massless two-force "
                              "member, its friction is its seal's (friction.actuators)")
            near = suggest(point, points)
            hint = f" (did you mean '{near[0]}'?)" if near else ""
            raise e.error(f"no pin at '{point}'{hint}; pins: {', '.join(points)}")
        named[point] = _circle(e, units)
    default = _circle(f.child("all_pins", f.raw("all_pins")), units) if "all_pins" in f.data else None
    pins = []
    for i, p in usable:
        mu_r = named.get(p.point, default)
        if mu_r is not None and mu_r[0] > 0.0 and mu_r[1] > 0.0:
            pins.append(PinFriction(i, p.point, p.body, p.other, mu_r[0], mu_r[1]))
    blocks = {names.get(s.body, s.body): (i, s.body) for i, s in enumerate(structure.slides)}
    blocks.update({s.body: (i, s.body) for i, s in enumerate(structure.slides)})
    slides = []
    for key, value in _mapping(f, "slides").items():
        name = str(key)
        e = f.child("slides", f.raw("slides")).child(name, value)
        if name not in blocks:
            known = [names.get(s.body, s.body) for s in structure.slides]
            near = suggest(name, known)
            hint = f" (did you mean '{near[0]}'?)" if near else ""
            raise e.error(f"unknown slider block '{name}'{hint}; blocks: {', '.join(known) or 'none'}")
        e.expect(("mu",))
        mu = _mu(e)
        e.done()
        i, link = blocks[name]
        if mu > 0.0:
            slides.append(SlideFriction(i, link, mu))
    seals = []
    for key, value in _mapping(f, "actuators").items():
        name = str(key)
        e = f.child("actuators", f.raw("actuators")).child(name, value)
        if name not in actuators:
            near = suggest(name, list(actuators))
            hint = f" (did you mean '{near[0]}'?)" if near else ""
            raise e.error(f"unknown actuator '{name}'{hint}; actuators: {', '.join(actuators) or 'none'}")
        e.expect(("force",))
        force = e.number("force")
        if not 0.0 <= force <= SEAL_MAX:
            raise e.error(f"a seal force is 0 … {SEAL_MAX:g} N, got {force}", "force")
        e.done()
        if force > 0.0:
            seals.append(SealFriction(name, actuators[name], force))
    f.done()
    return FrictionSpec(tuple(pins), tuple(slides), tuple(seals))


def _mapping(f: Entry, key: str) -> Mapping:
    if key not in f.data:
        return {}
    raw = f.raw(key)
    if not isinstance(raw, Mapping):
        raise f.error(f"must map names to their friction, got {show(raw)}", key)
    return raw


def _mu(e: Entry) -> float:
    mu = e.number("mu")
    if mu < 0.0:
        raise e.error(f"a coefficient of friction must not be negative, got {mu}", "mu")
    if mu > MU_MAX:
        raise e.error(f"a coefficient of friction is at most {MU_MAX:g}, got {mu}", "mu")
    return mu


def _circle(e: Entry, units: Units) -> tuple[float, float]:
    e.expect(("mu", "radius"))
    mu = _mu(e)
    radius = e.length("radius", units, positive=False)
    if radius < 0.0:
        raise e.error(f"a pin's radius must not be negative, got {e.raw('radius')}", "radius")
    e.done()
    return mu, radius

