"""The nodes and rigid bodies of a vector-loop scene, read off its vectors (for :mod:`.vectors`).

See :mod:`.vectors` and docs/urdf.md, "Vector scenes": nodes from the sums' chains, one body per
connected set of constant-length vectors of one angle class, the frame as the constant-angle set
that holds the fixed points, ranks in the solver's order, names.
"""

from __future__ import annotations

import cmath
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from solver.errors import SceneError

from .tree import BASE_LINK

__all__ = ["TOL_PLACE", "Comp", "UnionFind", "Vector", "VectorBodies"]

EPS = float(np.finfo(float).eps)
#: Two frame nodes this close (relative to the scene's size) are one place (a constant vector's
#: end on a fixed point).
TOL_PLACE = 1024 * EPS

_Key = tuple[Any, ...]
_Z = 0j


class UnionFind:
    def __init__(self) -> None:
        self.up: dict[Any, Any] = {}

    def find(self, k: Any) -> Any:
        self.up.setdefault(k, k)
        root = k
        while self.up[root] != root:
            root = self.up[root]
        while self.up[k] != root:
            self.up[k], k = root, self.up[k]
        return root

    def union(self, a: Any, b: Any) -> bool:
        ra, rb = self.find(a), self.find(b)
        if ra == rb:
            return False
        self.up[rb] = ra
        return True


@dataclass
class Vector:
    name: str
    cls: str | None  # the base of its angle: the input unit, an unknown angle, or None
    length: str | None  # the base of its length (None: constant)
    r: float  # the length's offset (the length, when constant)
    angle: float  # the angle's offset (the angle, when constant)
    order: int

    @property
    def canon(self) -> complex:
        """The vector in its class's frame (x along the class's base angle)."""
        return self.r * cmath.exp(1j * self.angle)


@dataclass
class Comp:
    cls: str | None
    nodes: list[str] = field(default_factory=list)
    pos: dict[str, complex] = field(default_factory=dict)  # in the class frame
    rank: int = 0
    order: int = 0
    name: str = ""
    is_base: bool = False
    slides: list[str] = field(default_factory=list)  # variable vectors with an end here


class VectorBodies:
    def __init__(self, scene: Any) -> None:
        self.scene = scene
        self.file = getattr(scene, "path", None) or getattr(scene, "name", None)
        groups = list(scene.ordered)
        self.inp = next(g for g in groups if g.kind == "vector_input")
        self.contours = [g for g in groups if g.kind == "contour"]
        self.points = [g for g in groups if g.kind == "vector_point"]
        self.vjoints = [g for g in groups if g.kind == "vector_joint"]
        self.fixed = {n: complex(float(v[0]), float(v[1])) for n, v in scene.fixed_points.items()}
        self.reported = set(scene.point_names)
        self.solver_of: dict[str, str] = {u: c.name for c in self.contours for u in c.unknowns}
        self.rank_of: dict[str | None, int] = {None: 0, self.inp.unit: 1}
        for i, c in enumerate(self.contours):
            for u in c.unknowns:
                self.rank_of[u] = 2 + i
        self.size = max([abs(z) for z in self.fixed.values()] + [1e-300])

    def error(self, message: str, entry: str | None = None) -> SceneError:
        """An export failure of this vector scene: :func:`~.model.exportable_model` reads the words
        ``has no URDF export`` and gives None, so the node still publishes the scene's joints."""
        return SceneError(f"URDF export: this vector scene has no URDF export: {message}", file=self.file, entry=entry)

    # -- vectors and nodes ---------------------------------------------------------------------
    def collect(self) -> None:
        self.vectors: dict[str, Vector] = {}
        sums: list[tuple[str, tuple[Any, ...]]] = [(f"contour '{c.name}'", c.chain) for c in self.contours]
        sums += [(f"point '{p.point}'", p.chain) for p in self.points]
        for where, chain in sums:
            if not chain:
                raise self.error(f"{where} carries no chain of vectors (a scene loaded by an older solver?)")
            for t in chain:
                if t.vector not in self.vectors:
                    self.vectors[t.vector] = Vector(
                        t.vector, t.alpha.base, t.r.base, float(t.r.offset), float(t.alpha.offset), len(self.vectors)
                    )
                    self.size = max(self.size, abs(float(t.r.offset)))
        uf = self.uf = UnionFind()
        for n in self.fixed:
            uf.find(("node", n))
        for c in self.contours:
            chain = c.chain
            for i, t in enumerate(chain):
                self._link(t, ("c", c.name, i), ("c", c.name, (i + 1) % len(chain)))
        for p in self.points:
            cur: _Key = ("node", p.origin)
            for k, t in enumerate(p.chain):
                nxt: _Key = ("node", p.point) if k == len(p.chain) - 1 else ("p", p.point, k)
                self._link(t, cur, nxt)
                cur = nxt

    def _link(self, t: Any, cur: _Key, nxt: _Key) -> None:
        tail, head = ("tail", t.vector), ("head", t.vector)
        if t.sign > 0:
            self.uf.union(cur, tail)
            self.uf.union(nxt, head)
        else:
            self.uf.union(cur, head)
            self.uf.union(nxt, tail)

    def ends(self, v: str) -> tuple[_Key, _Key]:
        return self.uf.find(("tail", v)), self.uf.find(("head", v))

    def frame_places(self) -> dict[_Key, complex]:
        """Absolute places of the nodes the constant vectors hold on the fixed points."""
        place: dict[_Key, complex] = {}
        for n, z in self.fixed.items():
            root = self.uf.find(("node", n))
            if root in place and abs(place[root] - z) > TOL_PLACE * self.size:
                raise self.error(f"the vectors' sums put the fixed point '{n}' on another fixed point")
            place[root] = z
        steady = [v for v in self.vectors.values() if v.cls is None and v.length is None]
        changed = True
        while changed:
            changed = False
            for v in steady:
                t, h = self.ends(v.name)
                for a, b, z in ((t, h, v.canon), (h, t, -v.canon)):
                    if a in place:
                        if b not in place:
                            place[b] = place[a] + z
                            changed = True
                        elif abs(place[b] - place[a] - z) > TOL_PLACE * self.size:
                            raise self.error(f"the constant vector '{v.name}' does not join the places its sums give")
        return place

    def merge_onto_fixed_points(self) -> None:
        place = self.frame_places()
        for root, z in list(place.items()):
            for n, fz in self.fixed.items():
                if abs(z - fz) <= TOL_PLACE * self.size:
                    self.uf.union(("node", n), root)
        self.place = {self.uf.find(k): z for k, z in place.items()}
        for n, z in self.fixed.items():  # a fixed point keeps its own coordinates, not a sum's rounding
            self.place[self.uf.find(("node", n))] = z

    def name_nodes(self) -> None:
        """``{root: name}``: the fixed or named point it is, else ``<vector>.tail``/``.head``."""
        names: dict[_Key, str] = {}
        for key in list(self.uf.up):
            if key[0] == "node":
                root = self.uf.find(key)
                if root not in names or key[1] in self.fixed:
                    names[root] = str(key[1])
        for v in self.vectors.values():
            for end, root in zip(("tail", "head"), self.ends(v.name)):
                names.setdefault(root, f"{v.name}.{end}")
        self.node = names
        self.node_order = {n: i for i, n in enumerate(dict.fromkeys(names[self.uf.find(k)] for k in self.uf.up))}

    # -- bodies -------------------------------------------------------------------------------
    def components(self) -> None:
        for v in self.vectors.values():
            t, h = (self.node[k] for k in self.ends(v.name))
            if t == h and not (v.length is None and v.r == 0.0):
                raise self.error(
                    f"the sums make vector '{v.name}' start and end at one node ({t}): a vector is added "
                    "somewhere it does not lie (used as a free vector in a point's or a contour's sum)"
                )
        by_cls: dict[str | None, list[Vector]] = {}
        for v in self.vectors.values():
            by_cls.setdefault(v.cls, []).append(v)
        by_cls.setdefault(None, [])
        self.comp_of: dict[tuple[str | None, str], Comp] = {}
        self.comps: list[Comp] = []
        for cls, vecs in by_cls.items():
            uf = UnionFind()
            touched: list[str] = []
            for v in vecs:
                t, h = (self.node[k] for k in self.ends(v.name))
                touched += [t, h]
                uf.find(t)
                uf.find(h)
                if v.length is None:
                    uf.union(t, h)
            if cls is None:
                frame = [self.node[k] for k in self.place]
                touched += frame
                for n in frame:
                    uf.union(frame[0], n)
            groups: dict[_Key, Comp] = {}
            for n in dict.fromkeys(touched):
                comp = groups.setdefault(uf.find(n), Comp(cls))
                comp.nodes.append(n)
                self.comp_of[(cls, n)] = comp
            for comp in groups.values():
                self._places(comp, [v for v in vecs if v.length is None])
                comp.is_base = cls is None and any(self.node[k] in comp.nodes for k in self.place)
                self.comps.append(comp)
        for v in self.vectors.values():
            if v.length is not None:
                t, h = (self.node[k] for k in self.ends(v.name))
                a, b = self.comp_of[(v.cls, t)], self.comp_of[(v.cls, h)]
                if a is b:
                    raise self.error(
                        f"the length of vector '{v.name}' varies, but its two ends lie on one rigid body "
                        f"(joined by vectors of constant length whose angle follows the same parameter)"
                    )
                a.slides.append(v.name)
                b.slides.append(v.name)

    def _places(self, comp: Comp, rigid: list[Vector]) -> None:
        if comp.cls is None and any(self.node[k] in comp.nodes for k in self.place):
            comp.pos = {self.node[k]: z for k, z in self.place.items()}
            missing = [n for n in comp.nodes if n not in comp.pos]
            if missing:  # pragma: no cover - frame_places reaches every node a constant vector joins
                raise self.error(f"the frame's nodes {missing} have no place")
            return
        pos = {comp.nodes[0]: _Z}
        changed = True
        while changed:
            changed = False
            for v in rigid:
                t, h = (self.node[k] for k in self.ends(v.name))
                for a, b, z in ((t, h, v.canon), (h, t, -v.canon)):
                    if a in pos and b in comp.nodes:
                        if b not in pos:
                            pos[b] = pos[a] + z
                            changed = True
                        elif abs(pos[b] - pos[a] - z) > TOL_PLACE * self.size:
                            raise self.error(
                                f"the vectors of one rigid body do not close at vector '{v.name}' (a vector used "
                                "as a free vector in a point's or a contour's sum?)"
                            )
        comp.pos = pos

    def rank_and_name(self) -> None:
        taken: set[str] = {BASE_LINK}
        first: dict[tuple[str | None, str], int] = {}
        for v in sorted(self.vectors.values(), key=lambda v: v.order):
            for k in self.ends(v.name):
                first.setdefault((v.cls, self.node[k]), v.order)
        for comp in self.comps:  # the order its first vector comes in the file's sums
            comp.order = min(first.get((comp.cls, n), len(self.vectors)) for n in comp.nodes)
            if comp.is_base:
                comp.name = BASE_LINK
                continue
            if comp.cls is not None:
                comp.rank = self.rank_of.get(comp.cls, 1)
            else:
                comp.rank = min((self.rank_of.get(self.vectors[v].length, 1) for v in comp.slides), default=1)
        ordered = sorted((c for c in self.comps if not c.is_base), key=lambda c: (c.rank, c.order))
        for comp in ordered:
            comp.name = self._unique(self._name(comp), taken)
            taken.add(comp.name)
        if sum(c.is_base for c in self.comps) != 1:
            raise self.error("the scene has no fixed point a vector starts or ends on: the frame holds nothing")

    def _name(self, comp: Comp) -> str:
        """The class's main body (the one holding its owner vector's tail) is ``<contour>_<owner>``
        (the input's: the input joint's name); the far side of a slide ``<main>[_<vector>]_slider``;
        a translating body ``<contour>_<vector>`` after the slide that carries it."""
        cls = comp.cls
        slide = comp.slides[0] if comp.slides else None
        if cls is not None:
            mine = sorted((v for v in self.vectors.values() if v.cls == cls), key=lambda v: v.order)
            owner = cls.rsplit(".", 1)[0]
            if cls == self.inp.unit or owner not in self.vectors:
                owner = mine[0].name
            main = str(self.inp.joint) if cls == self.inp.unit else f"{self.solver_of.get(cls, cls)}_{owner}"
            if self.node[self.uf.find(("tail", owner))] in comp.nodes:
                return main
            if slide is None:
                return f"{main}_part"
            return f"{main}_slider" if slide == owner else f"{main}_{slide}_slider"
        if slide is None:  # pragma: no cover - a constant-angle body off the frame is reached by a slide
            return "translating_body"
        return f"{self.solver_of.get(self.vectors[slide].length or '', self.inp.joint)}_{slide}"

    @staticmethod
    def _unique(name: str, taken: set[str]) -> str:
        out, i = name, 2
        while out in taken:
            out, i = f"{name}_{i}", i + 1
        return out
