"""linkage-view of a recording cut short before its first chunk was closed says so in one line."""

from __future__ import annotations

from pathlib import Path

import pytest

pytest.importorskip("mcap", reason="the record extra (mcap) is not installed")
pytest.importorskip("rosbags", reason="the record extra (rosbags) is not installed")

from linkage_ros.cli import run_main, view_main


def test_a_file_cut_inside_its_first_chunk_is_said_to_hold_no_message_yet(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    mcap = tmp_path / "run.mcap"
    # one chunk: 0.2 s of messages, and a wall-clock interval no loaded machine reaches
    assert run_main(["four_bar", "--cycles", "0.2", "--chunk-interval", "600", "--mcap", str(mcap), "--no-rrd"]) == 0
    data = mcap.read_bytes()
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(data[: len(data) * 2 // 3])  # cut inside the one chunk
    capsys.readouterr()
    assert view_main([str(cut), "-o", str(tmp_path / "cut.rrd")]) == 2
    err = capsys.readouterr().err.strip()
    assert err == (f"linkage-view: error: {cut}: cut short before its first chunk was closed: no messages to show "
                   f"(a recording keeps what it wrote up to its last closed chunk; linkage-mcap info {cut})")


def test_a_file_that_is_not_a_recording_is_still_called_so(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    junk = tmp_path / "junk.mcap"
    junk.write_text("not an mcap\n")
    assert view_main([str(junk), "-o", str(tmp_path / "j.rrd")]) == 2
    assert "not a readable linkage_ros recording" in capsys.readouterr().err
