"""Tracing a function of a scene's numbers into straight-line code: the public face of the tracer.

Run a function once on :class:`Tracer` values instead of floats and complex numbers, and a
:class:`Recorder` writes down each operation it did as one line of Python (``v7 = v3 * v5``), so
the lines, run on other numbers, perform the same operations and give the same bits. ``TRACE``
is the backend whose elementary functions (``TRACE.atan2``, ``TRACE.sin``, ``TRACE.call``) record
too; a comparison of a traced value leaves a :class:`Guard` (the outcome seen while tracing), and
whatever cannot be recorded (a conversion to a plain number, a numpy call) raises
:class:`TraceError`. :func:`fold_single_use` writes each temporary read once into its reader.
The compiled instant (:meth:`solver.Scene.compiled`) is built this way;
:mod:`linkage_ros._derived` traces the numbers a message builder derives from a frame with it.
"""

from __future__ import annotations

from ._paths import fold_single_use
from ._trace import TRACE, Guard, Recorder, TraceError, Tracer

__all__ = ["TRACE", "Guard", "Recorder", "TraceError", "Tracer", "fold_single_use"]
