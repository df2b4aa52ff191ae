"""The resolution benchmark's own pieces (benchmarks/resolution.py) on constructed lattices:
its reference I10 is the closed form of a clean step, an isolated window does not move it,
and its stand-in for an analysis answers what the lattice says, cut at the goal asked."""

from __future__ import annotations

import math

import numpy as np
import pytest

from benchmarks import resolution as bench
from rocking.dynamics.result import Status
from rocking.spectra.limit_states import parse_limit_states

ALPHA = math.atan(0.2)
W, P = bench.Q.w, bench.Q.p


def constructed(exceeds, lo: int, hi: int, periods=(bench.FINE,)) -> bench.Lattice:
    """A lattice of one goal (overturning) from uplift 1.0: every index n in [lo, hi] that is a
    multiple of one of ``periods`` analysed, overturned where ``exceeds(I)``."""
    ns = sorted({n for p in periods for n in range(lo, hi + 1) if n % p == 0 and n > 0})
    intens = np.exp(np.asarray(ns) * bench.STEP)
    over = [bool(exceeds(i)) for i in intens]
    key = ("m", "3d", 1.0, 0.2, ("overturning",))
    return bench.Lattice(key, 1.0, ALPHA, parse_limit_states(key[4]), ns,
                         [math.pi / 2 if o else 0.01 for o in over], over,
                         [Status.OVERTURNED.value if o else Status.OK.value for o in over],
                         [math.nan] * len(ns), [0.001] * len(ns))


def test_reference_of_a_step_is_its_closed_form():
    s_star = math.exp(0.5)  # lattice index 5000
    lat = constructed(lambda I: I >= s_star, 4000, 6000)
    n, known, _ = lat.decided()
    own = n[(n % bench.FINE == 0)]
    ref, top = bench.lattice_i10(lat, 0, bench.FINE, own, 2 * bench.FINE)
    assert ref == pytest.approx(s_star * math.exp(-W * (1 - 2 * P)), rel=3 * bench.STEP)
    assert top == 0.0  # nothing below: no plateau


def test_an_isolated_window_does_not_move_the_reference():
    s_star = math.exp(0.5)
    window = (math.exp(0.45), math.exp(0.4503))  # 0.03 % wide, 5 % below the rise
    lat = constructed(lambda I: I >= s_star or window[0] <= I < window[1], 4000, 6000)
    n, _, _ = lat.decided()
    ref, top = bench.lattice_i10(lat, 0, bench.FINE, n, 2 * bench.FINE)
    assert ref == pytest.approx(s_star * math.exp(-W * (1 - 2 * P)), rel=3 * bench.STEP)
    assert 0.0 < top < P / 2  # seen, not near p


def test_judged_quantile_says_where_the_crossing_lies():
    x = np.exp(np.arange(0, 0.3, 1e-3))
    e = x >= math.exp(0.1)
    ip, edge = bench.judged_quantile(x, e, x[0], x[-1])
    assert edge == "ok" and ip == pytest.approx(math.exp(0.1 - W * 0.8), rel=2e-3)
    # a sample that starts above the crossing: P >= p at its lowest judged s
    sel = x >= math.exp(0.095)
    assert bench.judged_quantile(x[sel], e[sel], x[sel][0], x[-1])[1] == "low"
    # a sample that ends below it: P < p throughout
    sel = x <= math.exp(0.09)
    assert bench.judged_quantile(x[sel], e[sel], x[0], x[sel][-1])[1] == "none"


def test_the_oracle_answers_the_nearest_lattice_point_cut_at_the_goal():
    s_star = math.exp(0.5)
    lat = constructed(lambda I: I >= s_star, 4000, 6000)
    oracle = bench.Oracle(lat)
    above = oracle(s_star * math.exp(3e-5), None, 1e-7)  # nearest point: n = 5000, over
    assert above.overturned and above.status is Status.OVERTURNED
    cut = oracle(s_star * math.exp(3e-5), 0.5 * ALPHA, 1e-7)  # stopped at the goal asked
    assert cut.status is Status.STOPPED_AT_LIMIT and cut.theta_max == 0.5 * ALPHA
    below = oracle(s_star * math.exp(-5e-4), None, 1e-7)
    assert not below.overturned
    assert oracle.analyses == 3 and oracle.seconds == pytest.approx(0.003)
