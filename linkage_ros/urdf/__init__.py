"""URDF export of a scene and the exact joint states of its tree (``linkage-urdf``).

URDF describes trees; a linkage has loops. :func:`build_model` opens the mechanism into a spanning
tree rooted at ``base_link`` (one joint cut per loop, see :mod:`.model`), :func:`generate_urdf`
writes it with simple visuals and two fixed frames ``<cut>_a``/``<cut>_b`` per cut, and
:func:`tree_joint_states` gives the tree's joint positions and velocities from the solver's
points and joints, so that robot_state_publisher puts every link where the solver put it.

    linkage-urdf four_bar -o four_bar.urdf
"""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from solver import SolverError, load_scene
from solver._cmdline import Parser, check_output, one_line, quiet_pipe

from .model import BASE_LINK, SUPPORTED_GROUPS, Body, Cut, TreeJoint, TreeModel, build_model, exportable_model
from .states import TreeJointStates, frame_tree_joint_states, kinematics_tree_joint_states, tree_joint_states
from .writer import urdf_xml

__all__ = [
    "BASE_LINK",
    "SUPPORTED_GROUPS",
    "Body",
    "Cut",
    "TreeJoint",
    "TreeJointStates",
    "TreeModel",
    "build_model",
    "exportable_model",
    "frame_tree_joint_states",
    "generate_urdf",
    "kinematics_tree_joint_states",
    "main",
    "tree_joint_states",
]


def generate_urdf(scene: Any, *, frame_id: str = "world") -> str:
    """The URDF text of ``scene`` (a :class:`solver.Scene`, a path or a shipped scene name).

    ``frame_id`` is the root link (the node's ``frame_id``, where its markers are drawn); it
    holds ``base_link`` by a fixed identity joint unless it is ``base_link`` itself.
    """
    if not hasattr(scene, "ordered"):
        scene = load_scene(scene)
    model = build_model(scene)
    return urdf_xml(scene, model, frame_id=frame_id, provenance=str(getattr(scene, "provenance", "")))


def _parser() -> argparse.ArgumentParser:
    p = Parser(
        prog="linkage-urdf",
        description="Write the URDF of a linkage scene: the mechanism opened into a tree, with two "
        "fixed frames <cut>_a and <cut>_b at every cut joint.",
    )
    p.add_argument("scene", help="scene file, or the name of a shipped scene (e.g. four_bar)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (default: standard output)")
    p.add_argument("--frame-id", default="world", metavar="NAME",
                   help="root link, the node's frame_id (default: world); base_link hangs from it")
    return p


@quiet_pipe
def main(argv: Sequence[str] | None = None) -> int:
    """``linkage-urdf SCENE [-o FILE] [--frame-id NAME]``; returns the exit status (one line on
    stderr for a bad scene or output path; quiet when the reader of stdout goes away)."""
    args = _parser().parse_args(argv)
    try:
        if args.output:
            check_output(args.output, "-o")
        text = generate_urdf(args.scene, frame_id=args.frame_id)
        if args.output:
            Path(args.output).write_text(text, encoding="utf-8")
        else:
            sys.stdout.write(text)
    except BrokenPipeError:
        raise
    except (SolverError, ValueError) as exc:
        print(f"linkage-urdf: error: {one_line(str(exc))}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"linkage-urdf: error: {exc.filename or ''}: {exc.strerror or exc}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":  # pragma: no cover
    raise SystemExit(main())
