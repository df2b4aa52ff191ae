"""One check per value (issue 40 item 4, docs/design.md "One check per value"): the sliding
comparison written once and every caller agreeing with it, the accuracy preset resolved once
per batch, μ checked where it enters and carried as a number."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rocking.dynamics.result import contact_slides, slid_in_contact


def test_the_sliding_comparison_by_hand():
    mu_req = np.array([0.1, 0.5, math.nan, 0.5, 0.3])
    overturned = np.array([False, False, False, True, False])
    # 0.1 < 0.3: no; 0.5 > 0.3: slid; NaN: nothing monitored; overturned: says nothing;
    # equal to mu: needs no more friction than there is
    np.testing.assert_array_equal(slid_in_contact(mu_req, overturned, 0.3),
                                  [False, True, False, False, False])
    for m, o in zip(mu_req, overturned, strict=True):
        one = contact_slides(float(m), bool(o), 0.3)
        assert one is None if o else one == bool(slid_in_contact(m, o, 0.3))
    assert contact_slides(0.5, False, None) is None


def test_the_search_flags_and_the_limit_state_use_the_one_comparison():
    """The search's per-limit-state ``slides`` and the ``sliding:<mu>`` limit state say what
    slid_in_contact says on the same analyses."""
    from rocking.spectra.limit_states import MU_REQUIRED_MAX, OVERTURNED, parse_limit_state
    from rocking.spectra.search import _Rows

    # (mu_required_max, normal_force_min, overturned) per analysis
    know = _Rows(1, intensity=[1.0, 2.0, 3.0],
                 monitors=[(0.2, 0.5, 0.0), (0.45, 0.1, 0.0), (9.0, -0.1, 1.0)])
    mon = np.asarray(know.monitors)
    limit = np.array([2.0])
    slides, lifts_off = know.monitor_flags(limit, 0.4)
    up_to = mon[:2]
    assert slides[0] == float(slid_in_contact(up_to[:, 0], up_to[:, 2] != 0, 0.4).any()) == 1.0
    assert not lifts_off[0]
    slides, lifts_off = know.monitor_flags(np.array([3.0]), 0.5)
    assert slides[0] == 0.0 and lifts_off[0]  # the overturned analysis never counts
    sliding = parse_limit_state("sliding:0.4")
    for m, _, o in know.monitors:
        peaks = {MU_REQUIRED_MAX: m, OVERTURNED: bool(o)}
        assert sliding.exceeded(peaks, 0.2) == bool(slid_in_contact(m, bool(o), 0.4))


def test_a_batch_resolves_its_accuracy_once(monkeypatch):
    from rocking.motions.catalogue import load_record
    from rocking.spectra import accuracy, critical

    calls = []
    real = accuracy.Accuracy.of

    def counting(cls, value):
        calls.append(value)
        return real(value)

    monkeypatch.setattr(accuracy.Accuracy, "of", classmethod(counting))
    motion = load_record("el-centro-1940")
    out = critical.critical_intensity_batch(
        [(1.0, 0.2, motion, "2d-x"), (2.0, 0.2, motion, "2d-x")], ["tilt:0.5"],
        accuracy="fast", upper=3.0)
    assert calls == ["fast"] and len(out) == 2
    # the answers are those of the public one-point function (which resolves its own)
    one = critical.critical_intensity(critical.Cylinder(2.0, 0.2), motion, ["tilt:0.5"],
                                      "2d-x", accuracy="fast", upper=3.0)
    assert np.array_equal(one.intensity, out[1].intensity, equal_nan=True)
    assert one.n_analyses == out[1].n_analyses


@pytest.mark.parametrize("bad", [0.0, -1.0, math.inf, math.nan])
def test_mu_is_checked_where_it_enters(bad):
    import argparse

    from rocking.cli._common import friction
    from rocking.dynamics.bodies import Cylinder

    with pytest.raises(ValueError, match="^--mu must be a finite number > 0"):
        friction(argparse.Namespace(mu=bad))
    with pytest.raises(ValueError, match="mu must be"):
        Cylinder(1.0, 0.2, mu=bad)
    assert friction(argparse.Namespace(mu=0.3)) == 0.3
    assert friction(argparse.Namespace(mu=None)) is None
