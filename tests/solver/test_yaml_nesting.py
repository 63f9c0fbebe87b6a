"""Deep nesting is refused with the reader's own message, whichever YAML parser is installed."""

from __future__ import annotations

from typing import Any

import pytest

import solver
from solver import _yaml
from solver._yaml import MAX_DEPTH, parse_yaml

_HAS_LIBYAML = len(_yaml._LOADERS) > 1


def _flow_list(depth: int) -> str:
    return "a: " + "[" * depth + "]" * depth + "\n"


def _flow_map(depth: int) -> str:
    return "a: " + "{a: " * depth + "1" + "}" * depth + "\n"


def _block(depth: int) -> str:
    return "".join(" " * i + "a:\n" for i in range(depth)) + " " * depth + "1\n"


@pytest.fixture(params=["libyaml", "pure-python"])
def parser(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> str:
    if request.param == "libyaml":
        if not _HAS_LIBYAML:
            pytest.skip("PyYAML here is built without libyaml")
    else:
        monkeypatch.setattr(_yaml, "_LOADERS", (_yaml._Loader,))
    return str(request.param)


@pytest.mark.parametrize("depth", [MAX_DEPTH + 1, 1_001, 100_000])
@pytest.mark.parametrize("shape", [_flow_list, _flow_map, _block])
def test_nesting_deeper_than_the_limit_is_refused_in_the_readers_words(parser: str, shape: Any, depth: int) -> None:
    if shape is _block and depth > 2_000:
        depth = 2_000  # indentation grows quadratically: 2,000 levels are 2 MB
    with pytest.raises(solver.SceneError, match=rf"^x\.yaml:\d+: refused: nested more than {MAX_DEPTH} levels deep$"):
        parse_yaml(shape(depth), file="x.yaml")


@pytest.mark.parametrize(("shape", "extra"), [(_flow_list, 1), (_flow_map, 2), (_block, 1)])
def test_nesting_exactly_at_the_limit_is_read_and_one_more_level_is_not(parser: str, shape: Any, extra: int) -> None:
    # `extra`: the levels a shape adds around its `depth` nested collections (the top mapping, a scalar)
    depth = MAX_DEPTH - extra
    data = parse_yaml(shape(depth))
    levels = 1
    while isinstance(data, (dict, list)) and data:
        data = data["a"] if isinstance(data, dict) else data[0]
        levels += 1
    assert levels == MAX_DEPTH
    with pytest.raises(solver.SceneError, match=r"nested more than 64 levels deep"):
        parse_yaml(shape(depth + 1))


class _ShallowCParser(_yaml._Loader):
    """A stand-in for a libyaml that refuses nesting on its own, at a depth below ours."""

    def __init__(self, stream: str) -> None:
        import yaml

        if stream.count("[") > 8:
            raise yaml.scanner.ScannerError(None, None, "exceeded maximum nesting depth", None)
        super().__init__(stream)


def test_a_c_parser_that_refuses_nesting_itself_does_not_change_the_outcome(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(_yaml, "_LOADERS", (_ShallowCParser, _yaml._Loader))
    with pytest.raises(solver.SceneError, match=rf"refused: nested more than {MAX_DEPTH} levels deep$"):
        parse_yaml(_flow_list(100_000), file="x.yaml")
    # and a file it refuses that is within our limits is read all the same
    assert parse_yaml(_flow_list(20))["a"] == [[[[[[[[[[[[[[[[[[[[]]]]]]]]]]]]]]]]]]]]


def test_syntax_errors_read_the_same_with_either_parser(monkeypatch: pytest.MonkeyPatch) -> None:
    text = "groups: [unclosed\nunits: {}\n"
    with pytest.raises(solver.SceneError) as fast:
        parse_yaml(text, file="x.yaml")
    monkeypatch.setattr(_yaml, "_LOADERS", (_yaml._Loader,))
    with pytest.raises(solver.SceneError) as pure:
        parse_yaml(text, file="x.yaml")
    assert str(fast.value) == str(pure.value)
    assert "while parsing a flow sequence on line 1" in str(pure.value)
