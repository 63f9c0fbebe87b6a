"""Dependencies in solver/ point one way: no module imports a higher layer, not even in a function.

Layers, from the bottom (docs/architecture.md, "Dependencies point one way"): errors and
tolerances and the backend ← jets and the tracer (and its paths' tree) ← groups ← plan ←
singular positions and the force layer ← assembly intervals and results ← several inputs and
scene reading ← the compiled instant ← scene ← summaries, classification and the CLI. Imports
inside ``if TYPE_CHECKING:`` count too: a lower module names the scene's type as an alias of
``Any`` instead of importing it.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2] / "solver"

#: module (or package prefix) → layer; a module may import its own layer or lower ones
LAYERS: dict[str, int] = {
    "solver.errors": 0,
    "solver.tolerances": 0,
    "solver._backend": 0,
    "solver._yaml": 0,
    "solver._fields": 0,
    "solver.jet": 1,
    "solver._trace": 1,
    "solver.tracing": 1,  # the tracer's public face (re-exports solver._trace)
    "solver._paths": 1,
    "solver.groups": 2,
    "solver.vectors.terms": 2,
    "solver.vectors.analogs": 2,
    "solver.vectors.pl1": 2,
    "solver.vectors.pl2": 2,
    "solver.vectors.pl3": 2,
    "solver.vectors.pl4": 2,
    "solver.vectors.nodes": 2,
    "solver.vectors.contour": 2,
    "solver.vectors.parse": 2,
    "solver.plan": 3,
    "solver._inputs": 3,
    "solver.singular": 4,
    "solver.forces": 4,
    "solver.assembly": 5,
    "solver.kinematics": 5,
    "solver.multi": 6,
    "solver._loader": 6,
    "solver.vectors": 7,  # the package: registers its scene section with the loader
    "solver._codegen": 7,
    "solver.scene": 8,
    "solver": 9,
}


def _layer(module: str) -> int:
    best = ""
    for name in LAYERS:
        if (module == name or module.startswith(name + ".")) and len(name) > len(best):
            best = name
    return LAYERS[best] if best else 9  # summaries, classification, the CLI: the top


def _module(path: Path) -> str:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path) -> list[tuple[str, int]]:
    """Every solver module ``path`` imports (module level and inside functions), with its line."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip: set[int] = set()  # (TYPE_CHECKING imports are upward imports as well)
    me = _module(path)
    package = me if path.name == "__init__.py" else me.rpartition(".")[0]
    out = []
    for node in ast.walk(tree):
        if getattr(node, "lineno", None) in skip:
            continue
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                target = ".".join(base + ([node.module] if node.module else []))
            else:
                target = node.module or ""
            names = [target] if node.module else [f"{target}.{a.name}" for a in node.names]
            out.extend((n, node.lineno) for n in names if n.startswith("solver"))
        elif isinstance(node, ast.Import):
            out.extend((a.name, node.lineno) for a in node.names if a.name.startswith("solver"))
    return out


MODULES = sorted(ROOT.rglob("*.py"))


@pytest.mark.parametrize("path", MODULES, ids=lambda p: str(p.relative_to(ROOT.parent)))
def test_no_module_imports_a_higher_layer(path: Path) -> None:
    me = _module(path)
    upward = [
        f"line {line}: {target} (layer {_layer(target)} above {me}'s {_layer(me)})"
        for target, line in _imports(path)
        if _layer(target) > _layer(me)
    ]
    assert not upward, "\n".join(upward)


def test_the_groups_never_reach_for_the_plan_the_singular_analysis_or_the_scene() -> None:
    # the cycle this replaced: groups → singular → plan → groups (solver.singular is now called by
    # whoever runs the plan: Plan.run asks the owning scene to refine a singular group)
    for path in sorted((ROOT / "groups").glob("*.py")):
        targets = {t for t, _ in _imports(path)}
        assert not targets & {"solver.plan", "solver.singular", "solver.scene", "solver.multi", "solver.assembly"}, path


def test_every_solver_module_has_a_layer_or_is_at_the_top() -> None:
    tops = {_module(p) for p in MODULES if _layer(_module(p)) == 9}
    tops = {t for t in tops if not t.startswith("solver.synthesis")}  # synthesis: on top of the scene
    assert tops <= {"solver.synth_cli",
                    "solver", "solver.classify", "solver.summary", "solver._extremes", "solver._cmdline",
                    "solver.cli", "solver.cli_inputs"}, tops
