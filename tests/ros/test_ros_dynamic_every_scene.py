"""Every shipped scene in dynamic mode with its defaults, as its own process over DDS (issue 32).

Each scene either publishes (``joint_states`` arrive) or is refused with one ``cannot start: …``
line and exit status 1 (a scene without inertia); a publishing node ends on SIGINT — and the
tipper, which falls back onto its closed length and holds there, on SIGTERM too — promptly:
its ticks always end (solver.dynamics._guard), so the spin loop sees the signal. The tipper
with ``phi0:=0`` (a stroke of 0 m, outside [0.74, 1.3] m) is refused at start with the reason,
as ``simulate`` refuses it.
"""

from __future__ import annotations

import signal
import time
from typing import Any

import pytest
from conftest import Client, NodeProcess

import solver

pytestmark = pytest.mark.dds

SCENES = sorted(solver.shipped_scenes().items())
#: Nodes started together (the machine has two cores).
BATCH = 5
#: Seconds for a node to publish or refuse (start-up under load: imports, the compiled instant).
WAIT_S = 60.0
#: The node must end within this after SIGINT / SIGTERM (the issue's target; measured values
#: are printed). EXIT_GRACE_S is what the assertion allows on a loaded machine: the interpreter's
#: own teardown, not a tick, is what is left.
EXIT_TARGET_S = 1.0
EXIT_GRACE_S = 5.0
JOINT_STATE = "sensor_msgs/msg/JointState"


def _ns(index: int) -> str:
    return f"/every{index}"


def _outcome(client: Client, listener: Any, process: NodeProcess, topic: str) -> str:
    def settled() -> bool:
        return process.popen.poll() is not None or len(listener.by_topic[topic]) >= 3

    assert client.spin_until(settled, WAIT_S), f"neither publishes nor refuses within {WAIT_S} s:\n{process.output()}"
    return "published" if process.popen.poll() is None else "refused"


def _stop(process: NodeProcess, sig: int) -> float:
    began = time.monotonic()
    code = process.stop(sig, timeout=30.0)
    seconds = time.monotonic() - began
    assert code == 0, process.output()
    return seconds


@pytest.mark.parametrize("first", range(0, len(SCENES), BATCH))
def test_every_shipped_scene_publishes_or_refuses_in_one_line_and_ends_on_sigint(
    first: int, start_node: Any, client: Client
) -> None:
    batch = SCENES[first:first + BATCH]
    topics = {f"{_ns(first + i)}/joint_states": JOINT_STATE for i in range(len(batch))}
    listener = client.listen(topics)
    processes = [start_node("-r", f"__ns:={_ns(first + i)}", "-p", f"scene:={path}", "-p", "mode:=dynamic")
                 for i, (_, path) in enumerate(batch)]
    report = []
    for i, ((name, _), process) in enumerate(zip(batch, processes)):
        outcome = _outcome(client, listener, process, f"{_ns(first + i)}/joint_states")
        if outcome == "refused":
            assert process.wait() == 1
            lines = [line for line in process.output().splitlines() if line.strip()]
            assert len(lines) == 1 and "cannot start: " in lines[0], process.output()
            report.append(f"{name}: refused — {lines[0].split('cannot start: ', 1)[1][:90]}")
            continue
        seconds = _stop(process, signal.SIGINT)
        report.append(f"{name}: published {len(listener.by_topic[f'{_ns(first + i)}/joint_states'])} "
                      f"joint_states, ended {seconds:.2f} s after SIGINT")
        assert seconds <= EXIT_GRACE_S, process.output()
    print("\n".join(report))


def test_the_tipper_holds_at_its_closed_length_and_ends_on_sigterm(start_node: Any, client: Client) -> None:
    topic = "/every_tipper/joint_states"
    listener = client.listen({topic: JOINT_STATE})
    process = start_node("-r", "__ns:=/every_tipper", "-p", "scene:=tipper", "-p", "mode:=dynamic")
    assert _outcome(client, listener, process, topic) == "published", process.output()
    count = len(listener.by_topic[topic])
    assert client.spin_until(lambda: len(listener.by_topic[topic]) >= count + 50, WAIT_S), process.output()
    seconds = _stop(process, signal.SIGTERM)
    print(f"tipper: ended {seconds:.2f} s after SIGTERM")
    assert seconds <= EXIT_GRACE_S


def test_the_tipper_outside_its_stroke_is_refused_with_the_reason(start_node: Any) -> None:
    process = start_node("-r", "__ns:=/every_tipper0", "-p", "scene:=tipper", "-p", "mode:=dynamic",
                         "-p", "phi0:=0.0")
    assert process.wait(timeout=WAIT_S) == 1
    lines = [line for line in process.output().splitlines() if line.strip()]
    assert len(lines) == 1, process.output()
    assert ("cannot start: tipper, t = 0 s, stroke = 0 m, group 'lift': cannot be assembled at the initial state "
            "(is outside its stroke [0.74, 1.3] m") in lines[0]
