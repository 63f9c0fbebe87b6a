"""The standalone run behind ``linkage-run``: the node's engine on simulated time, no ROS.

Ticks at ``t = k / rate`` (k = 0, 1, …; the first at φ0) are solved in blocks by
:meth:`Engine.frames`; every tick's messages (the node's topics, types and stamps: stamp = t)
go to the MCAP recorder, the arrays to the rerun view at the end. A SIGINT stops the run at the
next tick and both files are finished cleanly.
"""

from __future__ import annotations

import math
import signal
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, TextIO

import numpy as np

from .rundata import RunBuilder, RunData

__all__ = ["RunOptions", "RunResult", "duration_for_cycles", "run_standalone", "summary_lines"]

NS_PER_S = 1_000_000_000
TWO_PI = 2.0 * math.pi
BLOCK = 4096
PROGRESS_MIN_TICKS = 2000
"""Runs shorter than this show no progress bar."""


@dataclass
class RunOptions:
    scene: str  # a scene file or shipped name (a loaded solver.Scene works too)
    duration: float
    rate: float = 100.0
    omega: float | Sequence[float] = TWO_PI
    epsilon: float | Sequence[float] = 0.0
    phi0: float | Sequence[float] = 0.0
    """ω, ε, φ0: one number (for every input), or one per input of ``scene.inputs``."""
    mcap: Path | None = None
    rrd: Path | None = None
    spawn: bool = False
    points: Sequence[str] | None = None
    on_unassemblable: str = "stop"
    frame_id: str = "world"
    namespace: str = "/"
    chunk_interval_s: float = 1.0
    fast: bool = True
    law: Any = None
    """A time law in place of ω, ε, φ0 (``--dynamics``: :mod:`.dynamic_run`'s trajectory law)."""
    energy: Mapping[str, Any] | None = None
    """A dynamic run's energies per tick (``RunData.energy``), for the rerun view."""


@dataclass
class RunResult:
    data: RunData
    ticks: int
    messages: int
    interrupted: bool
    seconds: dict[str, float] = field(default_factory=dict)
    arrow_scales: dict[str, float] = field(default_factory=dict)
    templated: list[str] = field(default_factory=list)
    """Topics serialised from templates (the others were built per tick)."""
    statuses: dict[str, int] = field(default_factory=dict)


def duration_for_cycles(cycles: float, omega: float, epsilon: float, *, span: float = TWO_PI) -> float:
    """Time for the input to turn ``cycles`` turns from rest angle φ0 (|Δφ| = 2π·cycles; an
    actuator's ``span`` is its stroke: |Δs| = span·cycles)."""
    goal = span * cycles
    if epsilon == 0.0:
        if omega == 0.0:
            raise ValueError("with omega = 0 and epsilon = 0 the input never turns; "
                             "give --duration instead of --cycles")
        return goal / abs(omega)
    roots = []
    for target in (goal, -goal):  # ½ε t² + ω t − target = 0
        disc = omega * omega + 2.0 * epsilon * target
        if disc >= 0.0:
            sq = math.sqrt(disc)
            roots += [r for r in ((-omega + sq) / epsilon, (-omega - sq) / epsilon) if r > 0.0]
    return min(roots)


class _Progress:
    def __init__(self, total: int, stream: TextIO, enabled: bool) -> None:
        self.total, self.stream, self.enabled = total, stream, enabled
        self.start = time.monotonic()

    def update(self, done: int) -> None:
        if not self.enabled:
            return
        frac = done / max(self.total, 1)
        bar = "#" * int(30 * frac)
        rate = done / max(time.monotonic() - self.start, 1e-9)
        self.stream.write(f"\r[{bar:<30}] {100 * frac:5.1f}%  {done}/{self.total} ticks  "
                          f"{rate:,.0f} ticks/s")
        self.stream.flush()

    def close(self) -> None:
        if self.enabled:
            self.stream.write("\n")
            self.stream.flush()


class _StopOnSigint:
    """First SIGINT: finish the current tick, then stop; a second one interrupts at once."""

    def __init__(self) -> None:
        self.stop = False
        self._old: Any = None

    def __enter__(self) -> _StopOnSigint:
        try:
            self._old = signal.signal(signal.SIGINT, self._handle)
        except ValueError:  # not the main thread: no handler, Ctrl-C behaves as usual
            self._old = None
        return self

    def _handle(self, signum: int, frame: Any) -> None:
        self.stop = True
        signal.signal(signal.SIGINT, signal.default_int_handler)

    def __exit__(self, *exc: object) -> None:
        if self._old is not None:
            signal.signal(signal.SIGINT, self._old)


def _typestore() -> Any:
    from rosbags.typesys import Stores, get_typestore

    return get_typestore(Stores.ROS2_JAZZY)


def run_standalone(opts: RunOptions, *, progress: TextIO | None = None) -> RunResult:
    """Run, record and view; returns the arrays, counts and timings."""
    from linkage_ros.engine import Engine
    from linkage_ros.messages import MessageBuilder
    from linkage_ros.motion import Motion, Motions
    from linkage_ros.serialize import Serializer
    from linkage_ros.topics import topic_types
    from solver import load_scene

    from .mcap import Recorder
    from .replay import METADATA_NAME, scene_metadata

    if not (math.isfinite(opts.rate) and opts.rate > 0):
        raise ValueError(f"rate must be a finite number > 0, got {opts.rate!r}")
    if not (math.isfinite(opts.duration) and opts.duration >= 0):
        raise ValueError(f"duration must be a finite number >= 0, got {opts.duration!r}")
    clock = time.perf_counter()
    seconds: dict[str, float] = {}
    scene: Any = opts.scene if hasattr(opts.scene, "with_outputs") else load_scene(opts.scene)
    inputs = tuple(getattr(scene, "inputs", (scene.input_joint,)))
    motion: Motion | Motions
    if opts.law is not None:  # a dynamic run (.dynamic_run): the simulated trajectory
        motion = opts.law
    elif len(inputs) > 1:  # several inputs (docs/inputs.md): one law per input
        motion = Motions.of(len(inputs), phi0=opts.phi0, omega=opts.omega, epsilon=opts.epsilon,
                            units=getattr(scene, "input_units", None))
    else:
        motion = Motion(phi0=_single(opts.phi0, "phi0"), omega=_single(opts.omega, "omega"),
                        epsilon=_single(opts.epsilon, "epsilon"), unit=getattr(scene, "input_units", ("rad",))[0])
    engine = Engine(scene, motion, points=opts.points, on_unassemblable=opts.on_unassemblable)
    n = int(math.floor(opts.duration * opts.rate * (1 + 1e-12))) + 1
    times = np.arange(n, dtype=np.float64) / opts.rate
    stamps = np.rint(times * NS_PER_S).astype(np.int64)
    ts = _typestore()
    builder = MessageBuilder(engine, ts.types, frame_id=opts.frame_id)
    topics = topic_types(engine)
    recorder = None
    if opts.mcap is not None:
        recorder = Recorder(
            opts.mcap, topics, typestore=ts, namespace=opts.namespace,
            chunk_interval_s=opts.chunk_interval_s,
            metadata={METADATA_NAME: scene_metadata(
                engine, frame_id=opts.frame_id, rate_hz=opts.rate, omega=opts.omega,
                epsilon=opts.epsilon, phi0=opts.phi0)})
    serializer = Serializer(builder, ts.serialize_cdr) if recorder else None
    rb = RunBuilder(engine, n)
    statuses: dict[str, int] = {}
    bar = _Progress(n, progress or sys.stderr,
                    enabled=progress is not None and n >= PROGRESS_MIN_TICKS)
    interrupted = False
    frames = engine.frames(times)
    try:
        with _StopOnSigint() as sigint:
            for start in range(0, n, BLOCK):
                block_frames = []
                for _ in range(min(BLOCK, n - start)):
                    if sigint.stop:
                        break
                    frame = next(frames)
                    rb.add(frame)
                    block_frames.append(frame)
                    statuses[frame.status] = statuses.get(frame.status, 0) + 1
                stop = start + len(block_frames)
                if recorder is not None and serializer is not None and block_frames:
                    _record_block(recorder, serializer, block_frames, stamps[start:stop].tolist(),
                                  templates=opts.fast)
                bar.update(rb.k)
                if sigint.stop:
                    interrupted = True
                    break
    finally:
        bar.close()
        if recorder is not None:
            recorder.close()
    seconds["solve+mcap"] = time.perf_counter() - clock
    data = rb.build()
    if opts.energy:
        data.energy = {key: np.asarray(v, dtype=np.float64)[:data.n] for key, v in opts.energy.items()}
    scales: dict[str, float] = {}
    if opts.rrd is not None or opts.spawn:
        clock2 = time.perf_counter()
        from .rerun import write_rrd

        scales = write_rrd(data, opts.rrd, spawn=opts.spawn)
        seconds["rerun"] = time.perf_counter() - clock2
    seconds["total"] = time.perf_counter() - clock
    return RunResult(data, rb.k, recorder.message_count if recorder else 0, interrupted,
                     seconds, scales, serializer.template_topics if serializer and opts.fast else [],
                     statuses)


def _single(value: float | Sequence[float], label: str) -> float:
    """A single-input law's value: a number, or a sequence of one."""
    if isinstance(value, (int, float)):
        return float(value)
    values = [float(v) for v in value]
    if len(values) != 1:
        raise ValueError(f"{label} needs 1 value for a scene with one input, got {len(values)}")
    return values[0]


def _record_block(recorder: Any, serializer: Any, frames: list[Any], stamps: list[int], *,
                  templates: bool) -> None:
    """Every topic of a block of ticks into the recording: the byte templates of
    :mod:`linkage_ros.serialize`, one numpy pass per topic for the block (checked against the
    builder on the run's first frame), and the ordinary path for the diagnostics and the path
    markers (or, without ``templates``, for everything)."""
    builder = serializer.builder
    types = list(serializer.types)
    rendered: dict[str, list[bytes]] = {}
    if templates:
        if not serializer.verified:
            serializer.verify(frames[0], stamps[0])
        rows = np.array([serializer.numbers(f, s) for f, s in zip(frames, stamps)], dtype=np.float64)
        rendered = {t: serializer.render_block(t, rows) for t in serializer.template_topics}
    for i, (frame, stamp) in enumerate(zip(frames, stamps)):
        paths = builder.wants_paths(frame.t)
        ordinary = [t for t in types if t not in rendered or (paths and t == "markers")]
        built = dict(serializer.generic(frame, stamp, ordinary, paths=paths))
        recorder.write_serialized(stamp, [(t, built[t] if t in built else rendered[t][i]) for t in types])


def summary_lines(
    data: RunData,
    outputs: Sequence[str],
    output_joints: Sequence[str],
    units: Mapping[str, str] | None = None,
    *,
    descriptions: Mapping[str, str] | None = None,
    inputs: Sequence[str] = (),
    sections: Sequence[Any] = (),
) -> list[str]:
    """The run's summary in linkage-solve's words (:mod:`solver.summary`): per output point its
    position ranges and the largest speed and acceleration with the t and φ where they occur (or
    "constant"), read off the ticks (said so); per output joint its motion (a "full turn" for a
    joint that turns a revolution), velocity and acceleration. ``units``: each joint's "rad" or
    "m" (default rad); ``descriptions``: the scene's one-line descriptions of points and joints;
    ``inputs``: the scene's input joints (one line each: their law is the run's heading);
    ``sections``: more :data:`solver.summary.Section` functions, appended."""
    from solver.summary import Output, Sweep
    from solver.summary import summary_lines as lines_of

    if data.n == 0:
        return ["  no ticks"]
    desc = descriptions or {}
    points = [
        Output(p, data.positions[p], data.velocities[p], data.accelerations[p], description=desc.get(p, ""))
        for p in outputs
        if p in data.positions and p in data.velocities
    ]
    joints = [
        Output(j, *data.joints[j], unit=(units or {}).get(j, "rad"), description=desc.get(j, ""))
        for j in output_joints
        if j in data.joints
    ]
    sweep = Sweep(phi=data.phi, points=points, joints=joints, t=data.t, inputs=tuple(inputs),
                  units=tuple((units or {}).get(q, "rad") for q in inputs))
    return lines_of(sweep, sections=sections)
