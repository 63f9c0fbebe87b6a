"""``linkage-view`` and ``linkage-mcap``: the commands on a recorded MCAP run (:mod:`linkage_ros.cli`).

* ``linkage-view RUN.mcap``: the rerun view from the recorded messages, without solving again
  (also from a file cut short by a crash).
* ``linkage-mcap recover BROKEN.mcap FIXED.mcap`` and ``linkage-mcap info RUN.mcap``.

Exit statuses and error lines as for ``linkage-run`` (:mod:`linkage_ros.cli`).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

from solver._cmdline import Parser, check_output, one_line, quiet_pipe

from ._cli_common import (
    EXIT_ERROR,
    EXIT_OK,
    EXIT_USAGE,
    NO_RERUN,
    check_input,
    err,
    have_rerun,
    os_error,
    show,
    spawn_file,
)

__all__ = ["mcap_main", "view_main"]


@quiet_pipe
def view_main(argv: Sequence[str] | None = None) -> int:
    """``linkage-view``."""
    p = Parser(
        prog="linkage-view",
        description="Turn a recorded MCAP run into the rerun view (from the messages, without "
                    "solving again); works on files cut short by a crash.")
    p.add_argument("mcap", type=Path, help="recorded run (.mcap)")
    p.add_argument("-o", "--output", type=Path, metavar="RUN.rrd",
                   help="rerun file to write (default: next to the MCAP, RUN.view.rrd, so that the "
                        ".rrd linkage-run wrote beside it is kept)")
    p.add_argument("--spawn", action="store_true", help="show it in a rerun viewer")
    args = p.parse_args(argv)
    out = args.output or (None if args.spawn else args.mcap.with_suffix(".view.rrd"))
    kept = out is not None
    try:
        check_input(args.mcap, "an MCAP file")
        if out is not None:
            check_output(out, "-o" if args.output else "output")
            if out.resolve() == args.mcap.resolve():
                raise ValueError(f"-o {out}: that is the MCAP file being read")
    except ValueError as exc:
        err(str(exc), "linkage-view")
        return EXIT_USAGE
    if not have_rerun():
        err(NO_RERUN, "linkage-view")
        return EXIT_USAGE
    from linkage_ros.record.replay import run_data_from_mcap, stamp_text
    from linkage_ros.record.rerun import write_rrd

    try:
        data, contents = run_data_from_mcap(args.mcap)
    except OSError as exc:
        err(os_error(exc), "linkage-view")
        return EXIT_USAGE
    except (ValueError, KeyError, IndexError, TypeError) as exc:
        err(_unreadable(args.mcap, exc), "linkage-view")
        return EXIT_USAGE
    if out is None:
        out = spawn_file(None, args.mcap.stem)
    try:
        write_rrd(data, out)
    except OSError as exc:
        err(os_error(exc), "linkage-view")
        return EXIT_ERROR
    except RuntimeError as exc:
        err(str(exc), "linkage-view")
        return EXIT_ERROR
    state = "finished" if contents.complete else "cut short (no footer), read up to the last chunk"
    span = float(data.t[-1]) if data.n else 0.0
    first = f", from {stamp_text(data.start_ns)}" if data.n and data.start_ns else ""
    print(f"{args.mcap}: {state}; {contents.message_count} messages, {data.n} ticks over "
          f"{span:g} s of run time{first}")
    if kept:
        print(f"rerun: {out}")
    if args.spawn and not show(out, "linkage-view") and not kept:
        return EXIT_ERROR
    return EXIT_OK


def _unreadable(path: Path, error: Exception) -> str:
    """Why linkage-view cannot show ``path``: a recording cut short before any of its chunks was
    closed holds no message (said so), anything else is not a linkage_ros recording."""
    from linkage_ros.record.mcap_read import read_mcap

    try:
        contents = read_mcap(path, messages=False)
    except (OSError, ValueError, KeyError, IndexError, TypeError):
        contents = None
    if contents is not None and not contents.complete and contents.message_count == 0:
        return (f"{path}: cut short before its first chunk was closed: no messages to show (a recording "
                f"keeps what it wrote up to its last closed chunk; linkage-mcap info {path})")
    why = one_line(str(error), 200).removeprefix(f"{path}: ")
    return f"{path}: not a readable linkage_ros recording ({why})"


def _about(path: Path, error: Exception) -> str:
    """``PATH: what is wrong``, naming the path once (some messages already start with it)."""
    if isinstance(error, OSError) and error.filename:
        return os_error(error)  # names its own file (BROKEN or FIXED)
    text = str(error)
    return text if text.startswith(f"{path}:") else f"{path}: {text}"


@quiet_pipe
def mcap_main(argv: Sequence[str] | None = None) -> int:
    """``linkage-mcap``: one line per outcome, each file named once."""
    p = Parser(prog="linkage-mcap", description="Inspect and repair MCAP runs.")
    sub = p.add_subparsers(dest="command", required=True)
    rec = sub.add_parser("recover", help="write a valid, finished copy of a file cut short")
    rec.add_argument("broken", type=Path)
    rec.add_argument("fixed", type=Path)
    info = sub.add_parser("info", help="topics, counts and whether the file was finished")
    info.add_argument("file", type=Path)
    args = p.parse_args(argv)
    from linkage_ros.record.mcap_read import read_mcap, recover
    from linkage_ros.record.replay import stamp_text

    source: Path = args.broken if args.command == "recover" else args.file
    try:
        check_input(source, "an MCAP file")
        if args.command == "recover":
            check_output(args.fixed, "FIXED")
            if args.fixed.resolve() == args.broken.resolve():
                raise ValueError(f"FIXED {args.fixed}: write the recovered copy to another file than BROKEN")
    except ValueError as exc:
        err(str(exc), "linkage-mcap")
        return EXIT_USAGE
    try:
        contents = recover(args.broken, args.fixed) if args.command == "recover" else read_mcap(source)
    except (OSError, ValueError, KeyError, IndexError) as exc:
        err(_about(source, exc), "linkage-mcap")
        return EXIT_ERROR if isinstance(exc, OSError) and exc.filename != str(source) else EXIT_USAGE
    topics = contents.topics()
    if args.command == "recover":
        lost = contents.size - contents.valid_bytes
        what = ("it was finished, nothing lost" if contents.complete
                else f"cut short: the last {lost} bytes, after the last whole record, dropped")
        print(f"{args.fixed}: {len(contents.messages)} messages on {len(topics)} topics recovered "
              f"from {args.broken} ({what})")
        return EXIT_OK
    header = contents.header
    writer = f"{header.profile} profile, written by {header.library}" if header else "no header"
    times = [m.log_time for m in contents.messages]
    first, last = (min(times), max(times)) if times else (0, 0)
    span = f", {(last - first) / 1e9:g} s" if times else ""
    span += f" from {stamp_text(first)}" if first else ""
    if contents.complete:
        state = "finished"
    else:
        state = (f"NOT finished (readable up to byte {contents.valid_bytes} of {contents.size}; "
                 f"make a finished copy with: linkage-mcap recover {source} FIXED.mcap)")
    print(f"{source}: {state}; {len(times)} messages on {len(topics)} topics{span}; {writer}")
    counts: dict[str, int] = {}
    for m in contents.messages:
        counts[m.topic] = counts.get(m.topic, 0) + 1
    for topic, typename in topics.items():
        print(f"  {topic:40s} {typename:40s} {counts.get(topic, 0)}")
    return EXIT_OK
