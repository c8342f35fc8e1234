"""The run progress bar: its end and ETA come from the wave's progress and the
measured rate, not from the run's time cap."""

from __future__ import annotations

import math

import pytest

from dominowave.io import progress as prog


def test_expected_end_follows_the_wave_not_the_cap():
    """A 5 s run whose cap is 14.5 s: half-way along the chain at 2.5 s, the run is
    expected to end near 5 s; the cap is kept when the wave's length is unknown, and
    the stepper's own end once every domino is reached (the recorded tail)."""
    assert prog.expected_end(2.5, 14.5, toppled=15, dominoes=30) == pytest.approx(5.0)
    assert prog.expected_end(2.5, 14.5, toppled=15, dominoes=0) == 14.5
    assert prog.expected_end(5.1, 5.6, toppled=30, dominoes=30) == 5.6
    assert prog.expected_end(0.01, 14.5, toppled=1, dominoes=30) == 14.5  # no rate yet


def test_eta_is_the_remaining_simulated_time_at_the_measured_rate():
    assert prog.eta_seconds(wall=2.0, sim_time=1.0, end=4.0) == pytest.approx(6.0)
    assert math.isnan(prog.eta_seconds(wall=0.0, sim_time=0.0, end=4.0))


def test_bar_fields_from_a_run(monkeypatch):
    """Drive the bar as a run does (with a fake clock): the ETA leaves out the time
    before the first report (compiling kernels) and uses the wave's expected end."""
    monkeypatch.setattr(prog, "progress_enabled", lambda quiet: True)
    bar = prog.RunProgress()  # created at wall time 100 s, say; then 40 s of compiling
    clock = iter([140.0, 142.0])
    monkeypatch.setattr(prog.time, "perf_counter", lambda: next(clock))
    # first report: the origin of the rate; 1 s later (sim) after 2 s of wall time:
    bar(sim_time=0.5, end_time=14.5, steps=1000, toppled=3, dominoes=30)
    bar(sim_time=1.5, end_time=14.5, steps=3000, toppled=9, dominoes=30)
    task = bar._bar.tasks[0]
    assert task.total == pytest.approx(1.5 * 30 / 9)  # 5 s, not the 14.5 s cap
    assert task.fields["toppled"] == "9/30"
    assert task.fields["rate"] == pytest.approx(1000.0)  # 2000 steps in 2 s
    eta = (1.5 * 30 / 9 - 1.5) * 2.0 / 1.0  # the rest at 1 s simulated per 2 s
    assert task.fields["eta"] == prog._clock(eta)
