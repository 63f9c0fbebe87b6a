"""Mutations of the shipped scene files, and the special cases of issue #13, for fuzzing the loader.

Each mutation is ``(label, bytes, dup)``: a name saying what was done, the mutated file, and
whether the file has a key twice in one mapping (so it must never load). Everything is drawn
from a ``random.Random(seed)``: the same seed gives the same files.

* data mutations parse a shipped scene, change one thing (delete, misspell or retype a key, put
  an extreme number, an unknown name, a typo'd section, an empty or odd section, a duplicate
  group, scaled lengths) and write it back as YAML;
* text mutations change the file as text (delete, duplicate or truncate lines, a duplicate key,
  a number as ``1e-3``, odd bytes, an anchor bomb, deep nesting at a value).
"""

from __future__ import annotations

import contextlib
import copy
import io
import math
import random
import traceback
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import numpy as np
import yaml

import solver
from solver.cli import main as solve_main

__all__ = ["Mutation", "shipped_texts", "mutations", "special_cases", "has_duplicate_keys", "examine", "BOMB"]

Mutation = tuple[str, bytes, bool]

NUMBERS: list[Any] = [
    0,
    -1,
    1e-12,
    1e-9,
    9e-10,
    1e9,
    1.1e9,
    1e10,
    1.0e154,
    1e200,
    1e308,
    -1e308,
    10**29,
    2**63,
    10**400,
    float("nan"),
    float("inf"),
    -float("inf"),
    0.5,
    -0.5,
    3,
    360,
    1e4,
    1e5,
    True,
]
ODD_VALUES: list[Any] = ["1e-3", "abc", "", None, False, [], {}, [1, 2, 3], {"a": 1}, "A" * 300, [[[[1]]]]]
NAMES = ["Z", "", "A", "B", "O", "x" * 150, "crank", "finger"]

BOMB = "lol0: &l0 [lol, lol, lol, lol, lol, lol, lol, lol, lol, lol]\n" + "".join(
    f"lol{i}: &l{i} [{', '.join([f'*l{i - 1}'] * 10)}]\n" for i in range(1, 9)
)


def shipped_texts() -> dict[str, str]:
    """The shipped scene files (name → text), in a stable order."""
    return {name: Path(path).read_text(encoding="utf-8") for name, path in sorted(solver.shipped_scenes().items())}


def _paths(node: Any, here: tuple[Any, ...] = ()) -> Iterator[tuple[Any, ...]]:
    """Every key path into a parsed scene."""
    if isinstance(node, dict):
        for k, v in node.items():
            yield (*here, k)
            yield from _paths(v, (*here, k))
    elif isinstance(node, list):
        for i, v in enumerate(node):
            yield (*here, i)
            yield from _paths(v, (*here, i))


def _get(node: Any, path: tuple[Any, ...]) -> Any:
    for k in path:
        node = node[k]
    return node


def _typo(word: str, rng: random.Random) -> str:
    if len(word) < 2:
        return word + "x"
    i = rng.randrange(len(word) - 1)
    kind = rng.randrange(3)
    if kind == 0:  # swap two letters: lengths → lenghts
        return word[:i] + word[i + 1] + word[i] + word[i + 2 :]
    if kind == 1:  # drop one: joints → joint
        return word[:i] + word[i + 1 :]
    return word[:i] + rng.choice("aeiosz") + word[i:]


def _dump(data: Any) -> bytes:
    return yaml.safe_dump(data, sort_keys=False, allow_unicode=True, width=10_000).encode("utf-8")


def _data_mutation(data: Any, rng: random.Random) -> tuple[str, Any]:
    paths = list(_paths(data))
    path = rng.choice(paths)
    parent, key = _get(data, path[:-1]), path[-1]
    op = rng.randrange(14)
    if op == 13:  # every number anywhere in the allowed range (docs/scenes.md#number-ranges)
        for q in paths:
            value = _get(data, q)
            if isinstance(value, float) and q[-1] != "M":
                _get(data, q[:-1])[q[-1]] = math.copysign(10 ** rng.uniform(-8.9, 8.9), rng.choice([value, -value]))
        return "every number log-uniform in 1e-9 … 1e9", data
    if op >= 10:  # keep the structure, move a number: the scenes that load are the interesting ones
        numbers = [q for q in paths if isinstance(_get(data, q), (int, float)) and not isinstance(_get(data, q), bool)]
        if numbers:
            q = rng.choice(numbers)
            holder, last = _get(data, q[:-1]), q[-1]
            old = holder[last]
            holder[last] = rng.choice([old * rng.uniform(0.2, 5.0), -old, old + rng.uniform(-0.5, 0.5), 0.0])
            return f"perturb {q}", data
    if op == 0:
        del parent[key]
        return f"delete {path}", data
    if op == 1 and isinstance(key, str):
        typo = _typo(key, rng)
        if typo not in parent:
            parent[typo] = parent.pop(key)
            return f"misspell {path} as {typo!r}", data
    if op in (2, 3):
        parent[key] = rng.choice(NUMBERS)
        return f"number at {path}: {parent[key] if not isinstance(parent[key], int) else 'int'}", data
    if op == 4:
        parent[key] = copy.deepcopy(rng.choice(ODD_VALUES))
        return f"odd value at {path}", data
    if op == 5 and isinstance(parent[key], str):
        parent[key] = rng.choice(NAMES)
        return f"name at {path}: {parent[key][:10]!r}", data
    if op == 6:
        groups = data.get("groups")
        if isinstance(groups, list) and groups:
            groups.append(copy.deepcopy(rng.choice(groups)))
            return "a group twice", data
    if op == 7:
        factor = rng.choice([1e-15, 1e-9, 1e9, 1e12, 1e150, -1.0])
        _scale(data, factor)
        return f"lengths × {factor:g}", data
    if op == 8:
        section = rng.choice(["groups", "joints", "outputs", "fixed", "units", "vector_model"])
        if section in data:
            data[section] = rng.choice([None, [], {}, 7, "x"])
            return f"section {section} emptied", data
    if op == 9 and isinstance(parent[key], list) and parent[key]:
        parent[key] = parent[key][:-1] if rng.random() < 0.5 else [*parent[key], parent[key][0]]
        return f"list length at {path}", data
    parent[key] = rng.choice(NUMBERS + ODD_VALUES)
    return f"value at {path}", data


def _scale(node: Any, factor: float) -> None:
    numeric = ("length", "lengths", "distance", "radius", "r", "offset", "points")
    if isinstance(node, dict):
        for k, v in node.items():
            if k in numeric and isinstance(v, (int, float)) and not isinstance(v, bool):
                node[k] = v * factor
            elif k in numeric and isinstance(v, list):
                node[k] = [x * factor if isinstance(x, (int, float)) and not isinstance(x, bool) else x for x in v]
            elif k in ("points",) and isinstance(v, dict):
                node[k] = {a: b * factor if isinstance(b, (int, float)) else b for a, b in v.items()}
            else:
                _scale(v, factor)
    elif isinstance(node, list):
        for v in node:
            _scale(v, factor)


def _text_mutation(text: str, rng: random.Random) -> tuple[str, bytes]:
    lines = text.splitlines(keepends=True)
    i = rng.randrange(len(lines))
    op = rng.randrange(9)
    if op == 0:
        return f"delete line {i + 1}", "".join(lines[:i] + lines[i + 1 :]).encode()
    if op == 1:
        return f"duplicate line {i + 1}", "".join(lines[: i + 1] + lines[i:]).encode()
    if op == 2:
        cut = rng.randrange(len(text))
        return f"truncate at {cut}", text[:cut].encode()
    if op == 3:
        raw = text.encode()
        at = rng.randrange(len(raw))
        junk = rng.choice(
            [b"\xe9", b"\xff\xfe", b"\x00", b"\x07", b"\t", b"{", b"[", b"&a ", b"*a ", b"!!python/object:os.system "]
        )
        return f"bytes {junk!r} at {at}", raw[:at] + junk + raw[at:]
    if op == 4:
        import re

        nums = list(re.finditer(r"(?<![\w.])\d+\.\d+(?![\w.])", text))
        if nums:
            m = rng.choice(nums)
            return "number as 1e-3 text", (text[: m.start()] + "1e-3" + text[m.end() :]).encode()
    if op == 5:
        return "bomb at a value", _at_value(BOMB + text, rng, "*l8").encode()
    if op == 6:
        depth = rng.choice([100, 1000, 20_000])
        return f"nested {depth}", _at_value(text, rng, "[" * depth + "]" * depth).encode()
    if op == 7:
        return "alias to itself", _at_value(text, rng, "&self [*self]").encode()
    return f"line {i + 1} repeated at its end", "".join(
        lines[:i] + [lines[i].rstrip("\n") * 2 + "\n"] + lines[i + 1 :]
    ).encode()


def _at_value(text: str, rng: random.Random, value: str) -> str:
    """Put ``value`` in place of a random ``key: value`` line's value."""
    lines = text.splitlines(keepends=True)
    candidates = [i for i, line in enumerate(lines) if ": " in line and not line.lstrip().startswith(("#", "-"))]
    if not candidates:
        return text + f"x: {value}\n"
    i = rng.choice(candidates)
    head = lines[i].split(": ", 1)[0]
    lines[i] = f"{head}: {value}\n"
    return "".join(lines)


def has_duplicate_keys(raw: bytes) -> bool:
    """Whether the file has a key twice in one mapping (checked on the node graph, no expansion)."""
    try:
        root = yaml.compose(raw.decode("utf-8"), Loader=yaml.SafeLoader)
    except Exception:
        return False
    seen_nodes: set[int] = set()
    stack = [root]
    while stack:
        node = stack.pop()
        if node is None or id(node) in seen_nodes:
            continue
        seen_nodes.add(id(node))
        if isinstance(node, yaml.MappingNode):
            keys = [
                k.value for k, _ in node.value if isinstance(k, yaml.ScalarNode) and k.tag != "tag:yaml.org,2002:merge"
            ]
            if len(keys) != len(set(keys)):
                return True
            stack.extend(v for kv in node.value for v in kv)
        elif isinstance(node, yaml.SequenceNode):
            stack.extend(node.value)
    return False


def _dup_key_mutation(text: str, rng: random.Random) -> tuple[str, bytes]:
    """Give a key twice: a mapping line repeated with another value, or a flow key doubled."""
    lines = text.splitlines(keepends=True)
    flow = [i for i, line in enumerate(lines) if "{" in line and ", " in line and "M:" in line]
    if flow and rng.random() < 0.5:
        i = rng.choice(flow)
        line = lines[i].rstrip("\n")
        lines[i] = line[: line.rindex("}")] + ", M: -1}" + line[line.rindex("}") + 1 :] + "\n"
        return f"M given twice on line {i + 1}", "".join(lines).encode()
    candidates = [
        i
        for i, line in enumerate(lines)
        if line.startswith("  ") and ": " in line and not line.lstrip().startswith("-")
    ]
    i = rng.choice(candidates)
    return f"key of line {i + 1} given twice", "".join(lines[: i + 1] + [lines[i]] + lines[i + 1 :]).encode()


def mutations(seed: int, count: int) -> Iterator[Mutation]:
    """``count`` mutated files of the shipped scenes, drawn from ``seed``."""
    rng = random.Random(seed)
    texts = shipped_texts()
    names = list(texts)
    for n in range(count):
        name = names[n % len(names)]
        text = texts[name]
        kind = rng.random()
        if kind < 0.55:
            label, data = _data_mutation(yaml.safe_load(text), rng)
            raw = _dump(data)
        elif kind < 0.65:
            label, raw = _dup_key_mutation(text, rng)
        else:
            label, raw = _text_mutation(text, rng)
        yield f"{name}: {label}", raw, has_duplicate_keys(raw)


def _chain(n: int) -> bytes:
    lines = [
        "scene: chain",
        "units: {length: m, angle: deg}",
        "fixed: {O: [0.0, 0.0], C: [0.4, 0.0]}",
        "groups:",
        "  - {type: crank, name: crank, center: O, point: P0, length: 0.1}",
    ]
    prev = "O"
    for i in range(1, n):
        lines.append(
            f"  - {{type: attached, name: g{i}, point: P{i}, base: P{i - 1}, along: [{prev}, P{i - 1}], "
            "distance: 0.1, angle: 10}"
        )
        prev = f"P{i - 1}"
    lines.append(f"outputs: {{points: [P{n - 1}]}}")
    return ("\n".join(lines) + "\n").encode()


def special_cases(*, big: bool = True) -> Iterator[Mutation]:
    """The cases issue #13 lists, each as one file (``big``: include the 100k-deep nesting and the
    8,000-group chain)."""
    texts = shipped_texts()
    base = texts["four_bar"]
    no_groups = base[: base.index("groups:")] + "groups:\n" + base[base.index("joints:") :]
    for where, old in (
        ("units", "{length: m, angle: deg}"),
        ("fixed point", "[0.0, 0.0]"),
        ("lengths", "[0.4, 0.3]"),
        ("outputs.points", "[A, B]"),
        ("scene name", "four_bar\n"),
    ):
        yield (
            f"bomb as {where}",
            (BOMB + base.replace(old, "*l8" + ("\n" if old.endswith("\n") else ""), 1)).encode(),
            False,
        )
    yield (
        "bomb as provenance",
        (BOMB + base.replace("provenance: >-", "provenance: *l8\nxprovenance: >-", 1)).encode(),
        False,
    )
    yield "lengths 1.0e+154", base.replace("[0.4, 0.3]", "[1.0e+154, 0.3]").encode(), False
    yield "lengths 1e200", base.replace("[0.4, 0.3]", "[1.0e+200, 1.0e+200]").encode(), False
    yield "integer 10**29", base.replace("length: 0.1}", f"length: {10**29}}}").encode(), False
    yield "integer 10**29 fixed", base.replace("C: [0.4, 0.0]", f"C: [{10**29}, 0.0]").encode(), False
    yield "groups empty", no_groups.encode(), False
    yield "groups: 7", no_groups.replace("groups:\n", "groups: 7\n").encode(), False
    yield "latin-1", base.replace("–", "-").encode("utf-8").replace(b"four_bar\n", b"four_b\xe4r\n", 1), False
    yield "binary", bytes(range(256)) * 64, False
    for depth in (20_000, 100_000) if big else (20_000,):
        yield f"nested {depth}", (base + "description: " + "[" * depth + "]" * depth + "\n").encode(), False
        yield (
            f"nested map {depth}",
            (base + "description: " + "{a: " * depth + "1" + "}" * depth + "\n").encode(),
            False,
        )
    yield "M twice", base.replace("M: +1}", "M: +1, M: -1}").encode(), True
    yield "fixed point twice", base.replace("  C: [0.4, 0.0]\n", "  C: [0.4, 0.0]\n  C: [0.5, 0.0]\n").encode(), True
    yield "length 1e-3", base.replace("length: 0.1}", "length: 1e-3}").encode(), False
    for typo, right in (("lenghts:", "lengths:"), ("gropus:", "groups:"), ("joint:\n", "joints:\n")):
        yield f"misspelt {typo.strip()}", base.replace(right, typo, 1).encode(), False
    yoke = texts["vectors/pl2_scotch_yoke"]
    yield "parallel slides", yoke.replace("YA: {r: unknown, alpha: 90}", "YA: {r: unknown, alpha: 0}").encode(), False
    yield "huge file", b"a: " + b"x" * (5 << 20) + b"\n", False
    fixed_dyad = base.replace("  C: [0.4, 0.0]\n", "  C: [0.4, 0.0]\n  F: [5.0, 0.0]\n").replace(
        "groups:\n", "groups:\n  - {type: rrr, name: tri, ends: [O, F], point: T, lengths: [0.4, 0.3], M: +1}\n"
    )
    yield "a dyad between fixed points", fixed_dyad.encode(), False
    yield (
        "two fixed points at one place as a joint",
        base.replace("  C: [0.4, 0.0]\n", "  C: [0.4, 0.0]\n  P: [0.0, 0.0]\n")
        .replace("  rocker: {angle: [C, B]}\n", "  rocker: {angle: [C, B]}\n  zero: {angle: [O, P]}\n")
        .encode(),
        False,
    )
    yield "recursive alias", ("a: &a [*a]\n" + base).encode(), False
    if big:
        yield "chain 4000", _chain(4000), False
        yield "chain 8000", _chain(8000), False


def _nonfinite(k: Any, rows: Any, names: tuple[str, ...], point: bool) -> int:
    bad = 0
    for n in names:
        m = k.point(n) if point else k.joint(n)
        for arr in (m.position, m.velocity, m.acceleration):
            a = np.asarray(arr, float)
            a = a[rows] if np.ndim(rows) else (a if bool(rows) else a.reshape(-1)[:0])
            bad += int(np.count_nonzero(~np.isfinite(a)))
    return bad


def examine(path: Path, *, cli: bool = True) -> dict[str, Any]:
    """Load, solve (vectorised and per tick, in mask mode) and run ``linkage-solve`` on one file.

    ``outcome``: "loaded", "rejected" (a SceneError) or "traceback" (anything else escaped);
    ``nonfinite``: values that are not finite at samples reported valid and not singular;
    ``multiline``: an error message of more than one line; ``cli``: linkage-solve's exit status,
    or "traceback" when an exception escaped it."""
    out: dict[str, Any] = {"outcome": "", "message": "", "nonfinite": 0, "multiline": False, "cli": None}
    try:
        scene = solver.load_scene(path)
    except solver.SceneError as exc:
        out.update(outcome="rejected", message=str(exc), multiline="\n" in str(exc))
    except Exception:
        out.update(outcome="traceback", message=traceback.format_exc()[-1500:])
    else:
        out["outcome"] = "loaded"
        try:
            every = scene.everything()
            inputs = len(getattr(scene, "inputs", ())) or 1
            grid = np.linspace(0.0, 2 * math.pi, 181)
            phi = grid if inputs == 1 else np.stack([grid + 0.37 * i for i in range(inputs)], axis=1)
            k = every.solve(phi, omega=1.3, epsilon=0.7, mask=True)
            rows = np.asarray(k.valid, bool) & ~np.asarray(k.singular, bool)
            bad = _nonfinite(k, rows, every.output_points, True) + _nonfinite(k, rows, every.output_joints, False)
            for p in (0.3, 2.0, 4.5):
                ks = every.solve(p if inputs == 1 else np.full(inputs, p), omega=1.3, epsilon=0.7, mask=True)
                ok = bool(np.asarray(ks.valid)) and not bool(np.asarray(ks.singular))
                bad += _nonfinite(ks, ok, every.output_points, True) + _nonfinite(ks, ok, every.output_joints, False)
            out["nonfinite"] = bad
            out["valid"] = int(rows.sum())
        except solver.SolverError as exc:
            out["solve_error"] = str(exc)[:300]
            out["multiline"] = "\n" in str(exc)
        except Exception:
            out.update(outcome="traceback", message=traceback.format_exc()[-1500:])
    if cli:
        err, std = io.StringIO(), io.StringIO()
        try:
            with contextlib.redirect_stderr(err), contextlib.redirect_stdout(std):
                code = solve_main([str(path), "--phi-count", "60"])
            out["cli"] = code
            lines = err.getvalue().strip().splitlines()
            if code != 0 and len(lines) != 1:
                out["cli_lines"] = len(lines)
            if code == 0 and any(w in std.getvalue() for w in (" nan", " inf", "-inf")):
                out["cli_nonfinite"] = True
        except SystemExit as exc:
            out["cli"] = exc.code
        except Exception:
            out["cli"] = "traceback"
            out["cli_message"] = traceback.format_exc(limit=-4)[-2000:]
    return out
