"""Benchmarks: ``python -m benchmarks <name>`` writes ``results/benchmarks/<name>.csv``
and ``<name>.md``. They measure; they never assert."""
