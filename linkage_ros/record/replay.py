"""From the messages of a recorded MCAP file back to a :class:`~linkage_ros.record.rundata.RunData`
(no solving): the replay behind ``linkage-view``.

What each array comes from:

* ticks: the stamps of ``joint_kinematics`` (every topic of a tick carries the same stamp); a
  tick that lacks one of the needed topics (the last tick of a file cut by a crash) is dropped;
  ``t`` is run time, s from the first tick (``start_ns``: that tick's stamp — for a live node a
  wall-clock time);
* φ, ω, ε: ``diagnostics`` key values ``phi``, ``omega``, ``epsilon`` (written with ``repr``,
  so exact); without diagnostics, the input joint of ``joint_kinematics``. A scene with several
  inputs (docs/inputs.md) has the keys ``phi/<Q>``, ``omega/<Q>``, ``epsilon/<Q>`` per input Q
  and gives (N, k) arrays (the inputs from the metadata, else from those keys);
* joints: ``joint_kinematics`` (positions, velocities, accelerations);
* published points: ``points/<P>/{position,velocity,acceleration}``;
* the drawing: ``markers`` — ns ``joints`` (SPHERE_LIST of the moving points), ``fixed_pivots``,
  ``links`` (LINE_LIST) and ``paths`` (LINE_STRIP per published point, sent periodically).

Point and link names come from the ``linkage_ros`` metadata record that our recorders write
(:func:`scene_metadata`). A file without it (e.g. ``ros2 bag record`` of the live node) still
replays: published points are recognised by their positions, the other points get generic
names, and each link segment is drawn on its own.
"""

from __future__ import annotations

import json
import os
from collections import defaultdict
from collections.abc import Callable, Mapping
from typing import Any

import numpy as np

from ..forces import TOPIC_PREFIX
from .cdr import extract
from .forces import forces_from_mcap, forces_metadata
from .friction import friction_from_mcap
from .mcap_read import McapContents, read_mcap
from .rundata import RunData, joint_units

__all__ = ["METADATA_NAME", "scene_metadata", "run_data_from_mcap", "stamp_text"]

METADATA_NAME = "linkage_ros"
NS_PER_S = 1_000_000_000
#: Stamps from this many ns on are wall-clock times (after 2001-09-09), shown as dates.
WALL_CLOCK_NS = 10**18


def stamp_text(ns: int) -> str:
    """A message stamp for people: a UTC date and time for a wall-clock stamp (a live node's),
    else the (simulated) clock's seconds."""
    if ns >= WALL_CLOCK_NS:
        from datetime import datetime, timezone

        when = datetime.fromtimestamp(ns // NS_PER_S, tz=timezone.utc)
        return f"{when:%Y-%m-%d %H:%M:%S}.{ns % NS_PER_S // 1_000_000:03d} UTC"
    return f"clock time {ns / NS_PER_S:g} s"
POINT_KINDS = ("position", "velocity", "acceleration")


def scene_metadata(engine: Any, *, frame_id: str = "world", topics: Mapping[str, str] | None = None,
                   **extra: Any) -> dict[str, str]:
    """The ``linkage_ros`` metadata record: how to name and join what the markers draw, and
    (``topics``: relative name → name on the wire) where remapped topics were recorded."""
    scene = engine.scene
    fixed = {k: [float(x) for x in np.asarray(v).reshape(-1)]
             for k, v in scene.fixed_points.items()}
    record = {
        "scene": str(scene.name),
        "dim": str(int(scene.dim)),
        "frame_id": frame_id,
        "input_joint": str(getattr(scene, "input_joint", "")),
        "inputs": json.dumps(list(getattr(scene, "inputs", ()))),
        "moving_points": json.dumps([p for p in engine.point_names if p not in fixed]),
        "published_points": json.dumps(list(engine.published_points)),
        "fixed_points": json.dumps(fixed),
        "links": json.dumps([[str(link.name), list(link.points)] for link in scene.links]),
        "cylinders": json.dumps([[str(g.name), str(g.base), str(g.point), float(g.stroke[0])]
                                 for g in scene.ordered if getattr(g, "kind", "") == "actuator"]),
        "joints": json.dumps(list(engine.joint_names)),
        "joint_units": json.dumps(joint_units(scene, engine.joint_names)),
    }
    if topics:
        record["topics"] = json.dumps(dict(topics))
    record.update(forces_metadata(engine))  # scenes with forces: the loads and effort units
    record.update({k: str(v) for k, v in extra.items()})
    return record


def _typestore() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_JAZZY)


def _suffix(contents: McapContents, meta: Mapping[str, str]) -> dict[str, str]:
    """Relative topic name (``joint_states``, ``points/B/position``) → absolute, for one node:
    the names the metadata record gives (remapped topics), else found by their endings."""
    recorded = contents.topics()
    out = {rel: name for rel, name in json.loads(meta.get("topics", "{}")).items() if name in recorded}
    for name in recorded:
        for rel in ("joint_kinematics", "joint_states", "markers", "diagnostics", "friction_power"):
            if name.endswith("/" + rel):
                out.setdefault(rel, name)
        parts = name.rsplit("/", 3)
        if len(parts) == 4 and parts[1] == "points" and parts[3] in POINT_KINDS:
            out.setdefault(f"points/{parts[2]}/{parts[3]}", name)
        if len(parts) >= 3 and parts[-2] in TOPIC_PREFIX.values():  # scenes with forces
            out.setdefault(f"{parts[-2]}/{parts[-1]}", name)
    return out


def run_data_from_mcap(path: str | os.PathLike[str],
                       typestore: Any = None) -> tuple[RunData, McapContents]:
    """Decode a recorded run (finished or cut short) into arrays for the rerun view."""
    ts = typestore if typestore is not None else _typestore()
    raw: dict[str, tuple[list[int], list[bytes]]] = defaultdict(lambda: ([], []))

    def keep(channel: Any, message: Any) -> None:
        stamps, datas = raw[channel.topic]
        stamps.append(message.log_time)
        datas.append(message.data)

    contents = read_mcap(path, on_message=keep)
    meta: dict[str, str] = {}
    for m in contents.metadata:
        if m.name == METADATA_NAME:
            meta = dict(m.metadata)
    topics = _suffix(contents, meta)
    if "joint_kinematics" not in topics:
        raise ValueError(f"{path}: no joint_kinematics topic; is this a linkage_ros recording?")
    types = contents.topics()
    kind_of = {rel: (raw[topics[rel]], types[topics[rel]]) for rel in topics}

    published = [k.split("/")[1] for k in topics if k.startswith("points/") and k.endswith("/position")]
    if "published_points" in meta:
        published = [p for p in json.loads(meta["published_points"]) if p in published]
    needed = ["joint_kinematics", *(f"points/{p}/{k}" for p in published for k in POINT_KINDS
                                    if f"points/{p}/{k}" in topics)]
    needed += [t for t in ("markers",) if t in topics]
    stamps = _common_stamps([kind_of[rel][0][0] for rel in needed])
    n = stamps.size
    start_ns = int(stamps[0]) if n else 0
    t = (stamps - start_ns) / NS_PER_S  # run time: a live node's stamps are wall-clock (epoch) times

    def rows(rel: str) -> list[bytes]:
        (st, datas), _ = kind_of[rel]
        index = {s: i for i, s in zip(range(len(st) - 1, -1, -1), reversed(st))}  # first wins
        return [datas[index[s]] for s in stamps.tolist()]

    kin_rows = rows("joint_kinematics")
    first = ts.deserialize_cdr(kin_rows[0], kind_of["joint_kinematics"][1]) if n else None
    joint_names = list(first.joint_names) if first is not None else []
    kinds = ("positions", "velocities", "accelerations")
    jk = extract(ts, kind_of["joint_kinematics"][1], kin_rows,
                 lambda m: [("points", 0, k, i) for k in kinds for i in range(len(m.joint_names))])
    jk = jk.reshape(n, 3, len(joint_names)) if n else np.zeros((0, 3, len(joint_names)))
    joints = {j: (jk[:, 0, i].copy(), jk[:, 1, i].copy(), jk[:, 2, i].copy())
              for i, j in enumerate(joint_names)}

    dim = int(meta.get("dim", "0")) or 0
    vectors: dict[tuple[str, str], np.ndarray] = {}
    for p in published:
        for kind in POINT_KINDS:
            rel = f"points/{p}/{kind}"
            if rel in topics:
                field = "point" if kind == "position" else "vector"
                vectors[p, kind] = extract(ts, kind_of[rel][1], rows(rel), _xyz_paths(field))
    markers = rows("markers") if "markers" in topics else []
    marker_type = kind_of["markers"][1] if markers else ""
    if not dim:
        planar = all(not np.any(v[:, 2]) for v in vectors.values())
        dim = 2 if planar else 3
    positions = {p: vectors[p, "position"][:, :dim] for p in published if (p, "position") in vectors}
    velocities = {p: vectors[p, "velocity"][:, :dim] for p in published
                  if (p, "velocity") in vectors and (p, "acceleration") in vectors}
    accelerations = {p: vectors[p, "acceleration"][:, :dim] for p in velocities}

    fixed: dict[str, np.ndarray] = {}
    links: list[tuple[str, tuple[str, ...]]] = []
    paths: dict[str, np.ndarray] = {}
    if markers:
        fixed, links, paths = _drawing(ts, marker_type, markers, kind_of["markers"][0][1], meta,
                                       positions, published, dim)

    input_joint = meta.get("input_joint", "")
    inputs = [str(q) for q in json.loads(meta.get("inputs", "[]"))]
    diags = rows("diagnostics") if "diagnostics" in topics and _has_all(kind_of["diagnostics"][0][0], stamps) else []
    diag_type = kind_of["diagnostics"][1] if diags else ""
    if not inputs and diags:  # a recording without our metadata: the inputs named by the keys
        inputs = _diagnostic_inputs(ts, diag_type, diags[0])
    if len(inputs) > 1:
        phi, omega, eps = _inputs(ts, diag_type, diags, inputs, joints)
    else:
        phi, omega, eps = _input(ts, diag_type, diags, joints.get(input_joint))
    friction = {}
    if "friction_power" in topics and _has_all(kind_of["friction_power"][0][0], stamps):
        friction = friction_from_mcap(ts, kind_of["friction_power"][1], rows("friction_power"))
    note = ""
    if not contents.complete:
        note = (f"Replayed from a file cut short (no footer): {n} complete ticks read, "
                f"{contents.size - contents.valid_bytes} trailing bytes ignored.")
    data = RunData(
        scene=meta.get("scene", os.path.splitext(os.path.basename(os.fspath(path)))[0]),
        dim=dim, t=t, phi=phi, omega=omega, epsilon=eps, positions=positions,
        velocities=velocities, accelerations=accelerations, joints=joints, links=links,
        fixed=fixed, paths=paths, input_joint=input_joint, note=note,
        inputs=tuple(inputs) if len(inputs) > 1 else (), start_ns=start_ns,
        joint_units={str(j): str(u) for j, u in json.loads(meta.get("joint_units", "{}")).items()},
        cylinders=[(str(n), str(a), str(c), float(s)) for n, a, c, s in json.loads(meta.get("cylinders", "[]"))],
        friction=friction,
        **forces_from_mcap(ts, meta, topics, rows, types, (kind_of["joint_kinematics"][1], kin_rows, joint_names)))
    return data, contents


def _xyz_paths(field: str) -> Callable[[Any], list[tuple[str, str]]]:
    return lambda _msg: [(field, "x"), (field, "y"), (field, "z")]


def _common_stamps(series: list[list[int]]) -> np.ndarray:
    """Stamps present in every topic (ticks a cut file has whole), ascending."""
    common = np.unique(np.asarray(series[0], dtype=np.int64))
    for st in series[1:]:
        common = np.intersect1d(common, np.asarray(st, dtype=np.int64), assume_unique=False)
    return common


def _has_all(stamps: list[int], wanted: np.ndarray) -> bool:
    return bool(np.isin(wanted, np.asarray(stamps, dtype=np.int64)).all())


def _xyz(points: list[Any], dim: int) -> np.ndarray:
    arr = np.array([(p.x, p.y, p.z) for p in points], dtype=np.float64).reshape(-1, 3)
    return arr[:, :dim]


def _ns_index(msg: Any, ns: str) -> list[int]:
    return [i for i, m in enumerate(msg.markers) if m.ns == ns]


def _marker_points(ts: Any, typename: str, rows: list[bytes], ns: str, dim: int) -> np.ndarray:
    """(N, count, dim) points of the markers of namespace ``ns`` at every tick."""
    def select(m: Any) -> list[tuple[Any, ...]]:
        return [("markers", j, "points", i, c) for j in _ns_index(m, ns)
                for i in range(len(m.markers[j].points)) for c in "xyz"]

    flat = extract(ts, typename, rows, select)
    return flat.reshape(len(rows), -1, 3)[:, :, :dim]


def _drawing(ts: Any, typename: str, rows: list[bytes], every: list[bytes],
             meta: Mapping[str, str], positions: dict[str, np.ndarray], published: list[str],
             dim: int) -> tuple[dict[str, np.ndarray], list[tuple[str, tuple[str, ...]]],
                                dict[str, np.ndarray]]:
    """Fixed pivots, links and paths from the markers; fills ``positions`` of moving points."""
    n = len(rows)
    first = ts.deserialize_cdr(rows[0], typename)
    fixed_pts = [p for j in _ns_index(first, "fixed_pivots") for p in first.markers[j].points]
    fixed_arr = _xyz(fixed_pts, dim)
    fixed_names = list(json.loads(meta["fixed_points"])) if "fixed_points" in meta else []
    if len(fixed_names) != len(fixed_pts):
        fixed_names = [f"pivot_{i}" for i in range(len(fixed_pts))]
    fixed = {name: fixed_arr[i] for i, name in enumerate(fixed_names)}

    joint_series = _marker_points(ts, typename, rows, "joints", dim)
    count = joint_series.shape[1]
    moving = json.loads(meta["moving_points"]) if "moving_points" in meta else []
    if len(moving) != count:
        moving = []
        for i in range(count):
            match = [p for p, arr in positions.items() if np.array_equal(arr, joint_series[:, i])]
            moving.append(match[0] if match else f"joint_{i}")
    for i, name in enumerate(moving):
        positions.setdefault(name, np.ascontiguousarray(joint_series[:, i]))

    links: list[tuple[str, tuple[str, ...]]] = []
    if "links" in meta:
        known = set(positions) | set(fixed)
        links = [(str(name), tuple(pts)) for name, pts in json.loads(meta["links"])
                 if all(p in known for p in pts)]
    else:
        segs = _marker_points(ts, typename, rows, "links", dim)  # (N, 2 * segments, dim)
        series = {**positions, **{k: np.broadcast_to(v, (n, dim)) for k, v in fixed.items()}}
        for j in range(segs.shape[1] // 2):
            ends = []
            for end in (segs[:, 2 * j], segs[:, 2 * j + 1]):
                match = [p for p, arr in series.items() if np.array_equal(arr, end)]
                ends.append(match[0] if match else "")
            if all(ends):
                links.append((f"segment_{j}", tuple(ends)))

    paths: dict[str, np.ndarray] = {}
    seen: set[int] = set()
    for data in every:  # the first markers message that carries the paths (one decode per size)
        if len(data) in seen:
            continue
        seen.add(len(data))
        msg = ts.deserialize_cdr(data, typename)
        strips = _ns_index(msg, "paths")
        if strips:
            for j in strips:
                m = msg.markers[j]
                if 0 <= m.id < len(published):
                    paths[published[m.id]] = _xyz(list(m.points), dim)
            break
    return fixed, links, paths


def _input(ts: Any, typename: str, diags: list[bytes],
           input_joint: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """φ, ω, ε from the diagnostics key values, else from the input joint."""
    if diags:
        out = np.empty((3, len(diags)))
        for i, data in enumerate(diags):
            msg = ts.deserialize_cdr(data, typename)
            values = {kv.key: kv.value for st in msg.status for kv in st.values}
            out[:, i] = [float(values.get(k, "nan")) for k in ("phi", "omega", "epsilon")]
        if np.isfinite(out).all():
            return out[0], out[1], out[2]
    if input_joint is not None:
        p, v, a = (np.array(x, dtype=float) for x in input_joint)
        return p, v, a
    raise ValueError("neither diagnostics (phi, omega, epsilon) nor the input joint was recorded")


def _diagnostic_inputs(ts: Any, typename: str, data: bytes) -> list[str]:
    """The inputs named by a several-input scene's diagnostics keys ``phi/<Q>`` (in key order)."""
    msg = ts.deserialize_cdr(data, typename)
    return [kv.key.split("/", 1)[1] for st in msg.status for kv in st.values if kv.key.startswith("phi/")]


def _inputs(ts: Any, typename: str, diags: list[bytes], inputs: list[str],
            joints: Mapping[str, Any]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(N, k) φ, ω, ε of a several-input scene from the keys ``phi/<Q>``, ``omega/<Q>``,
    ``epsilon/<Q>``, else from the input joints of ``joint_kinematics``."""
    keys = [f"{kind}/{q}" for kind in ("phi", "omega", "epsilon") for q in inputs]
    k = len(inputs)
    if diags:
        out = np.empty((len(diags), 3 * k))
        for i, data in enumerate(diags):
            msg = ts.deserialize_cdr(data, typename)
            values = {kv.key: kv.value for st in msg.status for kv in st.values}
            out[i] = [float(values.get(key, "nan")) for key in keys]
        if np.isfinite(out).all():
            return out[:, :k].copy(), out[:, k: 2 * k].copy(), out[:, 2 * k:].copy()
    if all(q in joints for q in inputs):
        p, v, a = (np.stack([np.asarray(joints[q][i], dtype=float) for q in inputs], axis=1) for i in range(3))
        return p, v, a
    raise ValueError(f"neither diagnostics ({', '.join(keys[:: k])}, … per input) nor the input joints "
                     f"({', '.join(inputs)}) were recorded")
