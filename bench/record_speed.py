"""Speed of recording (issue 7): MCAP writing in messages per second, and the 10-minute
standalone run of the harvester finger at 100 Hz with every topic and the rerun recording.

``python -m bench.record_speed [--quick]`` prints the figures (they are quoted in
docs/recording.md). Targets: MCAP writing ≥ 50 000 msg/s; the 10-minute run < 30 s.
"""

from __future__ import annotations

import argparse
import platform
import tempfile
import time
from pathlib import Path

import numpy as np

from linkage_ros.engine import Engine
from linkage_ros.messages import MessageBuilder, topic_types
from linkage_ros.motion import Motion
from linkage_ros.record.mcap import Recorder
from linkage_ros.record.run import RunOptions, run_standalone

TARGET_MSG_PER_S = 50_000
TARGET_RUN_S = 30.0


def mcap_rates(ticks: int, folder: Path) -> dict[str, float]:
    """msg/s of Recorder.write (rosbags messages, serialised inside) and of
    Recorder.write_serialized (bytes ready), for the harvester finger's 13 topics."""
    from rosbags.typesys import Stores, get_typestore

    ts = get_typestore(Stores.ROS2_JAZZY)
    engine = Engine("harvester_finger", Motion(omega=2 * np.pi))
    builder = MessageBuilder(engine, ts.types)
    times = np.arange(ticks) / 100.0
    stamps = [int(round(t * 1e9)) for t in times]
    ticks_msgs = [builder.build(f, s) for f, s in zip(engine.frames(times), stamps)]
    types = dict(topic_types(engine))
    raw = [[(t, bytes(ts.serialize_cdr(m, types[t]))) for t, m in msgs] for msgs in ticks_msgs]
    count = sum(len(m) for m in raw)
    out = {}
    start = time.perf_counter()
    with Recorder(folder / "objects.mcap", topic_types(engine), typestore=ts) as rec:
        for s, msgs in zip(stamps, ticks_msgs):
            rec.write(s, msgs)
    out["write (serialise + write)"] = count / (time.perf_counter() - start)
    start = time.perf_counter()
    with Recorder(folder / "bytes.mcap", topic_types(engine), typestore=ts) as rec:
        for s, msgs in zip(stamps, raw):
            rec.write_serialized(s, msgs)
    out["write_serialized (write only)"] = count / (time.perf_counter() - start)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="1-minute run instead of 10")
    args = parser.parse_args()
    print(
        f"machine: {platform.machine()}, {platform.python_implementation()} "
        f"{platform.python_version()}, {platform.processor() or 'cpu ?'}"
    )
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        for name, rate in mcap_rates(3000, folder).items():
            flag = "ok" if rate >= TARGET_MSG_PER_S else "BELOW TARGET"
            print(f"MCAP {name}: {rate:,.0f} msg/s ({flag})")
        duration = 60.0 if args.quick else 600.0
        start = time.perf_counter()
        result = run_standalone(
            RunOptions(
                scene="harvester_finger",
                duration=duration,
                rate=100.0,
                mcap=folder / "run.mcap",
                rrd=folder / "run.rrd",
            )
        )
        total = time.perf_counter() - start
        size = (folder / "run.mcap").stat().st_size / 2**20
        print(
            f"linkage-run harvester_finger {duration:g} s at 100 Hz: {result.ticks} ticks, "
            f"{result.messages} messages ({size:.0f} MiB), {total:.1f} s in all "
            f"(solve + MCAP {result.seconds['solve+mcap']:.1f} s, rerun "
            f"{result.seconds.get('rerun', 0.0):.1f} s)"
            + ("" if args.quick else f" — target < {TARGET_RUN_S:g} s: {'ok' if total < TARGET_RUN_S else 'MISSED'}")
        )


if __name__ == "__main__":
    main()
