"""The actuator scenes against their 50-digit reference (tests/data/reference_actuators.json).

The reference comes from tests/reference/mp_actuator.py (mpmath only, never the solver): seed
003's circle intersection and the attached points in mpmath at mp.dps = 50, read from the scene
files; every derivative by mpmath's ``diff``. Checked here: the tipper's positions and analogs
d/ds, d²/ds² (and its per-tick real motion), the excavator's positions, Jacobians, Hessians and
real motion v = J·ω, a = J·ε + ωᵀHω, and that the generator reproduces the stored file.
"""

from __future__ import annotations

import importlib.util
import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

import solver

DATA = Path(__file__).resolve().parents[1] / "data" / "reference_actuators.json"
REF = json.loads(DATA.read_text())
#: Agreement of the doubles with the 50-digit values, relative to the mechanism's scale (m): positions,
#: first and second derivatives (measured: 7e-16, 4e-15 and 1.2e-13 at most; conditioning ≥ 0.1 here).
TOL = (2e-15, 2e-14, 1e-12)
SCALE = {"tipper": 2.4, "excavator": 4.0}


def _f(values: Any) -> np.ndarray:
    return np.array(values, dtype=object).astype(float)


def _close(got: Any, want: Any, tol: float, scale: float, what: object) -> None:
    err = float(np.max(np.abs(np.asarray(got, float) - _f(want))))
    assert err <= tol * scale, (what, err)


def test_tipper_positions_and_analogs_match_the_50_digit_reference() -> None:
    ref = REF["tipper"]
    scene = solver.load_scene("tipper").everything()
    strokes = _f(ref["s"])
    k = scene.solve(strokes)
    for name, rows in ref["points"].items():
        m = k.point(name)
        for order, key in enumerate(("position", "d_ds", "d2_ds2")):
            _close((m.position, m.velocity, m.acceleration)[order], rows[key], TOL[order], SCALE["tipper"], (name, key))
    floor = k.joint("floor")
    for order, key in enumerate(("position", "d_ds", "d2_ds2")):
        _close((floor.position, floor.velocity, floor.acceleration)[order], ref["joints"]["floor"][key], TOL[order],
               1.0, ("floor", key))
    np.testing.assert_array_equal(k.joint("stroke").position, strokes)
    assert (k.joint("stroke").velocity == 1.0).all()


def test_the_per_tick_path_gives_the_real_motion_of_the_reference() -> None:
    ref = REF["tipper"]
    scene = solver.load_scene("tipper")
    w, e = 0.07, -0.4  # m/s, m/s²
    for i in (2, 5):
        s = float(ref["s"][i])
        pos, vel, acc = (np.array(x) for x in scene.solve(s, omega=w, epsilon=e).floats("F"))
        rows = ref["points"]["F"]
        d1, d2 = _f(rows["d_ds"][i]), _f(rows["d2_ds2"][i])
        _close(pos, rows["position"][i], TOL[0], SCALE["tipper"], "position")
        _close(vel, d1 * w, TOL[1], SCALE["tipper"], "velocity")
        _close(acc, d2 * w * w + d1 * e, TOL[1], SCALE["tipper"], "acceleration")


def test_excavator_jacobian_hessian_and_real_motion_match_the_50_digit_reference() -> None:
    ref = REF["excavator"]
    scene = solver.load_scene("excavator").with_outputs(points=list(ref["points"]), joints=[])
    assert list(scene.inputs) == ref["inputs"]
    q = _f(ref["q"])
    w, e = _f(ref["motion"]["omega"]), _f(ref["motion"]["epsilon"])
    k = scene.solve(q, omega=w, epsilon=e)
    for name, rows in ref["points"].items():
        m = k.point(name)
        for key, got, tol in (("position", m.position, TOL[0]), ("jacobian", m.jacobian, TOL[1]),
                              ("hessian", m.hessian, TOL[2]), ("velocity", m.velocity, TOL[1]),
                              ("acceleration", m.acceleration, TOL[2])):
            _close(got, rows[key], tol, SCALE["excavator"], (name, key))


def test_the_generator_reproduces_the_stored_reference() -> None:
    path = Path(__file__).resolve().parents[1] / "reference" / "mp_actuator.py"
    spec = importlib.util.spec_from_file_location("mp_actuator", path)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules.setdefault("mp_actuator", module)
    spec.loader.exec_module(module)
    assert "solver" not in path.read_text().split('"""')[2]  # (the code after the docstring never imports it)
    date = REF["provenance"].split("), ")[1].split(":")[0]
    assert module.build(date=date) == REF
    assert REF["provenance"].startswith("tests/reference/mp_actuator.py (mpmath ")
