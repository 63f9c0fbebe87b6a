"""Bulk reading of numbers out of many CDR messages that share one layout.

A recorded topic repeats one message layout tick after tick: same strings, same sequence
lengths, only numbers change. :func:`extract` decodes one message per layout with the rosbags
type store, computes the byte offset of every numeric field by the CDR (XCDR1) alignment rules,
checks that every message of the group has the same bytes outside those numeric fields (so the
layout really is the same), and then reads the wanted fields of the whole group with one numpy
gather. Groups whose other bytes differ are decoded message by message instead.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ["Path", "extract", "numeric_leaves"]

Path = tuple[str | int, ...]
HEADER = 4  # CDR encapsulation header; alignment counts from after it
_SIZES = {"bool": 1, "byte": 1, "char": 1, "int8": 1, "uint8": 1, "int16": 2, "uint16": 2,
          "int32": 4, "uint32": 4, "int64": 8, "uint64": 8, "float32": 4, "float64": 8}
_DTYPES = {"float64": "<f8", "float32": "<f4", "int32": "<i4", "uint32": "<u4", "int64": "<i8",
           "uint64": "<u8", "int16": "<i2", "uint16": "<u2", "int8": "i1", "uint8": "u1",
           "bool": "u1", "byte": "u1", "char": "u1"}


def _align(pos: int, size: int) -> int:
    rel = pos - HEADER
    return HEADER + (rel + size - 1) // size * size


def numeric_leaves(typestore: Any, typename: str, msg: Any) -> dict[Path, tuple[int, str]]:
    """Every numeric field of ``msg``: path → (byte offset in the serialised message, type)."""
    out: dict[Path, tuple[int, str]] = {}
    pos = _walk(typestore, typename, msg, HEADER, (), out)
    out[("__size__",)] = (pos, "")
    return out


def _walk(ts: Any, typename: str, msg: Any, pos: int, path: Path,
          out: dict[Path, tuple[int, str]]) -> int:
    for name, (kind, detail) in ts.fielddefs[typename][1]:
        pos = _field(ts, kind.value, detail, getattr(msg, name), pos, (*path, name), out)
    return pos


def _field(ts: Any, kind: int, detail: Any, value: Any, pos: int, path: Path,
           out: dict[Path, tuple[int, str]]) -> int:
    if kind == 1:  # BASE
        base = detail[0]
        if base == "string" or base == "wstring":
            pos = _align(pos, 4)
            return pos + 4 + len(value.encode()) + 1
        size = _SIZES[base]
        pos = _align(pos, size)
        out[path] = (pos, base)
        return pos + size
    if kind == 2:  # NAME: nested message
        return _walk(ts, detail, value, pos, path, out)
    (sub_kind, sub_detail), _ = detail
    if kind == 4:  # SEQUENCE: uint32 count first
        pos = _align(pos, 4) + 4
    for i, item in enumerate(value):
        pos = _field(ts, sub_kind.value, sub_detail, item, pos, (*path, i), out)
    return pos


def extract(typestore: Any, typename: str, raws: Sequence[bytes],
            select: Callable[[Any], Sequence[Path]]) -> NDArray[np.float64]:
    """``(len(raws), k)`` float64: the ``k`` fields that ``select(first decoded message)`` names
    (paths of numeric fields), for every message. Messages are grouped by length; see the module
    docstring for the layout check and the fallback."""
    n = len(raws)
    by_len: dict[int, list[int]] = {}
    for i, raw in enumerate(raws):
        by_len.setdefault(len(raw), []).append(i)
    out: NDArray[np.float64] | None = None
    for length, idx in by_len.items():
        first = typestore.deserialize_cdr(raws[idx[0]], typename)
        paths = list(select(first))
        if out is None:
            out = np.empty((n, len(paths)))
        values = _gather(typestore, typename, first, [raws[i] for i in idx], length, paths)
        if values is None:
            values = np.array([[_get(typestore.deserialize_cdr(raws[i], typename), p) for p in paths]
                               for i in idx], dtype=float).reshape(len(idx), len(paths))
        out[idx] = values
    return out if out is not None else np.empty((0, 0))


def _gather(ts: Any, typename: str, first: Any, raws: list[bytes], length: int,
            paths: list[Path]) -> NDArray[np.float64] | None:
    leaves = numeric_leaves(ts, typename, first)
    if leaves.pop(("__size__",))[0] != length or any(p not in leaves for p in paths):
        return None
    rows = np.frombuffer(b"".join(raws), dtype=np.uint8).reshape(len(raws), length)
    fixed = np.ones(length, dtype=bool)
    for off, base in leaves.values():
        fixed[off: off + _SIZES[base]] = False
    if not (rows[:, fixed] == rows[0, fixed]).all():
        return None  # same length, different strings or counts: not one layout
    cols = []
    for p in paths:
        off, base = leaves[p]
        size = _SIZES[base]
        cols.append(np.ascontiguousarray(rows[:, off: off + size]).view(_DTYPES[base]).reshape(-1))
    return np.stack(cols, axis=1).astype(np.float64) if cols else np.empty((len(raws), 0))


def _get(msg: Any, path: Path) -> float:
    for key in path:
        msg = msg[key] if isinstance(key, int) else getattr(msg, key)
    return float(msg)
