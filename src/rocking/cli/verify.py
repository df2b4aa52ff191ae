"""``rocking verify``: a run's tables held against the committed gallery, table by table.

For every table of the gallery's studies (critical.csv, mean_spectra.csv, fragility.csv,
...) one line: identical (reported, never required across machines) / within the answers'
stated error / differs beyond it (the rows beyond named). Exit 0 when no table differs
beyond the stated error, 1 when some table does, 2 on a folder that is no run, a partial
run or a run of another configuration (one line naming the folder and what is missing or
which keys differ). The comparison and its
tolerances: :mod:`rocking.study.verify` (docs/cli.md, "rocking verify").
"""

from __future__ import annotations

from pathlib import Path

from rocking.cli import _common

EXAMPLES = """\
  snakemake --cores 2 --configfile config/paper.yaml && rocking verify results
  rocking verify results --against results/paper --show 10"""


def add_parser(subparsers) -> None:
    """Register the ``verify`` subcommand."""
    p = _common.add_command(
        subparsers, "verify", examples=EXAMPLES,
        help="compare a run's tables with the committed gallery",
        description="Compare the tables of a run (its output folder) with those of a gallery "
        "(results/paper), table by table: identical (bit for bit: reported, never required "
        "across machines), within the answers' stated error (the accuracy preset's: a share "
        "q of its answers within e of the converged I10, so two runs' answers within 2e in "
        "all but 2(1 - q) of them, propagated to means, medians, fragilities and risk), or "
        "beyond it (rows named; exit code 1).",
    )
    p.add_argument("run", type=Path, metavar="RUN_DIR",
                   help="the run's output folder (e.g. results), or a gallery-like copy")
    p.add_argument("--against", type=Path, default=Path("results/paper"),
                   help="the gallery to compare with")
    p.add_argument("--show", type=int, default=5,
                   help="rows named per table that differ beyond their tolerance")
    p.set_defaults(func=run)


def run(args) -> int:
    from rocking.study.verify import format_verdicts, motions_lines, verify_run

    if args.show < 0:
        raise ValueError(f"--show must be >= 0, got {args.show}")
    verdicts = verify_run(args.run, args.against)
    for line in [*motions_lines(args.run, args.against), *format_verdicts(verdicts, args.show)]:
        print(line)
    beyond = [v.table for v in verdicts if v.verdict == "beyond"]
    same = sum(v.verdict == "identical" for v in verdicts)
    print(f"bit-identical: {same} of {len(verdicts)} tables (one machine and one process "
          "order give identical tables; another machine need not)")
    if beyond:
        print(f"{len(beyond)} of {len(verdicts)} tables differ beyond the answers' stated "
              f"error: {', '.join(beyond)}")
        return 1
    print(f"all {len(verdicts)} tables of {args.against} agree with {args.run} within the "
          "answers' stated error")
    return 0
