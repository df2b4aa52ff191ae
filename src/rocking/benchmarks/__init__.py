"""Benchmarks: ``python -m rocking.benchmarks <name>`` writes ``results/benchmarks/<name>.csv``
and ``<name>.md``. They measure; they never assert."""
