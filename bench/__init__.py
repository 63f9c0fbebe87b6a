"""Benchmarks: speed against error of the solver, its alternatives and its peers (scripts, not tests).

Entry point: ``python -m bench.speed_vs_error [--quick]`` rewrites ``docs/speed-vs-error.md`` and
``docs/speed-vs-error.png``.
"""
