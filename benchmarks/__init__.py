"""Benchmarks of caster-designer: ``python -m benchmarks.run [--quick]``; the suite runs ``--quick`` as a smoke test
(tests/test_benchmarks.py), asserting the tables, never a time."""
