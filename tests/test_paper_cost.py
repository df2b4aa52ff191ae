"""The paper-cost benchmark: rule times read from Snakemake logs, and a point searched with
and without the early end of decided analyses (counts, identity)."""

import numpy as np
import pytest

import rocking
from benchmarks import paper_cost
from rocking.motions.motion import GroundMotion

LOG = """\
Building DAG of jobs...

[Wed Nov 25 03:41:00 2026]
localrule motions:
    output: results/motions/elcentro.nc
    log: logs/motions/elcentro.log
    jobid: 4
    reason: Missing output files
    wildcards: ensemble=elcentro
    resources: tmpdir=/tmp

[Wed Nov 25 03:41:35 2026]
Finished jobid: 4 (Rule: motions)
1 of 3 steps (33%) done

[Wed Nov 25 03:41:35 2026]
localrule stripes:
    jobid: 7
    wildcards: study=elcentro
    threads: 2

[Wed Nov 25 03:41:38 2026]
Error in rule stripes:
    message: None
    jobid: 7
"""


def test_rule_times_reads_starts_ends_and_failures(tmp_path):
    logdir = tmp_path / ".snakemake" / "log"
    logdir.mkdir(parents=True)
    (logdir / "2026-11-25T034056.snakemake.log").write_text(LOG)
    df = paper_cost.rule_times(tmp_path)
    assert list(df["rule"]) == ["motions", "stripes"]  # the error block is no second job
    assert df["seconds"].iloc[0] == 35.0 and df["wildcards"].iloc[0] == "ensemble=elcentro"
    assert np.isnan(df["seconds"].iloc[1])  # never finished


def test_rule_times_without_logs_names_the_directory(tmp_path):
    with pytest.raises(ValueError, match=r"\.snakemake"):
        paper_cost.rule_times(tmp_path)


def test_search_pair_counts_and_finds_the_answers_identical():
    m = rocking.load_motion("el-centro-1940")
    pad = np.zeros(3000)
    padded = GroundMotion(np.concatenate([m.ax, pad]), np.concatenate([m.ay, pad]), m.dt, "p")
    row = paper_cost.search_pair(rocking.Cylinder(4.0, 0.2), padded, ["tilt:1/3"], "3d",
                                 20.0, "default")
    assert row["identical"]
    assert row["analyses_before"] == row["analyses_after"] > 3
    assert row["steps_after"] < row["steps_before"]
