"""Dependencies in solver/ and linkage_ros/ point one way: no module imports a higher layer, not
even in a function.

Layers, from the bottom (docs/architecture.md, "Dependencies point one way"): errors and
tolerances and the backend ← jets and the tracer (and its paths' tree) ← groups ← plan ←
singular positions and the force layer ← assembly intervals and results ← several inputs and
scene reading ← the compiled instant ← scene ← dynamics ← summaries, classification and the CLI. Imports
inside ``if TYPE_CHECKING:`` count too: a lower module names the scene's type as an alias of
``Any`` instead of importing it.

linkage_ros/ (its own table, :data:`ROS_LAYERS`), from the bottom: frames, time laws, message
classes and the arrow rule ← the force layout, the URDF tree's types and states, the drawings'
helpers ← the engine, the tree builders, the recorded forces ← topics, the URDF model, the rerun
view ← load messages ← the message builder ← serialisation ← the instant ← the runtime, the CLI
and the node. It imports solver/ freely (solver/ never imports it).
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
    "solver._arguments": 0,  # the public functions' argument checks (errors only)
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
    "solver.structure": 5,  # the drawn form → groups (the loader reads a drawing through it)
    "solver.structure.export": 9,  # a scene drawn at given inputs: solves the scene
    "solver._loader": 6,
    "solver.vectors": 7,  # the package: registers its scene section with the loader
    "solver._codegen": 7,
    "solver.scene": 8,
    "solver.classify": 9,  # Grashof type, dead centres of a scene (the summaries and synthesis read it)
    "solver.dynamics": 9,  # forward and machine dynamics, on the scene (Scene.simulate is a door into it)
    "solver.models": 9,  # MJCF / URDF importers → scene data → Scene (load_scene of a model file is a door into it)
    "solver.synthesis": 9,  # dimensional synthesis, on the scene (solver.synthesize is a door into it)
    "solver": 10,
}


def _layer(module: str) -> int:
    best = ""
    for name in LAYERS:
        if (module == name or module.startswith(name + ".")) and len(name) > len(best):
            best = name
    return LAYERS[best] if best else 10  # summaries, classification, the CLI: the top


def _module(path: Path, root: Path = ROOT) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _imports(path: Path, root: Path = ROOT) -> list[tuple[str, int]]:
    """Every module of ``root``'s package (solver) that ``path`` imports (module level and inside
    functions), with its line."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    skip: set[int] = set()  # (TYPE_CHECKING imports are upward imports as well)
    me, top = _module(path, root), root.name
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
            out.extend((n, node.lineno) for n in names if n.split(".")[0] == top)
        elif isinstance(node, ast.Import):
            out.extend((a.name, node.lineno) for a in node.names if a.name.split(".")[0] == top)
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
    tops = {_module(p) for p in MODULES if _layer(_module(p)) == 10}
    assert tops <= {"solver.synth_cli", "solver.structure_cli", "solver.mjcf_cli",
                    "solver", "solver.summary", "solver._extremes", "solver._cmdline",
                    "solver.cli", "solver.cli_inputs"}, tops


# ---------------------------------------------------------------------------------- linkage_ros
ROS_ROOT = ROOT.parent / "linkage_ros"
ROS_TOP = 10
#: linkage_ros module → layer (a module not listed is at the top, :data:`ROS_TOP`)
ROS_LAYERS: dict[str, int] = {
    # data, time laws, message classes, the arrow rule; the run's arrays; the URDF tree's types
    "linkage_ros.frame": 0,
    "linkage_ros.motion": 0,
    "linkage_ros.msgtypes": 0,
    "linkage_ros.arrows": 0,
    "linkage_ros._sentinels": 0,
    "linkage_ros._relay_rates": 0,
    "linkage_ros.record": 0,  # the package (lazy: imports nothing)
    "linkage_ros.record.rundata": 0,
    "linkage_ros.record.cdr": 0,
    "linkage_ros.record.rosbag2": 0,
    "linkage_ros.urdf.tree": 0,
    "linkage_ros.record.viewer": 0,
    # the force layout, the tree joints' states, the drawings' helpers, reading an MCAP
    "linkage_ros.forces": 1,
    "linkage_ros.urdf.states": 1,
    "linkage_ros.urdf.inertial": 1,  # a link's inertial from the scene's bodies (on the tree's types)
    "linkage_ros.urdf.vector_bodies": 1,
    "linkage_ros.record._drawing": 1,
    "linkage_ros.record.mcap_read": 1,
    "linkage_ros.dynamic": 1,  # the dynamic time law (a Motion over solver.dynamics' Stepper)
    "linkage_ros.record.dynamic_run": 1,  # a simulated run as a time law, its summary
    # the engine, the tree of a vector scene, the URDF text, the recorded forces
    "linkage_ros.engine": 2,
    "linkage_ros.urdf.vectors": 2,
    "linkage_ros.urdf.writer": 2,
    "linkage_ros.record.forces": 2,
    "linkage_ros.record.energy": 2,  # the energy plots of a dynamic run
    "linkage_ros.record.friction": 2,  # the friction losses and efficiency plots
    # topic tables, the tree of a group scene, the rerun view, replay
    "linkage_ros": 3,
    "linkage_ros.topics": 3,
    "linkage_ros.urdf.model": 3,
    "linkage_ros.record.rerun": 3,
    "linkage_ros.record.replay": 3,
    "linkage_ros.urdf": 4,
    "linkage_ros.load_messages": 5,
    "linkage_ros.relay": 5,
    "linkage_ros._relay_joint": 5,  # the relay's input joints: the URDF tree's rod joints (linkage_ros.urdf)
    "linkage_ros._cli_common": 5,
    "linkage_ros.messages": 6,
    "linkage_ros.parameters": 6,
    "linkage_ros._cli_recorded": 6,
    "linkage_ros.serialize": 7,
    "linkage_ros._derived": 8,
    "linkage_ros.record.mcap": 8,
    "linkage_ros.instant": 9,
    "linkage_ros.record.run": 9,
    # the top: runtime, CLI, node, echo, linkage-urdf's __main__
}


def _ros_layer(module: str) -> int:
    return ROS_LAYERS.get(module, ROS_TOP)


ROS_MODULES = sorted(ROS_ROOT.rglob("*.py"))


@pytest.mark.parametrize("path", ROS_MODULES, ids=lambda p: str(p.relative_to(ROS_ROOT.parent)))
def test_no_linkage_ros_module_imports_a_higher_layer(path: Path) -> None:
    me = _module(path, ROS_ROOT)
    upward = [
        f"line {line}: {target} (layer {_ros_layer(target)} above {me}'s {_ros_layer(me)})"
        for target, line in ((_ros_target(t), line) for t, line in _imports(path, ROS_ROOT))
        if _ros_layer(target) > _ros_layer(me)
    ]
    assert not upward, "\n".join(upward)


def _ros_target(name: str) -> str:
    """The module ``from linkage_ros.x import y`` reaches: ``linkage_ros.x.y`` when that is a
    module, else ``linkage_ros.x``."""
    known = {_module(p, ROS_ROOT) for p in ROS_MODULES}
    while name not in known and "." in name:
        name = name.rpartition(".")[0]
    return name


def test_linkage_ros_has_no_import_circle() -> None:
    # whatever the table says: a walk of the whole graph (module level, in functions, TYPE_CHECKING)
    graph = {_module(p, ROS_ROOT): {_ros_target(t) for t, _ in _imports(p, ROS_ROOT)} for p in ROS_MODULES}
    state: dict[str, int] = {}  # 1: on the walk's path, 2: done

    def walk(m: str, path: list[str]) -> None:
        state[m] = 1
        for t in sorted(graph.get(m, ())):
            if t == m:
                continue
            assert state.get(t) != 1, "import circle: " + " → ".join(path[path.index(t):] + [m, t])
            if t not in state:
                walk(t, path + [m])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            walk(m, [])


def test_solver_never_imports_linkage_ros() -> None:
    found = [f"{_module(p)} line {line}" for p in MODULES for _, line in _imports(p, ROS_ROOT)]
    assert not found, found
