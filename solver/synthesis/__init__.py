"""Dimensional synthesis from template scenes (issue 23, docs/synthesis.md).

A template is a scene file with some numbers written ``{free: [lo, hi]}`` (:mod:`.template`); a
population of its designs is evaluated as arrays, candidates × samples in one pass of the plan
(:mod:`.population`); scipy's differential evolution searches the free values and
``least_squares`` polishes the best with the free phases as unknowns (:mod:`.search`,
:mod:`.polish`); every design returned is checked by solving its own scene (:mod:`.result`).
"""

from __future__ import annotations

from .api import synthesize
from .result import Design, SynthesisResult, same_curve
from .template import Free, Template, load_template

__all__ = ["Design", "Free", "SynthesisResult", "Template", "load_template", "same_curve", "synthesize"]
