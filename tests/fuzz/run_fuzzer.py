"""Standalone mutation fuzzer of the scene loader (issue #13): ≈1,000 mutated shipped scenes plus
the issue's special cases, each loaded, solved and run through ``linkage-solve`` in a fresh
process with a timeout and a memory limit.

    nice -n 10 .venv/bin/python tests/fuzz/run_fuzzer.py [--count 1000] [--seed 13] [--timeout 30]
        [--memory-mb 1536] [--keep DIR]

Counts: files, loaded, rejected (one SceneError line), tracebacks (any other exception, in the
API or in linkage-solve), hangs (timeout), crashes (killed, e.g. by the memory limit), duplicate
keys accepted, files with non-finite values at valid non-singular samples, errors of more than one
line, and linkage-solve exits other than 0 and 2. The special cases also run the installed
``linkage-solve`` command itself. Exit status 1 when any of the bad counts is non-zero.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from collections import Counter
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
sys.path[:0] = [str(ROOT), str(HERE)]

BAD = ("traceback", "hang", "crash", "dup_accepted", "nonfinite", "multiline", "cli_exit")


def _limits(memory_mb: int, cpu_s: int) -> object:
    def apply() -> None:
        limit = memory_mb << 20
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))
        resource.setrlimit(resource.RLIMIT_CPU, (cpu_s, cpu_s + 1))

    return apply


def _one(path: str) -> int:
    """The worker: examine one file, print the result as JSON."""
    from scene_mutations import examine

    print(json.dumps(examine(Path(path), cli=True), default=str))
    return 0


def _run(cmd: list[str], timeout: float, memory_mb: int) -> tuple[str, subprocess.CompletedProcess[str] | None]:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "OMP_NUM_THREADS": "1", "PYTHONPATH": str(ROOT)}
    try:
        done = subprocess.run(
            cmd,
            capture_output=True,
            text=True,
            timeout=timeout,
            env=env,
            preexec_fn=_limits(memory_mb, int(timeout) + 5),
        )
    except subprocess.TimeoutExpired:
        return "hang", None
    return "ok", done


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--count", type=int, default=1000, help="mutated files (default 1000)")
    p.add_argument("--seed", type=int, default=13)
    p.add_argument("--timeout", type=float, default=30.0, help="seconds per file (default 30)")
    p.add_argument("--memory-mb", type=int, default=1536, help="address-space limit per process (1536)")
    p.add_argument("--keep", type=Path, help="keep the files (and a report.json) in this folder")
    p.add_argument("--one", help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    if args.one:
        return _one(args.one)
    from scene_mutations import mutations, special_cases

    work = args.keep or Path(tempfile.mkdtemp(prefix="fuzz-scenes-"))
    work.mkdir(parents=True, exist_ok=True)
    cases = [("special", *c) for c in special_cases(big=True)] + [
        ("mutation", *m) for m in mutations(args.seed, args.count)
    ]
    counts: Counter[str] = Counter()
    examples: dict[str, list[str]] = {}
    solve_cmd = str(Path(sys.executable).with_name("linkage-solve"))
    start = time.monotonic()
    for i, (kind, label, raw, dup) in enumerate(cases):
        path = work / f"{i:04d}.yaml"
        path.write_bytes(raw)
        counts["files"] += 1
        counts[kind] += 1
        counts["with a duplicate key"] += dup
        state, done = _run(
            [sys.executable, str(HERE / "run_fuzzer.py"), "--one", str(path)], args.timeout, args.memory_mb
        )
        found: list[str] = []
        if state == "hang":
            found.append("hang")
        elif done is None or done.returncode != 0 or not done.stdout.strip():
            found.append("traceback" if done is not None and "Traceback" in done.stderr else "crash")
        else:
            r = json.loads(done.stdout.strip().splitlines()[-1])
            counts[r["outcome"]] += 1
            if r["outcome"] == "traceback" or r["cli"] == "traceback":
                found.append("traceback")
            if dup and r["outcome"] == "loaded":
                found.append("dup_accepted")
            if r["nonfinite"]:
                found.append("nonfinite")
            if r["multiline"] or r.get("cli_lines"):
                found.append("multiline")
            if r["cli"] not in (0, 2, "traceback"):
                found.append("cli_exit")
        if kind == "special" and os.access(solve_cmd, os.X_OK):  # the installed command itself
            state, run = _run([solve_cmd, str(path)], args.timeout, args.memory_mb)
            if state == "hang":
                found.append("hang")
            elif run is not None and (
                "Traceback" in run.stderr or (run.returncode != 0 and len(run.stderr.strip().splitlines()) != 1)
            ):
                found.append("traceback" if "Traceback" in run.stderr else "multiline")
        for f in dict.fromkeys(found):
            counts[f] += 1
            examples.setdefault(f, []).append(f"{path.name}: {label}")
        if (i + 1) % 100 == 0:
            print(f"  {i + 1}/{len(cases)} files, {time.monotonic() - start:.0f} s", file=sys.stderr, flush=True)
    elapsed = time.monotonic() - start
    print(
        f"{counts['files']} files ({counts['special']} special cases, {counts['mutation']} mutations of the "
        f"shipped scenes, seed {args.seed}) in {elapsed:.0f} s; timeout {args.timeout:g} s, memory limit "
        f"{args.memory_mb} MB per process"
    )
    print(
        f"loaded {counts['loaded']}, refused with one SceneError line {counts['rejected']} "
        f"({counts['with a duplicate key']} files with a key given twice)"
    )
    print(", ".join(f"{name} {counts[name]}" for name in BAD))
    for name in BAD:
        for line in examples.get(name, [])[:5]:
            print(f"  {name}: {line}")
    if args.keep:
        (work / "report.json").write_text(json.dumps({"counts": counts, "examples": examples}, indent=1))
    return 1 if any(counts[name] for name in BAD) else 0


if __name__ == "__main__":
    sys.exit(main())
