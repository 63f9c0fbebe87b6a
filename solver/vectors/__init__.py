"""Seed 004's vector model: closed vector contours solved as planar modules Пл1–Пл4, Пл1s–Пл4s.

Importing this package registers the ``vector_model:`` scene section (see :mod:`.parse` and
docs/scenes.md, "Vector-loop scenes"). Each contour becomes a group of the ordinary plan, so a
vector scene has the same outputs, API, CLI and exact analogs as a group scene.
"""

from __future__ import annotations

from .._loader import SECTION_PARSERS
from .contour import SOLUTIONS, Contour
from .nodes import VectorInput, VectorJoint, VectorPoint
from .parse import SECTION, parse_vector_model

__all__ = ["Contour", "SOLUTIONS", "SECTION", "VectorInput", "VectorJoint", "VectorPoint", "parse_vector_model"]

SECTION_PARSERS[SECTION] = parse_vector_model
