"""A safe YAML reader for scene files: bounded in time and memory, strict about keys.

PyYAML's ``safe_load`` refuses arbitrary objects but not the other ways a file can hurt: an
anchor "bomb" (a few lines of aliases that expand to 10⁹ nodes once anything walks the
structure), nesting 100,000 deep (a RecursionError in the composer), a file of hundreds of MB,
bytes that are not UTF-8, and a key given twice (silently last-wins). :func:`load_yaml` refuses
each of these with one :class:`~solver.errors.SceneError` line naming the file and the line:

* the file is read up to :data:`MAX_BYTES` and must be UTF-8 text (a BOM is allowed) without NULs;
* nesting deeper than :data:`MAX_DEPTH` is refused before the composer recurses, with the same
  message whichever PyYAML and libyaml are installed (a file the C parser refuses is read again
  by the pure-Python parser, see :func:`_read`);
* the structure, with every alias expanded, may hold at most :data:`MAX_NODES` nodes and use at
  most :data:`MAX_ALIASES` aliases; the expanded size is counted while composing (an alias adds
  the size of the node it repeats), so a bomb is refused after reading its few lines, before
  anything expands; an alias to a node that contains it (a recursive structure) is refused;
* a mapping with a key twice is refused, naming both lines (keys merged in with ``<<`` may be
  overridden, as YAML's merge key intends).

Mappings and sequences come back as :class:`YamlMap` and :class:`YamlList`, a ``dict`` and a
``list`` that also know the line of every key and item (1-based), so that the loader's messages
can point at the line.
"""

from __future__ import annotations

import gc
import os
from typing import Any

import yaml
from yaml.composer import Composer
from yaml.constructor import SafeConstructor
from yaml.events import AliasEvent
from yaml.nodes import MappingNode, Node
from yaml.parser import Parser
from yaml.reader import Reader
from yaml.resolver import Resolver
from yaml.scanner import Scanner

from .errors import SceneError

__all__ = ["MAX_ALIASES", "MAX_BYTES", "MAX_DEPTH", "MAX_NODES", "YamlList", "YamlMap", "line_of", "load_yaml"]

#: Largest scene file read, bytes (a scene of 8,000 chained groups is about 0.8 MB).
MAX_BYTES = 4 << 20
#: Deepest nesting of mappings and sequences (a scene nests 5 deep).
MAX_DEPTH = 64
#: Most nodes in the document with every alias expanded.
MAX_NODES = 1_000_000
#: Most aliases (``*name``) in one document.
MAX_ALIASES = 10_000


class YamlMap(dict):  # type: ignore[type-arg]
    """A mapping from a YAML file: ``line`` where it starts, ``key_lines[key]`` of each key."""

    line: int | None = None
    key_lines: dict[Any, int]

    def __init__(self, *args: Any, **kwargs: Any) -> None:
        super().__init__(*args, **kwargs)
        self.key_lines = {}


class YamlList(list):  # type: ignore[type-arg]
    """A sequence from a YAML file: ``line`` where it starts, ``item_lines[i]`` of each item."""

    line: int | None = None
    item_lines: list[int]

    def __init__(self, *args: Any) -> None:
        super().__init__(*args)
        self.item_lines = []


def line_of(data: Any, key: Any = None) -> int | None:
    """The 1-based line of ``data[key]`` (or of ``data`` itself) where the file is known."""
    if key is not None:
        if isinstance(data, YamlMap) and key in data.key_lines:
            return data.key_lines[key]
        if isinstance(data, YamlList) and isinstance(key, int) and 0 <= key < len(data.item_lines):
            return data.item_lines[key]
    return getattr(data, "line", None)


class _Limit(yaml.YAMLError):
    def __init__(self, message: str, line: int | None) -> None:
        super().__init__(message)
        self.message, self.line = message, line


class _Composer(Composer):
    """PyYAML's composer with a depth limit and a count of the expanded size."""

    def __init__(self) -> None:
        super().__init__()
        self._depth = 0
        self._aliases = 0
        self._total = 0  # nodes so far, aliases expanded
        self._sizes: dict[int, int] = {}  # id(node) → expanded size, once composed

    def compose_node(self, parent: Node | None, index: Any) -> Any:
        if self.check_event(AliasEvent):  # type: ignore[attr-defined]
            line = self.peek_event().start_mark.line + 1  # type: ignore[attr-defined]
            node = super().compose_node(parent, index)
            self._aliases += 1
            if self._aliases > MAX_ALIASES:
                raise _Limit(f"more than {MAX_ALIASES:,} aliases", line)
            size = self._sizes.get(id(node))
            if size is None:
                raise _Limit("an alias refers to a node that contains it (a recursive structure)", line)
            self._count(size, line)
            return node
        self._depth += 1
        line = self.peek_event().start_mark.line + 1  # type: ignore[attr-defined]
        if self._depth > MAX_DEPTH:
            raise _Limit(f"nested more than {MAX_DEPTH} levels deep", line)
        before = self._total
        node = super().compose_node(parent, index)
        self._depth -= 1
        self._count(1, line)
        self._sizes[id(node)] = self._total - before
        return node

    def _count(self, n: int, line: int) -> None:
        self._total += n
        if self._total > MAX_NODES:
            raise _Limit(
                f"more than {MAX_NODES:,} values once its aliases are expanded (an alias 'bomb'?)", line
            )


class _Constructor(SafeConstructor):
    """SafeConstructor building :class:`YamlMap`/:class:`YamlList` and refusing duplicate keys."""

    def construct_yaml_map(self, node: MappingNode) -> Any:
        data = YamlMap()
        data.line = node.start_mark.line + 1
        yield data
        explicit = list(node.value)  # before merge keys (<<) are flattened in
        seen: dict[Any, int] = {}
        for key_node, _ in explicit:
            if key_node.tag == "tag:yaml.org,2002:merge":
                continue
            key = self.construct_object(key_node, deep=True)
            line = key_node.start_mark.line + 1
            try:
                first = seen.get(key)
            except TypeError:
                kind = "list" if isinstance(key, list) else "mapping" if isinstance(key, dict) else type(key).__name__
                raise _Limit(f"a mapping key must be a name, got a {kind}", line) from None
            if first is not None:
                raise _Limit(f"duplicate key '{_short(key)}' (first given on line {first})", line)
            seen[key] = line
        data.update(self.construct_mapping(node))
        for key_node, _ in node.value:
            key = self.construct_object(key_node, deep=True)
            data.key_lines.setdefault(key, key_node.start_mark.line + 1)
        for key, line in seen.items():
            data.key_lines[key] = line

    def construct_yaml_seq(self, node: Any) -> Any:
        data = YamlList()
        data.line = node.start_mark.line + 1
        yield data
        data.extend(self.construct_sequence(node))
        data.item_lines = [child.start_mark.line + 1 for child in node.value]


_Constructor.add_constructor("tag:yaml.org,2002:map", _Constructor.construct_yaml_map)  # type: ignore[type-var]
_Constructor.add_constructor("tag:yaml.org,2002:seq", _Constructor.construct_yaml_seq)  # type: ignore[type-var]


class _Loader(Reader, Scanner, Parser, _Composer, _Constructor, Resolver):
    def __init__(self, stream: str) -> None:
        Reader.__init__(self, stream)
        Scanner.__init__(self)
        Parser.__init__(self)
        _Composer.__init__(self)
        _Constructor.__init__(self)
        Resolver.__init__(self)


try:  # libyaml's event parser, about 4× faster; the composer (the limits) stays the one above
    from yaml._yaml import CParser as _CParser

    class _FastLoader(_CParser, _Composer, _Constructor, Resolver):  # type: ignore[misc]
        get_single_node = _Composer.get_single_node
        compose_document = _Composer.compose_document
        compose_node = _Composer.compose_node

        def __init__(self, stream: str) -> None:
            _CParser.__init__(self, stream)
            _Composer.__init__(self)
            _Constructor.__init__(self)
            Resolver.__init__(self)

    _LOADERS: tuple[Any, ...] = (_FastLoader, _Loader)
except ImportError:  # pragma: no cover - PyYAML without libyaml
    _LOADERS = (_Loader,)


def _short(value: Any, limit: int = 40) -> str:
    text = value if isinstance(value, str) else type(value).__name__
    return text if len(text) <= limit else text[: limit - 3] + "..."


def load_yaml(path: str | os.PathLike[str]) -> Any:
    """The document in ``path``, read within the limits above, or one SceneError line."""
    file = str(path)
    try:
        with open(path, "rb") as fh:
            raw = fh.read(MAX_BYTES + 1)
    except IsADirectoryError:
        raise SceneError("is a directory, not a scene file", file=file) from None
    except OSError as exc:
        raise SceneError(f"cannot read the scene file: {exc.strerror or exc}", file=file) from None
    if len(raw) > MAX_BYTES:
        raise SceneError(f"larger than {MAX_BYTES >> 20} MiB: not a scene file", file=file)
    return parse_yaml(raw, file=file)


def parse_yaml(raw: bytes | str, *, file: str | None = None) -> Any:
    """The YAML document in ``raw`` (bytes must be UTF-8), within the limits above."""
    if isinstance(raw, bytes):
        if b"\0" in raw:
            line = raw[: raw.index(b"\0")].count(b"\n") + 1
            raise SceneError("a binary file (a NUL byte), not YAML text", file=file, line=line)
        try:
            text = raw.decode("utf-8-sig")
        except UnicodeDecodeError as exc:
            line = raw[: exc.start].count(b"\n") + 1
            raise SceneError(
                f"not UTF-8 text (byte 0x{raw[exc.start]:02x}); save the file as UTF-8",
                file=file,
                line=line,
            ) from None
    else:
        text = raw
    if len(text) > MAX_BYTES:
        raise SceneError(f"larger than {MAX_BYTES >> 20} MiB: not a scene file", file=file)
    # The collector is paused while the tree is built: its young-generation passes rescan the
    # growing tree and make reading superlinear (8,000 groups: 1.2 s with it, 0.56 s without;
    # bench/load_scaling.py). What the tree can hold is bounded by the limits above.
    collecting = gc.isenabled()
    gc.disable()
    try:
        return _read(text, file)
    finally:
        if collecting:
            gc.enable()


def _read(text: str, file: str | None) -> Any:
    """The document, or the SceneError of the pure-Python parser whatever libyaml says.

    libyaml's own refusals depend on its version (PyYAML 6.0.4's C parser stops flow nesting
    itself, with "exceeded maximum nesting depth", before our composer sees the depth): when the
    fast loader fails, the text is read again by PyYAML's pure-Python parser, which has no limits
    of its own, so the refusal and its wording are ours (or that one parser's) on every version.
    The retry costs time only for a file that is refused anyway.
    """
    for loader_cls in _LOADERS:
        try:
            return _compose(loader_cls, text)
        except _Limit as exc:
            raise SceneError(f"refused: {exc.message}", file=file, line=exc.line) from None
        except yaml.YAMLError as exc:
            if loader_cls is not _Loader:
                continue
            if isinstance(exc, yaml.MarkedYAMLError):
                raise SceneError(_yaml_message(exc), file=file, line=_line(exc)) from None
            raise SceneError(f"not valid YAML: {_one_line(str(exc))}", file=file) from None
        except (ValueError, OverflowError) as exc:  # e.g. an integer of more than 4,300 digits, a bad date
            what = "an integer of more than 4,300 digits" if "digits" in str(exc) else _one_line(str(exc), 80)
            raise SceneError(f"not valid YAML: a value that cannot be read ({what})", file=file) from None
        except RecursionError:  # pragma: no cover - depth is limited above
            raise SceneError(f"refused: nested more than {MAX_DEPTH} levels deep", file=file) from None
    raise AssertionError("unreachable: the pure-Python loader is always the last")  # pragma: no cover


def _compose(loader_cls: Any, text: str) -> Any:
    loader = loader_cls(text)
    try:
        return loader.get_single_data()
    finally:
        loader.dispose()


def _line(exc: yaml.MarkedYAMLError) -> int | None:
    mark = exc.problem_mark or exc.context_mark
    return mark.line + 1 if mark is not None else None


def _yaml_message(exc: yaml.MarkedYAMLError) -> str:
    """PyYAML's 3–7 line report as one line: the problem, the column, and its context."""
    problem = _one_line(exc.problem or "syntax error")
    mark = exc.problem_mark
    where = f" (column {mark.column + 1})" if mark is not None else ""
    context = ""
    if exc.context:
        cm = exc.context_mark
        at = f" on line {cm.line + 1}" if cm is not None and mark is not None and cm.line != mark.line else ""
        context = f", {_one_line(exc.context)}{at}"
    return f"not valid YAML: {problem}{where}{context}"


def _one_line(text: str, limit: int = 160) -> str:
    text = " ".join(text.split())
    return text if len(text) <= limit else text[: limit - 3] + "..."
