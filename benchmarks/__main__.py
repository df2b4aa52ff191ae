"""``python -m benchmarks NAME [options]``: run ``benchmarks.NAME.main``."""

from __future__ import annotations

import importlib
import sys


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in {"-h", "--help"}:
        print("usage: python -m benchmarks "
              "{dynamics,damped,motions,resolution,coldstart,paper_cost,"
              "monitors,surface_holdout,portfolio,unidirectional} [options]")
        return 0 if argv else 2
    name, rest = argv[0], argv[1:]
    try:
        module = importlib.import_module(f"benchmarks.{name}")
    except ModuleNotFoundError:
        print(f"unknown benchmark {name!r}", file=sys.stderr)
        return 2
    return int(module.main(rest) or 0)


if __name__ == "__main__":
    raise SystemExit(main())
