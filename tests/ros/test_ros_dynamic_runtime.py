"""The node's dynamic mode without ROS (issue 22): :class:`linkage_ros.runtime.Runtime` with
``mode: dynamic`` and the laws of :mod:`linkage_ros.dynamic` — the parameters and their checks,
the ticks against an offline simulation, the motor, effort commands and their timeout, a toggle
held with one event, a change of drive that keeps the state."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import pytest

import solver
from linkage_ros.dynamic import DynamicMotion, DynamicMotions
from linkage_ros.parameters import validate_parameter
from linkage_ros.runtime import Runtime

NS = 1_000_000_000
START_NS = 5 * NS
RATE = 1000.0
MOTOR = {"stall_torque": 4.0, "no_load_speed": 30.0}


def motor_scene(folder: Path) -> Path:
    """four_bar_loaded with a DC motor on its crank."""
    text = Path(solver.find_scene("four_bar_loaded")).read_text()
    path = folder / "four_bar_motor.yaml"
    path.write_text(text.replace("scene: four_bar_loaded", "scene: four_bar_motor")
                    + f"motor: {{crank: {{stall_torque: {MOTOR['stall_torque']}, "
                      f"no_load_speed: {MOTOR['no_load_speed']}}}}}\n")
    return path


def runtime(**values: Any) -> Runtime:
    return Runtime({"mode": "dynamic", "rate_hz": RATE, **values})


def run(rt: Runtime, seconds: float, *, since: float = 0.0) -> None:
    """Tick ``rt`` at RATE from run time ``since`` (exclusive unless 0) to ``since + seconds``."""
    first = 0 if since == 0.0 else 1
    for i in range(first, int(round(seconds * RATE)) + 1):
        rt.tick(START_NS + round((since + i / RATE) * NS))


def test_mode_and_drive_are_checked_with_a_reason() -> None:
    assert validate_parameter("mode", "dynamic") is None
    assert validate_parameter("mode", "physics") == "mode must be one of kinematic, dynamic, got 'physics'"
    assert validate_parameter("drive", "turbo") == "drive must be one of auto, motor, effort, free, got 'turbo'"
    assert validate_parameter("effort_timeout", 0.0) == "effort_timeout must lie in [0.001, 3600], got 0.0"
    with pytest.raises(ValueError, match="mode dynamic .* needs input_source clock, not topic"):
        runtime(scene="four_bar_loaded", input_source="topic")
    rt = Runtime({"scene": "four_bar_loaded", "input_source": "topic"})
    assert "needs input_source clock" in (rt.update({"mode": "dynamic"}, START_NS) or "")
    rt = runtime(scene="four_bar_loaded")
    assert rt.update({"drive": "motor"}, START_NS) == (
        "drive motor: scene 'four_bar_loaded' has no 'motor:' (docs/dynamics.md); use drive effort or free")
    assert rt.settings["drive"] == "auto"
    rt = Runtime({"scene": "four_bar"})
    assert "nothing gives it inertia" in (rt.update({"mode": "dynamic"}, START_NS) or "")
    assert rt.settings["mode"] == "kinematic"


def test_the_ticks_follow_the_equation_of_motion_as_an_offline_simulation_does() -> None:
    rt = runtime(scene="four_bar_loaded", phi0=0.3, omega=0.0)
    assert isinstance(rt.engine.motion, DynamicMotion) and rt.engine.motion.kind == "effort"
    run(rt, 0.5)
    frame = rt.last_frame
    assert frame is not None and frame.t == pytest.approx(0.5, abs=1e-12)
    reference = rt.engine.scene.simulate(0.5, phi0=0.3, omega0=0.0, drive="free", rtol=1e-12, atol=1e-12)
    assert frame.phi == pytest.approx(float(reference.phi[-1]), abs=1e-7)
    assert frame.omega == pytest.approx(float(reference.omega[-1]), abs=1e-6)
    assert abs(frame.efforts["crank"]) < 1e-9  # no command: free, M·ε + h = 0 to round-off


def test_the_scenes_motor_drives_it_and_commands_are_refused_with_a_reason(tmp_path: Path) -> None:
    rt = runtime(scene=str(motor_scene(tmp_path)), phi0=0.0, omega=0.0)
    law = rt.engine.motion
    assert isinstance(law, DynamicMotion) and law.kind == "motor"
    run(rt, 0.3)
    frame = rt.last_frame
    assert frame is not None and frame.omega > 1.0
    torque = MOTOR["stall_torque"] * (1.0 - frame.omega / MOTOR["no_load_speed"])
    assert frame.efforts["crank"] == pytest.approx(torque, rel=1e-9)
    assert rt.command_efforts([1.0], START_NS + NS) == (
        "effort command ignored: the drive is motor, not effort commands (set drive to effort or auto)")
    # a change of drive goes on from the state reached
    phi = frame.phi
    assert rt.update({"drive": "free"}, START_NS + round(0.3 * NS)) is None
    assert law.kind == "free" and rt.engine.motion is law
    run(rt, 0.001, since=0.3)
    assert rt.last_frame is not None and rt.last_frame.phi == pytest.approx(phi, abs=0.1)


def test_a_command_drives_until_it_times_out_then_the_efforts_are_zero() -> None:
    rt = runtime(scene="four_bar_loaded", phi0=0.3, omega=0.0, effort_timeout=0.1)
    run(rt, 0.05)
    assert rt.command_efforts([1.5], START_NS + round(0.05 * NS)) is None
    assert rt.command_efforts([1.5, 2.0], START_NS + round(0.05 * NS)) == (
        "effort command rejected: 2 value(s) for 1 input(s) (crank); keeping [1.5]")
    assert rt.command_efforts([math.inf], START_NS + round(0.05 * NS)) == (
        "effort command rejected: non-finite value(s) [inf]; keeping [1.5]")
    run(rt, 0.05, since=0.05)
    assert rt.last_frame is not None and rt.last_frame.efforts["crank"] == pytest.approx(1.5, rel=1e-9)
    run(rt, 0.1, since=0.1)
    assert rt.take_events() == ["effort command timed out (0.1 s without one): efforts set to zero"]
    assert rt.last_frame is not None and abs(rt.last_frame.efforts["crank"]) < 1e-9


def test_a_toggle_holds_the_last_state_with_one_event_until_omega_is_set() -> None:
    rt = runtime(scene="five_bar", input_phi0s=[0.3, 0.3], input_omegas=[0.0, 0.0])
    law = rt.engine.motion
    assert isinstance(law, DynamicMotions)
    run(rt, 0.3)  # five_bar from rest at (0.3, 0.3) reaches the distal toggle at t ≈ 0.129 s
    events = rt.take_events()
    assert len(events) == 1
    assert events[0].startswith("five_bar, t = 0.129")
    assert "group 'distal'" in events[0] and events[0].endswith("; holding the last state")
    frame = rt.last_frame
    assert frame is not None and frame.status == "unassemblable" and frame.message == events[0]
    assert frame.omega == (0.0, 0.0)
    held = frame.phi
    run(rt, 0.1, since=0.3)
    assert rt.last_frame is not None and rt.last_frame.phi == held and not rt.take_events()
    assert rt.update({"input_omegas": [-1.0, 1.0]}, START_NS + round(0.4 * NS)) is None
    assert law.segment_at(0.4).tag == "dynamics" and law.stop_message == ""
    run(rt, 0.3, since=0.4)  # back to the toggle from the other side, or not: held again or moving
    law.hold(0.7)
    assert law.segment_at(0.7).tag == "hold"
    # a new effort command resumes a held law from the held angle, at rest
    assert rt.command_efforts([0.01, -0.01], START_NS + round(0.7 * NS)) is None
    assert law.segment_at(0.7).tag == "dynamics" and law.efforts == (0.01, -0.01)
    assert law.state(0.7)[1] == (0.0, 0.0)


def test_diagnostics_carry_the_fixed_step_and_its_error_in_units_of_the_tolerance() -> None:
    rt = runtime(scene="four_bar_loaded", phi0=0.3, omega=0.0)
    run(rt, 0.01)
    law = rt.engine.motion
    frame = rt.last_frame
    assert frame is not None
    built = dict(rt.builder.build(frame, START_NS + round(0.01 * NS), include_paths=False))
    values = {kv.key: kv.value for kv in built["diagnostics"].status[0].values}
    assert float(values["fixed_step"]) == pytest.approx(law.step, rel=1e-5)
    assert float(values["step_error"]) == pytest.approx(law.step_error, rel=1e-2)
    assert 0.0 < law.step <= 1e-3 and law.step_error >= 0.0
