"""The real rerun viewer, rendered headless (software Vulkan), shows the mechanism."""

from __future__ import annotations

import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("rerun", reason="the view extra (rerun-sdk, needs numpy >= 2) is not installed")
Image = pytest.importorskip("PIL.Image", reason="Pillow is needed to read the screenshot")

from linkage_ros.record._drawing import FIXED_COLOR, LINK_COLOR, SERIES_PALETTE  # noqa: E402
from linkage_ros.record.run import RunOptions, run_standalone  # noqa: E402
from linkage_ros.record.viewer import viewer_environment  # noqa: E402

LAVAPIPE = Path("/usr/share/vulkan/icd.d/lvp_icd.x86_64.json")
RERUN = next((str(p) for p in (Path(sys.executable).parent / "rerun",) if p.exists()),
             shutil.which("rerun"))
COLOR_TOL = 40  # per channel, for antialiased edges and shading
MIN_LINK_FRACTION = 5e-4  # of the mechanism view's pixels
MIN_PIVOT_PIXELS = 20
ATTEMPTS = 5
"""The headless viewer shoots after a fixed number of frames; on a loaded machine the recording
may not be on screen yet (loading indicators, empty plots), so a blank picture is retaken."""

pytestmark = [
    pytest.mark.screenshot,
    pytest.mark.skipif(not LAVAPIPE.exists(), reason=f"no software Vulkan driver ({LAVAPIPE}); "
                       "apt-get install mesa-vulkan-drivers libvulkan1"),
    pytest.mark.skipif(RERUN is None, reason="the rerun viewer binary is not installed"),
]


def screenshot(rrd: Path, png: Path) -> np.ndarray:
    env = {**viewer_environment(), "VK_ICD_FILENAMES": str(LAVAPIPE), "RUST_LOG": "error"}
    done = subprocess.run(
        [str(RERUN), str(rrd), "--port", "auto", "--headless", "--renderer", "vulkan",
         "--screenshot-to", str(png), "--window-size", "1280x800"],
        env=env, capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr[-2000:]
    assert "XDG_RUNTIME_DIR" not in done.stderr, done.stderr[-2000:]  # (issue 24: a user reads "error")
    return np.asarray(Image.open(png).convert("RGB"), dtype=np.int16)


def near(pixels: np.ndarray, color: tuple[int, int, int]) -> np.ndarray:
    return (np.abs(pixels - np.array(color)) <= COLOR_TOL).all(axis=-1)


def problems(shot: np.ndarray) -> list[str]:
    h, w, _ = shot.shape
    mechanism = shot[int(0.08 * h): int(0.78 * h), : int(0.58 * w)]  # left column, top 5/6
    plots = shot[int(0.08 * h): int(0.95 * h), int(0.62 * w):]
    out = []
    if near(mechanism, LINK_COLOR).mean() <= MIN_LINK_FRACTION:
        out.append("no links drawn in the mechanism view")
    if near(mechanism, FIXED_COLOR).sum() <= MIN_PIVOT_PIXELS:
        out.append("no fixed pivots drawn")
    if not any(near(plots, c).sum() > MIN_PIVOT_PIXELS for c in SERIES_PALETTE[:2]):
        out.append("no plotted series")
    return out


@pytest.mark.parametrize("scene", ["four_bar", "spherical_converter"])
def test_headless_viewer_draws_the_mechanism_and_the_plots(scene: str, tmp_path: Path) -> None:
    rrd = tmp_path / f"{scene}.rrd"
    run_standalone(RunOptions(scene=scene, duration=1.0, rate=50.0, rrd=rrd))
    found: list[str] = []
    for attempt in range(ATTEMPTS):
        found = problems(screenshot(rrd, tmp_path / f"shot{attempt}.png"))
        if not found:
            break
    assert not found, f"after {ATTEMPTS} screenshots: {'; '.join(found)}"
