"""Benchmarks: ``python -m benchmarks <name>`` writes ``docs/benchmarks/<name>.csv`` and
``<name>.md`` (where the documents link them; caches under ``results/benchmarks/``). They
measure; they never assert."""
