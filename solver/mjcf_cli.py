"""``linkage-mjcf SCENE -o model.xml [--phi V[,V…]] [--deg]``: a planar scene as MJCF (solver.models.export).

The scene (a file, a shipped scene's name, or a model file) is written posed at the inputs
``--phi`` (rad, or degrees with ``--deg``; default 0), its loops closed by ``<connect>``
equalities, its bodies' inertias and its inputs as ``<motor>`` actuators. Importing the file
(``solver.load_scene("model.xml")``) gives back the scene. One line and exit 2 for a fault.
"""

from __future__ import annotations

import argparse
import math
import sys
from collections.abc import Sequence

from ._cmdline import PHI_MAX, Parser, bounded, check_output, error_line, write_out
from .errors import SolverError
from .models.export import scene_to_mjcf
from .scene import load_scene

__all__ = ["main"]


def _parser() -> argparse.ArgumentParser:
    p = Parser(prog="linkage-mjcf", description="Write a planar scene as an MJCF model with <connect> loop closures.")
    p.add_argument("scene", help="scene file, shipped scene name, or model file")
    p.add_argument("-o", "--output", default="-", help="the MJCF file to write (default: standard output)")
    p.add_argument("--phi", help="the inputs' values to pose the model at, comma-separated (rad; default 0)")
    p.add_argument("--deg", action="store_true", help="--phi in degrees")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(sys.argv[1:] if argv is None else list(argv))
    try:
        if args.output != "-":
            check_output(args.output, "--output")
        scene = load_scene(args.scene)
        phi = None
        if args.phi is not None:
            try:
                phi = [bounded(PHI_MAX)(v) for v in args.phi.split(",") if v.strip()]
            except argparse.ArgumentTypeError as exc:
                raise SolverError(f"--phi {args.phi!r}: {exc}") from None
            if args.deg:
                phi = [math.radians(v) for v in phi]
        text = scene_to_mjcf(scene, phi=phi)
        write_out(text, args.output)
    except BrokenPipeError:
        raise  # the reader went away (`| head`): quiet_pipe ends quietly
    except (SolverError, ValueError, OSError) as exc:
        return error_line("linkage-mjcf", exc)
    return 0


if __name__ == "__main__":
    sys.exit(main())
