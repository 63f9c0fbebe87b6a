"""What the node publishes of a scene's forces, read off the solver's result (no ROS here).

A scene with ``bodies``, ``gravity`` or ``loads`` (docs/forces.md) has, at every instant, an
effort per input joint (``k.effort(joint)``: N·m about +z for a crank, N along the guide for a
slider input) and a load at every pair of bodies: the solver's pins (revolute pairs) and slides
(prismatic pairs). The engine puts them into each :class:`~linkage_ros.frame.Frame`:

* ``frame.efforts``: input joint → effort (float);
* ``frame.loads``: load key → ``(Fx, Fy, M)``: the force (N, world frame) on the pair's first
  body from the other, and the couple (N·m about +z) — zero for a pin, the guide's couple on the
  block for a slide (taken at the block's point).

Topics: ``pin_loads/<name>`` and ``slide_loads/<name>``, where the name is the pair's point; where
several pins share a point, each but the first adds its body's name (``<P>_<body>``, dots turned
into underscores). A load's *key* (in ``frame.loads``, the rerun entities) is that name for a pin
and ``<name>_slide`` for a slide, so that a block's pin and its slide at one point stay apart.
:class:`LoadPair` lists them with their bodies.
A scene without forces has none of this: the frames' ``efforts`` and ``loads`` are empty and
every message is as before.

A scene with Coulomb friction (``friction:``, docs/forces.md#friction) has efforts and loads with
the friction in them (what ``k.effort`` and ``k.reaction`` give), and ``frame.friction``: the power
friction dissipates (W), ``total`` first (:data:`FRICTION_TOTAL`, ``k.friction_power``), then per
element (:func:`friction_names`: a pin by its point, a slider block, an actuator's seal;
``k.friction_loss``) — the ``friction_power`` topic. Empty without friction.

How long a load's arrow is drawn (the node's ``markers`` and the rerun view alike) is one rule,
:class:`LoadArrows` chosen by :func:`load_arrows` from the loads of one cycle: proportional,
``scale`` m per N, up to a ``knee``; beyond it each further tenfold of the load adds one knee
length (ℓ = s·F_k·(1 + log10(F/F_k))), or less where the peak is more than a tenfold above the
knee (``decade``: then the peak is drawn :data:`MAX_FRACTION` of the drawing long), so that a
peak far above the typical loads (the engine's gas force near firing top dead centre: 15.6 kN,
180 × the median) stays inside the drawing while the typical loads stay visible. Runs whose peak
fits proportionally have no knee (``knee`` = inf). A load that is not zero is drawn at least
:data:`FLOOR_FRACTION` of the drawing long, so that its direction shows.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from .arrows import ARROW_FRACTION, ARROW_PERCENTILE, nice_scale

__all__ = [
    "FRICTION_TOTAL",
    "KIND_PIN",
    "KIND_SLIDE",
    "TOPIC_PREFIX",
    "LoadArrows",
    "LoadPair",
    "effort_units",
    "force_layout",
    "forces_row",
    "frame_forces",
    "frame_friction",
    "friction_names",
    "friction_row",
    "has_forces",
    "load_arrows",
    "load_pairs",
    "run_forces",
    "run_friction",
    "sampled_loads",
]

#: The first entry of ``frame.friction`` and of the ``friction_power`` topic: all friction's power.
FRICTION_TOTAL = "total"
KIND_PIN = "pin"
KIND_SLIDE = "slide"
#: The first part of the load topics, by kind of pair.
TOPIC_PREFIX = {KIND_PIN: "pin_loads", KIND_SLIDE: "slide_loads"}
_UNSAFE = re.compile(r"[^A-Za-z0-9_]")
TYPICAL_RATIO = 1.5
"""A long load (drawn at a quarter of the drawing) is the 95th percentile of the cycle's loads,
but at most this many times their median: a few large loads do not shrink every other arrow."""
MAX_FRACTION = 0.5
"""The peak load is drawn proportionally when it fits in this fraction of the drawing; else the
arrows have a knee (:class:`LoadArrows`)."""
FLOOR_FRACTION = 0.04
"""The shortest arrow of a load that is not zero, as a fraction of the drawing (the engine's
small loads near 140° were stubs of a few pixels: issue 24)."""


class LoadArrows(NamedTuple):
    """How long a load's arrow is: ``scale`` m per N up to ``knee`` N (a length of
    ``scale · knee``), then each further tenfold of the load adds :attr:`step` m (``decade``, or
    that knee length again when ``decade`` is None): ℓ(F) = s·F for F ≤ F_k, s·F_k +
    step·log10(F/F_k) above (continuous, increasing); and never shorter than ``floor`` m for a
    load that is not zero (a small load keeps a visible arrow that shows its direction; a zero
    load has none)."""

    scale: float
    knee: float = math.inf
    floor: float = 0.0
    decade: float | None = None

    @property
    def step(self) -> float:
        """The length (m) each tenfold of the load above the knee adds."""
        return self.scale * self.knee if self.decade is None else self.decade

    def factor(self, force: Any) -> Any:
        """Arrow length per N of load at magnitude ``force`` (a float or an array): the arrow is
        the force vector times this factor. NaN stays NaN."""
        if isinstance(force, np.ndarray):
            fs = np.asarray(force, dtype=np.float64)
            with np.errstate(divide="ignore", invalid="ignore"):
                bent = (self.scale * self.knee + self.step * np.log10(fs / self.knee)) / fs
                least = self.floor / fs
            out = np.where(fs > self.knee, bent, np.where(np.isnan(fs), np.nan, self.scale))
            return np.where((fs > 0.0) & (out * fs < self.floor), least, out)
        f = float(force)
        if f > self.knee:
            return (self.scale * self.knee + self.step * math.log10(f / self.knee)) / f
        if f != f:
            return math.nan
        return self.floor / f if 0.0 < f and self.scale * f < self.floor else self.scale

    def planar_factor(self, fx: float, fy: float) -> float:
        """:meth:`factor` of the force (fx, fy) (Python floats: the node's per-tick path)."""
        return float(self.factor(math.hypot(fx, fy)))

    def length(self, force: Any) -> Any:
        """Arrow length (m) of a load of magnitude ``force`` (N)."""
        return self.factor(force) * force

    def describe(self, *, per: str = "m/N") -> str:
        """The rule in words: ``× 0.005 m/N``, or with a knee ``× 0.0001 m/N up to 650 N, then
        +0.065 m per ×10``."""
        text = f"× {self.scale:g} {per}"
        if math.isfinite(self.knee):
            text += f" up to {self.knee:.3g} N, then +{self.step:.3g} m per ×10"
        if self.floor > 0.0:
            text += f", at least {self.floor:.2g} m"
        return text


def load_arrows(samples: Mapping[str, NDArray[np.float64]], extent: float) -> LoadArrows:
    """The arrow rule for loads like ``samples`` (key → (N, 2+) forces, N) in a drawing of
    ``extent`` m: a round scale (1, 2 or 5 × 10^k m/N) that draws a long load
    (:data:`TYPICAL_RATIO`) at about a quarter of ``extent``; if the largest load would then be
    longer than :data:`MAX_FRACTION` of ``extent``, a knee where the proportional part reaches a
    quarter of ``extent``, with one knee length per tenfold above it — or less, so that the peak
    is drawn MAX_FRACTION of ``extent`` long, where it is more than a tenfold above the knee.
    Every rule has a floor of :data:`FLOOR_FRACTION` of ``extent``. Non-finite samples are left
    out; no load at all gives scale 1."""
    parts = [np.linalg.norm(np.asarray(v, dtype=np.float64)[:, :2], axis=1) for v in samples.values() if v.size]
    f = np.concatenate(parts) if parts else np.zeros(0)
    f = f[np.isfinite(f)]
    if not f.size or float(f.max()) <= 0.0:
        return LoadArrows(1.0)
    long = float(np.percentile(f, ARROW_PERCENTILE))
    median = float(np.median(f))
    reference = min(long, TYPICAL_RATIO * median) if median > 0.0 else long
    if reference <= 0.0:
        reference = float(f.max())
    scale = nice_scale(ARROW_FRACTION * extent / reference)
    floor = FLOOR_FRACTION * extent
    peak, most = float(f.max()), MAX_FRACTION * extent
    if scale * peak <= most:
        return LoadArrows(scale, floor=floor)
    knee = ARROW_FRACTION * extent / scale
    bent = LoadArrows(scale, knee, floor)
    if bent.length(peak) <= most:
        return bent
    return bent._replace(decade=(most - scale * knee) / math.log10(peak / knee))  # the peak at `most`


class LoadPair(NamedTuple):
    """One published load: the force on ``body`` from ``other`` at ``point`` (``kind`` pin or
    slide; for a slide ``other`` is the guide: ``ground`` or a slotted link), on ``topic``."""

    key: str
    kind: str
    point: str
    body: str
    other: str
    topic: str


def force_layout(scene: Any, inputs: Sequence[str]) -> tuple[bool, tuple[LoadPair, ...], dict[str, str]]:
    """``(has_forces, load_pairs, effort_units)`` of ``scene`` with input joints ``inputs``."""
    forces = has_forces(scene)
    return forces, load_pairs(scene), effort_units(scene, inputs) if forces else {}


def has_forces(scene: Any) -> bool:
    """Whether ``scene`` has bodies, gravity or loads (else no effort and no load is published)."""
    return bool(getattr(scene, "has_forces", False))


def load_pairs(scene: Any) -> tuple[LoadPair, ...]:
    """The scene's pins, then its slides, with their keys (empty without forces)."""
    if not has_forces(scene):
        return ()
    out: list[LoadPair] = []
    for kind, pairs in ((KIND_PIN, scene.pins), (KIND_SLIDE, scene.slides)):
        taken: set[str] = set()
        for pair in pairs:
            other = pair.other if kind == KIND_PIN else pair.guide
            name = pair.point if pair.point not in taken else _UNSAFE.sub("_", f"{pair.point}_{pair.body}")
            taken.add(name)
            key = name if kind == KIND_PIN else f"{name}_slide"
            out.append(LoadPair(key, kind, pair.point, pair.body, other, f"{TOPIC_PREFIX[kind]}/{name}"))
    return tuple(out)


def effort_units(scene: Any, inputs: Sequence[str]) -> dict[str, str]:
    """Each input's effort unit: N·m for an angle, N for a slide."""
    units = getattr(scene, "joint_units", {})
    return {q: "N" if units.get(q, "rad") == "m" else "N·m" for q in inputs}


def _pair_load(k: Any, pair: LoadPair) -> tuple[Any, Any, Any]:
    """(Fx, Fy, M) of one pair from a solved result (floats, or (N,) arrays)."""
    if pair.kind == KIND_PIN:
        force = k.reaction(pair.point, on=pair.body, by=pair.other)
        return force[..., 0], force[..., 1], 0.0
    slide = k.slide_reaction(pair.body)
    return slide.force[..., 0], slide.force[..., 1], slide.couple


def frame_forces(k: Any, inputs: Sequence[str], pairs: Sequence[LoadPair]
                 ) -> tuple[dict[str, float], dict[str, tuple[float, float, float]]]:
    """Efforts and loads of a one-instant solve, as Python floats."""
    efforts = {q: float(k.effort(q)) for q in inputs}
    loads = {}
    for pair in pairs:
        fx, fy, m = _pair_load(k, pair)
        loads[pair.key] = (float(fx), float(fy), float(m))
    return efforts, loads


def run_forces(k: Any, inputs: Sequence[str], pairs: Sequence[LoadPair]
               ) -> tuple[dict[str, NDArray[np.float64]], dict[str, NDArray[np.float64]]]:
    """Efforts ((N,) each) and loads ((N, 3) each: Fx, Fy, M) of a vectorised solve."""
    efforts = {q: np.asarray(k.effort(q), dtype=np.float64).reshape(-1) for q in inputs}
    loads = {}
    for pair in pairs:
        columns = np.broadcast_arrays(*(np.asarray(c, dtype=np.float64) for c in _pair_load(k, pair)))
        loads[pair.key] = np.stack([c.reshape(-1) for c in columns], axis=1)
    return efforts, loads


def forces_row(forces: Sequence[Mapping[str, Any]], i: Any
               ) -> tuple[dict[str, float], dict[str, tuple[float, float, float]]]:
    """Sample ``i`` of :func:`run_forces`' efforts and loads (the first two of ``forces``), as
    Python floats."""
    efforts, loads = forces[0], forces[1]
    return ({q: float(v[i]) for q, v in efforts.items()},
            {key: (float(v[i, 0]), float(v[i, 1]), float(v[i, 2])) for key, v in loads.items()})


def sampled_loads(k: Any, inputs: Sequence[str], pairs: Sequence[LoadPair]) -> dict[str, NDArray[np.float64]]:
    """(Fx, Fy) of every load of a masked vectorised solve, at its valid, finite samples only."""
    valid = np.asarray(k.valid, dtype=bool)
    _, loads = run_forces(k, inputs, pairs)
    return {key: np.ascontiguousarray(v[valid & np.isfinite(v).all(axis=1), :2]) for key, v in loads.items()}


def friction_names(scene: Any) -> tuple[str, ...]:
    """The entries of ``frame.friction``: :data:`FRICTION_TOTAL`, then each friction element
    (solver.forces.friction_report.friction_names: pins by point, slider blocks, actuators'
    seals); empty for a scene without friction."""
    if not getattr(scene, "has_friction", False):
        return ()
    from solver.forces.friction_report import friction_names as elements

    return (FRICTION_TOTAL, *elements(scene))


def frame_friction(k: Any, names: Sequence[str]) -> dict[str, float]:
    """``frame.friction`` of a one-instant solve (W, Python floats); ``names``: :func:`friction_names`."""
    return {name: float(k.friction_power if name == FRICTION_TOTAL else k.friction_loss(name)) for name in names}


def run_friction(k: Any, names: Sequence[str]) -> dict[str, NDArray[np.float64]]:
    """:func:`frame_friction` of a vectorised solve: (N,) arrays."""
    n = np.shape(k.valid)[0]
    return {name: np.broadcast_to(np.asarray(k.friction_power if name == FRICTION_TOTAL else k.friction_loss(name),
                                             dtype=np.float64), (n,)).reshape(-1) for name in names}


def friction_row(friction: Mapping[str, NDArray[np.float64]], i: Any) -> dict[str, float]:
    """Sample ``i`` of :func:`run_friction`, as Python floats."""
    return {name: float(v[i]) for name, v in friction.items()}
