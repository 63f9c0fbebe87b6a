"""A scene's mechanism opened into a spanning tree of bodies: the structure a URDF describes.

Every structural group adds its bodies and the joints that hang them on the tree; a group that
closes a loop leaves one joint out of the tree (the *cut*) and records a point on each side of it:

=========================  =====================================  ==============================
group                      bodies (tree joint from the parent)    cut (side a / side b)
=========================  =====================================  ==============================
crank O→A                  ``<g>`` (revolute about O)             none (no loop)
actuator A–C, pivot O      ``<g>`` link OC (revolute about O),    pin C: rod / link
                           ``<g>_barrel`` (revolute about A),
                           ``<g>_rod`` (prismatic along the
                           barrel: its coordinate is the stroke)
attached P                 none: P is fixed on the body that      none
                           carries its base and direction
rrr A–B–C                  ``<g>_AB`` (revolute about A),         pin B: ``<g>_AB`` / ``<g>_CB``
                           ``<g>_CB`` (revolute about C)
rrp A–B on a guide         ``<g>`` rod AB (revolute about A),     pin B: rod / slider
                           ``<g>_slider`` (prismatic on guide)
slotted A through B        ``<g>`` (revolute about A),            pin B: eyelet / the body that
                           ``<g>_eyelet`` (prismatic along it)    carries B (the drum)
triad A, B, C → D, E, F     ``<g>_AD`` (revolute about A),        pins E, F: ``<g>_BE`` /
                           ``<g>_BE`` (about B), ``<g>_CF``       ``<g>``, ``<g>_CF`` / ``<g>``
                           (about C), ternary ``<g>`` [D, E, F]
                           (revolute about D on ``<g>_AD``)
slider_triad D on a guide; ``<g>_slider`` (prismatic on the guide),  pins E, F: ``<g>_BE`` /
B, C → E, F                ternary ``<g>`` [D, E, F] (revolute     ``<g>``, ``<g>_CF`` / ``<g>``
                           about D on the slider), ``<g>_BE``
                           (about B), ``<g>_CF`` (about C); a
                           guide on a moving link: the slider
                           on the carrying body; the swinging
                           block at A: ``<g>_block`` (revolute
                           about A), the ternary link prismatic
                           along it
spherical_crank_slider     ``<g>_shaft`` (about y), ``<g>_ring``  pin K: ring / cage
                           (about the groove normal), ``<g>_cage``
                           (about −x)
=========================  =====================================  ==============================

Why these cuts: each loop is cut at the one pin whose both sides are bodies the group itself
adds, so every body stays on the tree (and moves in RViz) and each tree joint's coordinate is
a plain angle or slide read off the solved points. Planar bodies have their frame origin at
their pivot and their x axis along a named pair of points; angles are counter-clockwise
positive in (−π, π], except the driving crank's, which follows φ unwrapped.

Vector-loop scenes (seed 004) have no groups to read bodies from: :mod:`.vectors` reads them off
the vectors (bodies per angle class, slides for variable lengths, one pin cut per contour).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any

from solver.errors import SceneError
from solver.groups import (
    RRP,
    RRR,
    Actuator,
    Attached,
    CoupledCrank,
    Crank,
    JointExpression,
    SliderTriad,
    Slotted,
    SphericalCrankSlider,
    Triad,
)

from .inertial import name_and_weigh
from .tree import BASE_LINK, Body, Cut, TreeJoint, TreeModel, Vec3, check_names
from .vectors import build_vector_model

__all__ = [
    "BASE_LINK",
    "Body",
    "Cut",
    "TreeJoint",
    "TreeModel",
    "build_model",
    "exportable_model",
    "SUPPORTED_GROUPS",
]

#: Group kinds the URDF export understands.
SUPPORTED_GROUPS = ("crank", "actuator", "attached", "rrr", "rrp", "slotted", "triad", "slider_triad",
                    "spherical_crank_slider", "joint")


def _c(v: Vec3) -> complex:
    return complex(v[0], v[1])


def _v(z: complex) -> Vec3:
    return (float(z.real), float(z.imag), 0.0)


class _Builder:
    def __init__(self, scene: object) -> None:
        self.scene = scene
        self.file = getattr(scene, "path", None) or getattr(scene, "name", None)
        base = Body(BASE_LINK, "base")
        for name, value in scene.fixed_points.items():  # type: ignore[attr-defined]
            xyz = [float(x) for x in value] + [0.0] * (3 - len(value))
            base.local[name] = (xyz[0], xyz[1], xyz[2])
        self.bodies: dict[str, Body] = {BASE_LINK: base}
        self.owner: dict[str, str] = {n: BASE_LINK for n in base.local}
        self.joints: list[TreeJoint] = []
        self.cuts: list[Cut] = []
        self.slotted_through = {
            g.through for g in scene.ordered if isinstance(g, Slotted)  # type: ignore[attr-defined]
        }

    def error(self, message: str, group: object | None = None) -> SceneError:
        entry = f"{getattr(group, 'kind', '')} '{getattr(group, 'name', '')}'" if group else None
        return SceneError(f"URDF export: {message}", file=self.file, entry=entry)

    def add_body(self, body: Body, group: object) -> Body:
        if body.name in self.bodies:
            raise self.error(f"two bodies would be named '{body.name}'", group)
        self.bodies[body.name] = body
        return body

    def holder(self, point: str, group: object) -> Body:
        name = self.owner.get(point)
        if name is None:
            raise self.error(f"point '{point}' is on no body solved before this group", group)
        return self.bodies[name]

    def pin(self, parent: Body, child: Body, at: str, *, unwrap: str | None = None) -> None:
        """A planar revolute joint about point ``at`` (the child's frame origin)."""
        self.joints.append(
            TreeJoint(
                name=f"{child.name}_joint",
                type="continuous",
                parent=parent.name,
                child=child.name,
                xyz=parent.local[at],
                rpy=(0.0, 0.0, 0.0),
                axis=(0.0, 0.0, 1.0),
                rule="planar_pin",
                data=(unwrap,),
            )
        )
        child.pins.append(at)

    # -- groups ------------------------------------------------------------------------------
    def crank(self, g: Crank) -> None:
        role = "drum" if g.point in self.slotted_through else "bar"
        body = self.add_body(
            Body(g.name, role, g.center, (g.center, g.point),
                 {g.center: (0.0, 0.0, 0.0), g.point: (g.length, 0.0, 0.0)}),
            g,
        )
        body.bars.append((g.center, g.point))
        if role == "drum":
            body.size["radius"] = g.length
        self.pin(self.holder(g.center, g), body, g.center, unwrap=g.joint if g.drives and g.plain else None)
        self.owner[g.point] = body.name

    def actuator(self, g: Actuator) -> None:
        """The pushed link about O, and the cylinder: the barrel pinned at A, the rod sliding in
        it (a prismatic joint whose coordinate is the stroke s = |AC|), cut at the eye C."""
        a, c, o = g.base, g.point, g.pivot
        link = self.add_body(Body(g.name, "bar", o, (o, c), {o: (0.0, 0.0, 0.0), c: (g.length, 0.0, 0.0)}), g)
        link.bars.append((o, c))
        self.pin(self.holder(o, g), link, o)
        closed = g.stroke[0]
        barrel = self.add_body(Body(f"{g.name}_barrel", "barrel", a, (a, c), {a: (0.0, 0.0, 0.0)},
                                    size={"length": closed}), g)
        self.pin(self.holder(a, g), barrel, a)
        rod = self.add_body(Body(f"{g.name}_rod", "rod", c, (a, c), {c: (0.0, 0.0, 0.0)},
                                 size={"length": closed, "open": g.stroke[1]}), g)
        # (the input it follows: its effort is the cylinder's)
        self.joints.append(_planar_slide(barrel.name, rod.name, ((0.0, 0.0, 0.0), 0.0, g.joint)))
        self.owner[c] = link.name
        rod.pins.append(c)
        self.cuts.append(
            Cut(f"{g.name}_{c}", "pin", c, rod.name, (0.0, 0.0, 0.0), link.name, link.local[c],
                f"the eye {c} joins the rod of actuator '{g.name}' to the link it pushes; cutting it keeps "
                "barrel, rod and link on the tree")
        )

    def rrr(self, g: RRR) -> None:
        (a, c), b = g.ends, g.point
        l1, l2 = g.lengths
        sides = []
        for end, length in ((a, l1), (c, l2)):
            parent = self.holder(end, g)
            body = self.add_body(
                Body(f"{g.name}_{end}{b}", "bar", end, (end, b), {end: (0.0, 0.0, 0.0), b: (length, 0.0, 0.0)}), g
            )
            body.bars.append((end, b))
            self.pin(parent, body, end)
            sides.append(body)
        self.owner[b] = sides[0].name
        sides[0].pins.append(b)
        self.cuts.append(
            Cut(f"{g.name}_{b}", "pin", b, sides[0].name, sides[0].local[b], sides[1].name, sides[1].local[b],
                f"pin {b} joins the two bars of RRR dyad '{g.name}'; cutting it keeps both on the tree")
        )

    def rrp(self, g: RRP) -> None:
        a, b = g.end, g.point
        parent = self.holder(a, g)
        rod = self.add_body(Body(g.name, "bar", a, (a, b), {a: (0.0, 0.0, 0.0), b: (g.length, 0.0, 0.0)}), g)
        rod.bars.append((a, b))
        self.pin(parent, rod, a)
        slider = self.ground_slider(g, b)
        self.owner[b] = rod.name
        rod.pins.append(b)
        self.cuts.append(
            Cut(f"{g.name}_{b}", "pin", b, rod.name, rod.local[b], slider.name, (0.0, 0.0, 0.0),
                f"pin {b} joins rod and slider of RRP dyad '{g.name}'; cutting it keeps both on the tree")
        )

    def ground_slider(self, g: RRP | SliderTriad, b: str) -> Body:
        """A slider block ``<g>_slider`` at ``b`` on the group's fixed guide (a prismatic joint
        from the base along the guide: its coordinate is the slide from the guide's origin)."""
        slider = self.add_body(Body(f"{g.name}_slider", "slider", b, complex(g.direction), {b: (0.0, 0.0, 0.0)}), g)
        slider.size["guide_angle"] = math.atan2(g.direction.imag, g.direction.real)
        self.joints.append(
            TreeJoint(
                name=f"{slider.name}_joint",
                type="prismatic",
                parent=BASE_LINK,
                child=slider.name,
                xyz=_v(g.origin),
                rpy=(0.0, 0.0, slider.size["guide_angle"]),
                axis=(1.0, 0.0, 0.0),
                rule="planar_slide",
                data=(_v(g.origin), slider.size["guide_angle"]),
            )
        )
        return slider

    def slider_triad(self, g: SliderTriad) -> None:
        """The slider at D on the guide (on the base, or on the carrying body for a guide on a
        moving link), the ternary link hung at D on it (frame D → E, as the group's θ); the
        swinging block ``<g>_block`` pinned at A with the ternary link sliding along it instead;
        the binary bars about B and C, cut at E and at F (two loops)."""
        (b, c), (d, e, f) = g.ends, g.points
        u, v = g.shape
        local = {d: (0.0, 0.0, 0.0), e: _v(u), f: _v(v)}
        ternary = self.add_body(Body(g.name, "bar", d, (d, e), local), g)
        ternary.bars += [(d, e), (e, f), (f, d)]
        if g.block_at is not None:  # A = D + (p + s·e_t)·w: in the block's frame (x along D → E), D at −p − s·e_t
            a = g.block_at
            block = self.add_body(Body(f"{g.name}_block", "slider", a, (d, e), {a: (0.0, 0.0, 0.0)}), g)
            self.pin(self.holder(a, g), block, a)
            beta = math.atan2(-g.direction.imag, -g.direction.real)
            block.size["yaw"] = beta
            self.joints.append(_planar_slide(block.name, ternary.name, (_v(-complex(g.origin)), beta), beta=beta))
        else:
            slider = self.ground_slider(g, d) if g.carrier is None else self.carried_slider(g, d)
            self.pin(slider, ternary, d)
            slider.pins.append(d)
        bars = []
        for end, point, length in zip((b, c), (e, f), g.lengths):
            parent = self.holder(end, g)
            bar = self.add_body(
                Body(f"{g.name}_{end}{point}", "bar", end, (end, point),
                     {end: (0.0, 0.0, 0.0), point: (length, 0.0, 0.0)}), g
            )
            bar.bars.append((end, point))
            self.pin(parent, bar, end)
            bars.append(bar)
        for name in (d, e, f):
            self.owner[name] = ternary.name
        for bar, point in zip(bars, (e, f)):
            bar.pins.append(point)
            self.cuts.append(
                Cut(f"{g.name}_{point}", "pin", point, bar.name, bar.local[point], ternary.name, ternary.local[point],
                    f"pin {point} joins bar {bar.name} to the ternary link of slider triad '{g.name}'; cutting it "
                    "(and the other bar's pin) keeps the slider, the ternary link and both bars on the tree")
            )

    def carried_slider(self, g: SliderTriad, d: str) -> Body:
        """A slider block ``<g>_slider`` at ``d`` on the guide carried by the body through the
        group's P, Q: a prismatic joint from that body (the slider's frame the carrier's, its
        axis the guide's direction in it; its coordinate the slide from the guide's origin)."""
        assert g.carrier is not None
        p, q = g.carrier
        carrier = next((bd for bd in [self.holder(q, g), self.holder(p, g), *self.bodies.values()]
                        if p in bd.local and q in bd.local), None)
        if carrier is None:
            raise self.error(f"the guide's points {p}, {q} lie on no single rigid body", g)
        pl, ql = _c(carrier.local[p]), _c(carrier.local[q])
        along = (ql - pl) / abs(ql - pl)
        x0 = pl + complex(g.origin) * along
        beta = math.atan2((along * g.direction).imag, (along * g.direction).real)
        slider = self.add_body(Body(f"{g.name}_slider", "slider", d, carrier.axis, {d: (0.0, 0.0, 0.0)},
                                    turn=carrier.turn), g)
        slider.size["yaw"] = beta
        self.joints.append(_planar_slide(carrier.name, slider.name, (_v(x0), beta), beta=beta))
        return slider

    def slotted(self, g: Slotted) -> None:
        a, b = g.pivot, g.through
        parent = self.holder(a, g)
        carrier = self.holder(b, g)
        local = {a: (0.0, 0.0, 0.0), **{p: (d, 0.0, 0.0) for p, d in g.points}}
        link = self.add_body(Body(g.name, "bar", a, (a, b), local), g)
        far = max(g.points, key=lambda p: abs(p[1]))[0]
        link.bars.append((a, far))
        self.pin(parent, link, a)
        eyelet = self.add_body(Body(f"{g.name}_eyelet", "eyelet", b, (a, b), {b: (0.0, 0.0, 0.0)}), g)
        self.joints.append(_planar_slide(link.name, eyelet.name, ((0.0, 0.0, 0.0), 0.0)))
        for p, _ in g.points:
            self.owner[p] = link.name
        eyelet.pins.append(b)
        self.cuts.append(
            Cut(f"{g.name}_{b}", "pin", b, eyelet.name, (0.0, 0.0, 0.0), carrier.name, carrier.local[b],
                f"eyelet pin {b} joins the eyelet sliding on '{g.name}' to '{carrier.name}'; cutting it "
                "keeps the slotted link, the eyelet and the body that carries B on the tree")
        )

    def attached(self, g: Attached) -> None:
        need = (g.base, *g.along)
        candidates = [self.bodies[self.owner[g.base]]] if g.base in self.owner else []
        candidates += list(self.bodies.values())
        body = next((bd for bd in candidates if all(n in bd.local for n in need)), None)
        if body is None:
            raise self.error(
                f"point '{g.point}' is attached to {list(need)}, which lie on no single rigid body", g
            )
        x, r, q = (_c(body.local[n]) for n in need)
        d = q - r
        body.local[g.point] = _v(x + g.distance * complex(math.cos(g.angle), math.sin(g.angle)) * d / abs(d))
        body.bars.append((g.base, g.point))
        self.owner[g.point] = body.name

    def triad(self, g: Triad) -> None:
        """The three binary bars about A, B, C, the ternary link hung at D on the first (frame
        D → E, as the triad's θ), cut at E and at F (two loops)."""
        (a, b, c), (d, e, f) = g.ends, g.points
        u, v = g.shape
        bars = []
        for end, point, length in zip((a, b, c), (d, e, f), g.lengths):
            parent = self.holder(end, g)
            bar = self.add_body(
                Body(f"{g.name}_{end}{point}", "bar", end, (end, point),
                     {end: (0.0, 0.0, 0.0), point: (length, 0.0, 0.0)}), g
            )
            bar.bars.append((end, point))
            self.pin(parent, bar, end)
            bars.append(bar)
        ternary = self.add_body(Body(g.name, "bar", d, (d, e), {d: (0.0, 0.0, 0.0), e: _v(u), f: _v(v)}), g)
        ternary.bars += [(d, e), (e, f), (f, d)]
        self.pin(bars[0], ternary, d)
        bars[0].pins.append(d)
        for name in (d, e, f):
            self.owner[name] = ternary.name
        for bar, point in zip(bars[1:], (e, f)):
            bar.pins.append(point)
            self.cuts.append(
                Cut(f"{g.name}_{point}", "pin", point, bar.name, bar.local[point], ternary.name, ternary.local[point],
                    f"pin {point} joins bar {bar.name} to the ternary link of triad '{g.name}'; cutting it (and "
                    "the other binary bar's pin) keeps all four bodies on the tree")
            )

    def spherical(self, g: SphericalCrankSlider) -> None:
        centre = self.holder(g.center, g)
        if centre.name != BASE_LINK:
            raise self.error(f"the centre '{g.center}' must be a fixed point", g)
        o = centre.local[g.center]
        r = g.radius
        tip = (0.0, 0.0, r)
        shaft = self.add_body(Body(f"{g.name}_shaft", "shaft", size={"radius": r}), g)
        ring = self.add_body(Body(f"{g.name}_ring", "ring", size={"radius": r, "alpha": g.alpha}), g)
        cage = self.add_body(Body(f"{g.name}_cage", "cage", local={g.point: tip}, size={"radius": r}), g)
        ring.local[g.point] = tip
        normal = (math.cos(g.alpha), math.sin(g.alpha), 0.0)
        zero = (0.0, 0.0, 0.0)
        self.joints += [
            TreeJoint(f"{shaft.name}_joint", "continuous", BASE_LINK, shaft.name, o, zero, (0.0, 1.0, 0.0),
                      "joint_value", (g.shaft,)),
            TreeJoint(f"{ring.name}_joint", "continuous", shaft.name, ring.name, zero, zero, normal,
                      "spherical_ring", (g.shaft, g.cage, g.alpha)),
            TreeJoint(f"{cage.name}_joint", "continuous", BASE_LINK, cage.name, o, zero, (-1.0, 0.0, 0.0),
                      "joint_value", (g.cage,)),
        ]
        self.owner[g.point] = cage.name
        self.cuts.append(
            Cut(f"{g.name}_{g.point}", "pin", g.point, ring.name, tip, cage.name, tip,
                f"pin {g.point} joins the bearing ring and the cage of '{g.name}' (the spherical four-bar "
                "shaft–ring–cage–frame); cutting it keeps all three moving bodies on the tree")
        )


def build_model(scene: object) -> TreeModel:
    """The spanning tree of ``scene``'s mechanism (a :class:`solver.Scene`).

    The links the scene names in ``bodies:`` take those names and carry their mass properties
    (:mod:`.inertial`). Raises :class:`solver.SceneError` for a group kind the export does not
    know, or names that would clash in the URDF or in ``joint_states``.
    """
    if any(getattr(g, "kind", "") == "vector_input" for g in scene.ordered):  # type: ignore[attr-defined]
        return build_vector_model(scene)
    b = _Builder(scene)
    handlers: dict[type, Callable[[Any], None]] = {
        Crank: b.crank,
        CoupledCrank: b.crank,
        Actuator: b.actuator,
        RRR: b.rrr,
        RRP: b.rrp,
        Slotted: b.slotted,
        Attached: b.attached,
        SphericalCrankSlider: b.spherical,
        Triad: b.triad,
        SliderTriad: b.slider_triad,
    }
    for g in scene.ordered:  # type: ignore[attr-defined]
        if isinstance(g, JointExpression):
            continue
        handler = handlers.get(type(g))
        if handler is None:
            raise b.error(
                f"group kind '{getattr(g, 'kind', type(g).__name__)}' has no URDF export; "
                f"supported: {', '.join(SUPPORTED_GROUPS)}",
                g,
            )
        handler(g)
    model = TreeModel(
        scene_name=str(scene.name),  # type: ignore[attr-defined]
        dim=int(scene.dim),  # type: ignore[attr-defined]
        input_joint=str(scene.input_joint),  # type: ignore[attr-defined]
        bodies=b.bodies,
        joints=b.joints,
        cuts=b.cuts,
        owner=b.owner,
    )
    model = name_and_weigh(scene, model, b.error)
    check_names(model, tuple(scene.joint_names), b.error)  # type: ignore[attr-defined]
    return model


def exportable_model(scene: object) -> TreeModel | None:
    """:func:`build_model`, or ``None`` for a scene the export cannot open (a group kind it does
    not know, or a vector scene whose outputs do not say enough to read its bodies; the error of
    :func:`build_model` says why): for publishers that add the tree joints where there are any.
    A scene imported from a model file (MJCF, URDF: ``scene.model``, solver.models) has none: its
    joints are the model's own, and the user's model is the tree that robot_state_publisher reads."""
    if getattr(scene, "model", None) is not None:
        return None
    try:
        return build_model(scene)
    except SceneError as exc:
        if "has no URDF export" in str(exc):
            return None
        raise


def _planar_slide(parent: str, child: str, data: tuple[object, ...], *, beta: float = 0.0) -> TreeJoint:
    """A prismatic tree joint along the parent's x axis at its origin (a slotted link's eyelet, an
    actuator's rod in its barrel) — or, with ``data`` = (x₀, β), along the direction β in the
    parent's frame through its point x₀ (a slider triad's carried guide, its swinging block), the
    child's frame keeping the parent's orientation — its coordinate by the ``planar_slide`` rule."""
    x0 = data[0] if isinstance(data[0], tuple) else (0.0, 0.0, 0.0)
    return TreeJoint(name=f"{child}_joint", type="prismatic", parent=parent, child=child, xyz=x0,  # type: ignore[arg-type]
                     rpy=(0.0, 0.0, 0.0), axis=(math.cos(beta), math.sin(beta), 0.0), rule="planar_slide", data=data)
