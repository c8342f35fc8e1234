"""The run's time limit: long enough for the waves of real dominoes, and a run that
reaches it with the wave on its way says so (never a silent "not reached")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave.chain import ChainParams, DominoChain, Push
from dominowave.chain.compare import theory_speed
from dominowave.chain.presets import standard_domino
from dominowave.chain.scenario import default_speed_bound
from dominowave.cli.chain import _cut_short_note
from dominowave.sweep.run_chain import _speed_note


@pytest.mark.parametrize(("gap", "slowest"), [(0.005, 0.411), (0.00938, 0.565), (0.018, 0.644)])
def test_default_max_time_covers_the_standard_domino_chains(gap, slowest):
    """Eq 34 (frictionless elastic dominoes) is 4-45 times the speed of standard dominoes
    with friction: a default limit from eq 34 alone ended a 60-domino chain at 9.38 mm
    at domino 44.  The bound is sqrt(g l) there, and the limit leaves room for more than
    1.5 times the travel at the slowest speed measured at each gap (``slowest`` [m/s]:
    the nominal DEM chains of docs/real_dominoes.md section 8)."""
    p = standard_domino(n_dominoes=60, gap=gap, floor="hardwood")
    bound = default_speed_bound(p)
    assert bound == pytest.approx(math.sqrt(p.g * p.height), rel=1e-12)
    assert bound < theory_speed(p)
    travel = p.n_dominoes * p.pitch / slowest
    assert DominoChain(p).max_time > 1.5 * travel


def test_default_speed_bound_is_eq34_where_eq34_is_slower():
    """At wide spacing eq 34 falls below sqrt(g l) (the tipping time grows as d -> l):
    the bound follows it."""
    p = ChainParams(n_dominoes=10, d_over_l=0.95)
    assert theory_speed(p) < math.sqrt(p.g * p.height)
    assert default_speed_bound(p) == theory_speed(p)


def _box_chain(**options) -> tuple[DominoChain, object]:
    p = ChainParams(n_dominoes=8, d_over_l=0.4, shape="box", model="2d")
    chain = DominoChain(p, **options)
    return chain, chain.run(Push(omega=math.sqrt(p.g / p.height)))


def test_a_run_ended_by_max_time_is_cut_short_and_says_so():
    """max_time before the wave's end: the run stops there ("until"), is ``cut_short``,
    and the command line and the sweep summary name the time and the front."""
    chain, run = _box_chain(max_time=0.15)
    assert run.stop_reason == "until"
    assert run.cut_short and not run.reached_all
    front = int(np.flatnonzero(np.isfinite(run.arrival)).max())
    assert 1 <= front < 7 and run.front == front
    note = _cut_short_note(run, chain.max_time, None)
    assert "max_time = 0.15 s" in note and f"domino {front} of 7" in note
    assert "before it reached the last domino or went quiet" in note
    assert _speed_note(run, chain.max_time).startswith(
        f"the run ended at max_time = 0.15 s with the wave at domino {front} of 7"
    )


def test_a_run_that_reaches_the_last_domino_is_not_cut_short():
    chain, run = _box_chain()
    assert run.reached_all and run.stop_reason == "touched"
    assert not run.cut_short
    assert "max_time" not in _speed_note(run, chain.max_time)
