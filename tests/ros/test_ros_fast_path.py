"""One serialiser, three ways to fill it (linkage_ros.serialize, linkage_ros.instant): the node's
fast path (one flat instant, one pack per topic), a Frame, and a whole-run block give the bytes
of the message builder + rosbags' serialiser, topic for topic, on one-input, several-input and
force scenes."""

from __future__ import annotations

import struct
from typing import Any

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from rosbags.typesys import Stores, get_typestore

from linkage_ros.engine import Engine
from linkage_ros.messages import DIAGNOSTICS, MessageBuilder
from linkage_ros.motion import Motion, Motions
from linkage_ros.runtime import Runtime
from linkage_ros.serialize import Serializer, cdr_bytes

STORE = get_typestore(Stores.ROS2_JAZZY)
NS = 1_000_000_000
T0 = 1_700_000_000 * NS
#: one input, several inputs, forces (efforts on joint_states, pin and slide loads, arrows), friction
#: (friction_power; the scalar flat solve: a scene with friction is not compiled)
SCENES = ["four_bar", "five_bar", "harvester_finger", "four_bar_loaded", "slider_crank", "four_bar_loaded_friction"]


def _engine(scene: str) -> Engine:
    if scene == "five_bar":
        return Engine(scene, Motions.of(2, phi0=(1.7, 1.3), omega=(1.0, -2.0),  # type: ignore[arg-type]
                                        epsilon=(0.5, 0.0)))
    return Engine(scene, Motion(phi0=0.2, omega=2.0, epsilon=0.3))


def _ordinary(builder: MessageBuilder, frame: Any, stamp: int) -> list[tuple[str, bytes]]:
    types = dict(builder.topics)
    return [(t, cdr_bytes(STORE.serialize_cdr, m, types[t]))
            for t, m in builder.build(frame, stamp, include_paths=False) if t != DIAGNOSTICS]


@pytest.mark.parametrize("scene", SCENES)
def test_frames_and_blocks_give_the_builders_bytes(scene: str) -> None:
    engine = _engine(scene)
    serializer = Serializer(MessageBuilder(engine, STORE.types), STORE.serialize_cdr)
    frames = [engine.frame(0.013 * k) for k in range(6)]
    stamps = [T0 + 13_000_000 * k + 7 for k in range(6)]
    assert serializer.verify(frames[0], stamps[0]) == []
    expected = [_ordinary(MessageBuilder(engine, STORE.types), f, s) for f, s in zip(frames, stamps)]
    for frame, stamp, want in zip(frames, stamps, expected):
        assert serializer.render(frame, stamp, diagnostics=False) == want
    rows = np.array([serializer.numbers(f, s) for f, s in zip(frames, stamps)], dtype=np.float64)
    for topic in serializer.template_topics:
        assert serializer.render_block(topic, rows) == [dict(w)[topic] for w in expected], topic


@pytest.mark.parametrize("scene", SCENES)
def test_the_fast_path_sends_the_frame_paths_bytes_and_runs_on_ordinary_ticks(scene: str) -> None:
    values: dict[str, Any] = {"scene": scene, "rate_hz": 1000.0, "omega": 2.0, "epsilon": 0.3}
    fast, frames = Runtime(values, STORE.types), Runtime(values, STORE.types)
    frames._fast = lambda *args: None  # type: ignore[method-assign]  # the Frame path only
    taken = 0
    for k in range(1500):  # 1.5 s: path markers and diagnostics twice, by the Frame path
        stamp = T0 + k * NS // 1000
        got = fast.tick(stamp)
        assert got == frames.tick(stamp), k
        taken += fast._last_frame is fast._fast_path
    path = fast._fast_path
    assert path is not None and path.enabled
    # the generated tick ran; a scene with friction takes the scalar flat solve (no generated tick)
    assert (path._emit is None) == scene.endswith("_friction")
    assert taken >= 1490  # all but the first ticks and those that carry paths or diagnostics
    last = fast.last_frame  # solved again on demand: the frame the bytes came from
    assert last is not None and frames.last_frame is not None
    assert last.phi == frames.last_frame.phi and last.points == frames.last_frame.points


def test_topic_mode_answers_take_the_fast_path_with_the_relays_bytes() -> None:
    values = {"scene": "four_bar", "input_source": "topic"}
    fast, frames = Runtime(values, STORE.types), Runtime(values, STORE.types)
    frames._fast = lambda *args: None  # type: ignore[method-assign]
    taken = 0
    for k in range(200):
        args = (["crank"], [0.3 + 0.01 * k], [1.5], T0 + k * 2_000_000)
        assert fast.answer(*args) == frames.answer(*args), k
        taken += fast._last_frame is fast._fast_path
    assert taken >= 195
    # unassemblable and dropped input still take the relay's own answers: a dropped message gets
    # diagnostics (WARN) only, and not again within a second of stamps
    assert [topic for topic, _ in fast.answer(["crank"], [float("nan")], [], T0 + NS)] == ["diagnostics"]
    assert fast.take_input_warnings() and not fast.answer(["other"], [0.1], [], T0 + NS + 1_000_000)


def test_a_fast_path_whose_bytes_differ_switches_itself_off() -> None:
    runtime = Runtime({"scene": "four_bar", "rate_hz": 1000.0}, STORE.types)
    runtime.tick(T0)
    path = runtime._fast_path or _path(runtime)
    solve = path.solve
    path.solve = lambda *a: tuple(x + 1e-9 for x in solve(*a) or ())  # type: ignore[method-assign]
    expected = Runtime({"scene": "four_bar", "rate_hz": 1000.0}, STORE.types)
    expected._fast = lambda *args: None  # type: ignore[method-assign]
    expected.tick(T0)
    for k in range(1, 5):
        assert runtime.tick(T0 + k * NS // 1000) == expected.tick(T0 + k * NS // 1000)
    assert not path.enabled


def _path(runtime: Runtime) -> Any:
    from linkage_ros.instant import FastPath

    runtime._fast_path = FastPath(runtime.engine, runtime.builder, runtime.wire)
    return runtime._fast_path


@pytest.mark.parametrize("scene", ["four_bar", "harvester_finger", "slider_crank", "five_bar", "spherical_converter"])
def test_the_traced_tree_joints_are_the_tree_evaluations_bits(scene: str) -> None:
    from linkage_ros.instant import compiled_tree

    runtime = Runtime({"scene": scene, "rate_hz": 1000.0, "omega": 2.0, "epsilon": 0.3}, STORE.types)
    runtime.tick(T0)
    path = runtime._fast_path or _path(runtime)
    engine = runtime.engine
    function = None
    compared = 0
    for k in range(40):  # over most of a turn at ω = 2
        values = path.values(*engine.motion.state(0.07 * k), T0)
        if values is None:  # an instant the compiled code hands back (the Frame path's)
            continue
        compared += 1
        prefix = values[: len(values) - len(runtime.builder.tree_joint_names) * 2]
        function = function or compiled_tree(engine.scene, path.order, prefix)
        assert function is not None
        frame = engine.frame(0.07 * k)
        tree = runtime.builder.tree_states(frame)
        assert tree is not None
        assert function(prefix) == (*tree.position, *tree.velocity), k
    assert compared >= 30


def _bits(f: Any, x: tuple[float, ...]) -> bytes | str:
    """The bytes of ``f(x)`` (signed zeros and NaNs told apart), or the error it raised."""
    try:
        out = f(x)
    except ArithmeticError as exc:
        return type(exc).__name__
    return struct.pack(f"<{len(out)}d", *out)


_WIGGLE = st.sampled_from([0.0, -0.0, 1.0, -1.0, 0.5, -2.0, 1e-300, -1e-300, 3.0, 1e-9])


@pytest.mark.parametrize("scene", ["harvester_finger", "slider_crank", "five_bar", "spherical_converter"])
def test_the_simplified_tree_code_gives_the_recorded_codes_bits_at_any_finite_input(scene: str) -> None:
    """Fewer complex numbers and temporaries (linkage_ros._derived: ``_split``, ``_inline``), the
    same operations: the same bits as the lines as recorded, signed zeros, coincident points
    (a division by zero) and tiny numbers included."""
    from linkage_ros._derived import function_of, tree_code

    runtime = Runtime({"scene": scene, "rate_hz": 1000.0, "omega": 2.0, "epsilon": 0.3}, STORE.types)
    runtime.tick(T0)
    path = runtime._fast_path or _path(runtime)
    sample = next(v for k in range(40) if (v := path.values(*runtime.engine.motion.state(0.07 * k), T0)))
    prefix = sample[: len(sample) - len(runtime.builder.tree_joint_names) * 2]
    order = path.order[: len(prefix)]
    recorded = function_of(tree_code(runtime.engine.scene, order, prefix, simplify=False), "recorded")
    simplified = function_of(tree_code(runtime.engine.scene, order, prefix), "simplified")
    assert recorded is not None and simplified is not None

    @settings(max_examples=150, deadline=None)
    @given(st.lists(st.tuples(st.integers(0, len(prefix) - 1), _WIGGLE), max_size=12))
    def check(changes: list[tuple[int, float]]) -> None:
        x = list(prefix)
        for i, value in changes:
            x[i] = value if i % 3 else x[i] * value
        assert _bits(simplified, tuple(x)) == _bits(recorded, tuple(x))

    check()


@pytest.mark.parametrize("scene", ["harvester_finger", "four_bar_loaded", "engine"])
def test_the_traced_load_arrow_tips_are_the_builders_bits(scene: str) -> None:
    runtime = Runtime({"scene": scene, "rate_hz": 1000.0, "omega": 2.0, "epsilon": 0.3}, STORE.types)
    runtime.tick(T0)
    path = runtime._fast_path or _path(runtime)
    engine = runtime.engine
    compared = 0
    for k in range(40):
        values = path.values(*engine.motion.state(0.07 * k), T0)
        if values is None:
            continue
        assert path._tips_function is not None  # traced on the first instant
        tips = runtime.builder.load_tips(engine.frame(0.07 * k))
        assert values[len(values) - len(tips):] == tips, k
        compared += 1
    assert compared >= 30


@pytest.mark.parametrize("scene", ["four_bar", "five_bar", "harvester_finger", "hard/double_rocker"])
def test_the_generated_tick_gives_the_values_and_packers_bytes_or_hands_back_where_they_do(scene: str) -> None:
    from linkage_ros.instant import emit_source

    runtime = Runtime({"scene": scene, "rate_hz": 1000.0}, STORE.types)
    for k in range(3):
        runtime.tick(T0 + k * NS // 1000)
    path = runtime._fast_path
    assert path is not None and path._emit is not None and path._shape is not None and path._sample is not None
    packer = runtime.wire.packer(path.order)
    assert packer is not None
    source, _ = emit_source(path, path._shape, path._sample, packer) or ("", {})
    assert source.startswith("def emit(phi, w, e, stamp_ns):") and "_unit.core(" in source
    if scene == "five_bar":
        samples = [((1.7 + 0.01 * k, 1.3 - 0.02 * k), (1.0, -2.0), (0.5, 0.0)) for k in range(60)]
    elif scene == "hard/double_rocker":  # up to its toggle, where the guards hand the instant back
        toggle = np.arccos(-0.40625)
        samples = [(float(toggle - 0.1 * 10.0 ** (-k / 4)), 1.0, 0.0) for k in range(60)]
    else:
        samples = [(0.1 * k, 2.0, 0.3) for k in range(70)]
    handed_back = 0
    for k, (phi, omega, epsilon) in enumerate(samples):
        stamp = T0 + 7 * k
        path.solve(phi, omega, epsilon)  # a miss of the compiled code traces that branch: both see it
        values = path.values(phi, omega, epsilon, stamp)
        got = path._emit(phi, omega, epsilon, stamp)
        handed_back += got is None
        assert got == (None if values is None else packer(values)), k
    if scene == "hard/double_rocker":
        assert 0 < handed_back < len(samples)
    else:
        assert handed_back == 0
