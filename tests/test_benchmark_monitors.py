"""The monitors benchmark (:mod:`benchmarks.monitors`): interleaved trees, answers
compared to the bit."""

import pytest

from benchmarks import monitors


def test_two_copies_of_one_tree_give_the_same_answers():
    """One copy without the monitors (a study without μ), one with them: same bits."""
    tree = monitors.this_tree()
    df, loads = monitors.measure({"a": tree, "b": tree}, rounds=2, repeats=1,
                                 monitored=frozenset({"b"}))
    assert len(df) == 2 * df["case"].nunique() and df["case"].nunique() == 5
    assert df["same_as_first"].all()
    assert (df["n"] == 2).all() and (df["ms_best"] > 0).all()
    assert (df["ms_best"] <= df["ms_median"]).all()
    assert (df.loc[df["tree"] == "a", "best_vs_first"] == 0.0).all()
    assert len(loads) == 3


def test_a_tree_that_is_no_package_is_refused(tmp_path, capsys):
    with pytest.raises(SystemExit):
        monitors.main(["--tree", f"old={tmp_path}"])
    assert "--tree must be NAME=DIR" in capsys.readouterr().err


def test_a_monitored_name_that_is_no_tree_is_refused(capsys):
    with pytest.raises(SystemExit):
        monitors.main(["--monitored", "nope", "--rounds", "1"])
    assert "--monitored names no tree: ['nope']" in capsys.readouterr().err
