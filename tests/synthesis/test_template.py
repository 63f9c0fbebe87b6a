"""Template scenes: free values by place, one SceneError line per fault, populations that agree
with the scenes they stand for (the groups' parameters broadcast over candidates × samples)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import yaml

from solver import SceneError
from solver.synthesis import load_template
from solver.synthesis.population import run

HERE = Path(__file__).parent / "templates"
FOUR_BAR = Path(__file__).parents[2] / "config" / "templates" / "four_bar_path.yaml"


def _template(tmp_path: Path, text: str):  # type: ignore[no-untyped-def]
    path = tmp_path / "t.yaml"
    path.write_text(text)
    return load_template(path)


BASE = """\
scene: t
units: {{length: m, angle: deg}}
fixed:
  O: [0.0, 0.0]
  C: [{c}, 0.0]
groups:
  - {{type: {kind}, name: crank, center: O, point: A, length: {crank}}}
  - {{type: rrr, name: dyad, ends: [A, C], point: B, lengths: [0.4, 0.3], M: {mode}}}
outputs: {{points: [B]}}
"""


def test_places_name_every_free_value() -> None:
    t = load_template(FOUR_BAR)
    assert t.places == (
        "fixed.O[0]", "fixed.O[1]", "fixed.C[0]", "fixed.C[1]", "groups[0].length", "groups[1].lengths[0]",
        "groups[1].lengths[1]", "groups[2].distance", "groups[2].angle",
    )
    assert t.lo[4] == 0.02 and t.hi[8] == 180.0


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"crank": "{free: [0.2, 0.1]}"}, r"t\.yaml:7: groups\[0\]\.length: free range \[0\.2, 0\.1\] has lo > hi"),
        ({"kind": "{free: [0, 1]}"}, r"groups\[0\]\.type: a free value in a place that cannot vary"),
        ({"mode": "{free: [-1, 1]}"}, r"groups\[1\]\.M: a free value in a place that cannot vary"),
        ({"crank": "{free: [-0.1, 0.1]}"}, r"groups\[0\]\.length: a length's free range must be positive"),
        ({"crank": "{free: [0.1]}"}, r"free must be \[lo, hi\], got \[0\.1\]"),
        ({"crank": "{free: [0.1, .inf]}"}, r"free must be \[lo, hi\] with finite numbers"),
        ({"crank": "{free: [0.1, 0.2], step: 1}"}, r"unknown field\(s\): step"),
        ({"crank": "0.1"}, r"a template needs at least one \{free: \[lo, hi\]\} value"),
        ({"c": "{free: [0.3, 0.5]}", "kind": "crnk"}, r"unknown group type 'crnk'"),
    ],
)
def test_bad_templates_one_line(tmp_path: Path, fields: dict[str, str], message: str) -> None:
    values = {"c": "0.4", "kind": "crank", "crank": "{free: [0.05, 0.2]}", "mode": "+1", **fields}
    with pytest.raises(SceneError, match=message) as info:
        _template(tmp_path, BASE.format(**values))
    assert "\n" not in str(info.value)


def test_free_value_in_units_section_refused(tmp_path: Path) -> None:
    text = BASE.format(c="0.4", kind="crank", crank="{free: [0.05, 0.2]}", mode="+1").replace(
        "angle: deg", "angle: {free: [0, 1]}"
    )
    with pytest.raises(SceneError, match=r"units\.angle: a free value in a place that cannot vary"):
        _template(tmp_path, text)


@pytest.mark.parametrize("name", ["four_bar", "slider_crank", "six_bar"])
def test_population_equals_each_scene(name: str) -> None:
    path = {"four_bar": FOUR_BAR, "slider_crank": HERE / "slider_crank_path.yaml",
            "six_bar": HERE / "six_bar_path.yaml"}[name]
    t = load_template(path)
    point = t.template_scene.output_points[0]
    rng = np.random.default_rng(3)
    x = rng.uniform(t.lo, t.hi, (16, len(t.lo)))
    phi = np.linspace(0.0, 2 * np.pi, 50, endpoint=False)
    ctx = run(t, x, phi, (point,))
    pop = np.broadcast_to(ctx.values[point].value, (16, 50))
    bad = np.broadcast_to(np.asarray(ctx.invalid, bool), (16, 50))
    for c in range(16):
        k = t.scene(x[c]).solve(phi, mask=True)
        np.testing.assert_array_equal(~k.valid, bad[c])
        xy = k.point(point).position[k.valid]
        got = pop[c][k.valid]
        assert np.abs(xy[:, 0] + 1j * xy[:, 1] - got).max(initial=0.0) <= 1e-13


def test_filled_file_is_a_plain_scene(tmp_path: Path) -> None:
    t = load_template(FOUR_BAR)
    x = 0.5 * (t.lo + t.hi)
    data = t.filled(x)
    assert data["groups"][1]["lengths"] == [0.775, 0.775]
    (tmp_path / "s.yaml").write_text(yaml.safe_dump(data, sort_keys=False))
    from solver import load_scene

    assert load_scene(tmp_path / "s.yaml").point_names[:2] == ("O", "C")
