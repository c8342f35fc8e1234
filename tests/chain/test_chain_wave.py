"""Wave measurement on synthetic arrival times with known answers."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave.chain.wave import (
    ensemble_arrival_stats,
    ensemble_stats,
    first_and_second_onsets,
    local_speeds,
    reached_count,
    secondary_wave,
    settled_start,
    steady_speed,
)
from reference.rigid_chain import ej_transient_arrivals


@pytest.mark.parametrize(("d_over_l", "omega_factor"), [(0.5, 0.3), (0.5, 2.0), (0.7, 0.5)])
def test_validate_steady_speed_on_ej_transient(d_over_l, omega_factor):
    """Arrival times from the rigid EJ transient (eqs 6, 11): the fitted steady speed
    matches the exact limit (eq 14) within the settling tolerance, and the detected
    settled part starts where the profile comes within tolerance of the tail mean."""
    l, rtol = 0.05, 0.01
    # reference push: a fraction / multiple of sqrt(g/l)
    t, x, v_limit = ej_transient_arrivals(80, d_over_l, l, omega_factor * math.sqrt(9.81 / l))
    fit = steady_speed(t, x, rtol=rtol)
    assert fit.settled
    assert abs(fit.speed / v_limit - 1.0) < rtol
    v = local_speeds(t, x)
    k = fit.first
    assert k > 0  # the transient was detected and excluded, not just kept
    tail_mean = v[k:].mean()
    assert abs(v[k] / tail_mean - 1.0) <= rtol
    assert np.ptp(v[k - 1 :]) > rtol * tail_mean  # ... one more and the tail would vary more


def test_validate_settled_detection_on_noisy_ramp():
    """A ramp into a plateau plus noise: the detected start lies near the knee."""
    rng = np.random.default_rng(1)
    n, knee, v0, v1 = 60, 20, 1.0, 2.0
    j = np.arange(n)
    v_true = np.where(j < knee, v0 + (v1 - v0) * j / knee, v1)
    v = v_true + 0.02 * rng.standard_normal(n)
    k = settled_start(v, rtol=0.01)
    assert k is not None
    assert knee - 3 <= k <= knee + 3


def test_settled_start_none_when_still_accelerating():
    v = np.linspace(1.0, 2.0, 30)
    assert settled_start(v, rtol=0.01) is None
    fit = steady_speed(np.cumsum(1.0 / v), np.arange(30.0))
    assert not fit.settled and math.isnan(fit.speed) and fit.n_points == 0


@pytest.mark.parametrize("noise", ["interval", "timing"])
def test_validate_speed_uncertainty_is_calibrated(noise):
    """Over many seeded realisations the true speed lies within 2 reported sigmas
    in about 95% of cases, both for scattered intervals (random-walk arrival times)
    and for independent timing jitter."""
    rng = np.random.default_rng(7)
    n, v_true, dx = 40, 1.3, 0.01
    x = dx * np.arange(n)
    hits, trials = 0, 400
    for _ in range(trials):
        if noise == "interval":
            intervals = dx / v_true * (1.0 + 0.05 * rng.standard_normal(n - 1))
            t = np.concatenate([[0.0], np.cumsum(intervals)])
        else:
            t = x / v_true + 0.1 * dx / v_true * rng.standard_normal(n)
        fit = steady_speed(t, x)
        hits += fit.settled and abs(fit.speed - v_true) <= 2.0 * fit.speed_err
    assert hits / trials > 0.9


def test_local_speeds_and_reach():
    t = np.array([0.0, 1.0, 3.0, np.nan, 5.0])
    x = np.array([0.0, 2.0, 4.0, 6.0, 8.0])
    np.testing.assert_allclose(local_speeds(t, x)[:2], [2.0, 1.0])
    assert np.isnan(local_speeds(t, x)[2:]).all()
    assert reached_count(t) == 3
    assert reached_count([np.nan, 1.0, 0.5]) == 2  # out of order ends the reach


def test_bad_input_is_rejected():
    with pytest.raises(ValueError, match="strictly increasing"):
        local_speeds([0.0, 1.0], [1.0, 1.0])
    with pytest.raises(ValueError, match="equal length"):
        steady_speed([0.0, 1.0], [0.0, 1.0, 2.0])
    with pytest.raises(ValueError, match="rtol"):
        settled_start(np.ones(10), rtol=-1.0)


def test_ensemble_stats_known_values():
    s = ensemble_stats([1.0, 2.0, 3.0, np.nan])
    assert s.mean == 2.0 and s.std == 1.0 and s.n == 3 and s.n_failed == 1
    assert s.stderr == pytest.approx(1.0 / math.sqrt(3.0))
    mean, std, se = ensemble_arrival_stats([[0.0, 1.0, np.nan], [0.0, 3.0, 1.0]])
    np.testing.assert_allclose(mean, [0.0, 2.0, 1.0])
    np.testing.assert_allclose(std[:2], [0.0, math.sqrt(2.0)])
    assert np.isnan(std[2]) and np.isnan(se[2])


def test_validate_secondary_wave_overtaking():
    """Synthetic primary wave at speed 1 and a faster secondary one starting 5 s later:
    the detection finds both speeds, a shrinking lag, and the overtaking pair."""
    n = 30
    x = np.arange(n, dtype=float)
    first = x / 1.0
    second = 5.0 + x / 1.25  # lag = 5 - 0.2 n: reaches 0.5 at n = 22.5
    second[23:] = np.nan  # merged pairs show one long contact, no second onset
    sw = secondary_wave(first, second, x, merge_lag=0.5)
    assert sw is not None and sw.catching_up
    assert sw.primary.speed == pytest.approx(1.0)
    assert sw.secondary.speed == pytest.approx(1.25)
    assert sw.lag_slope == pytest.approx(-0.2)
    assert sw.predicted_pair == pytest.approx(22.5)
    assert sw.overtakes is False  # lag 0.6 at pair 22 is still above merge_lag
    sw2 = secondary_wave(first, 5.0 + x / 1.25, x, merge_lag=0.5)
    assert sw2.overtakes and sw2.merged_pair == 23


def test_no_secondary_wave_when_recontacts_run_backwards():
    """Second contacts that run *against* the chain (dominoes toppling backwards onto their
    predecessors, found at d/l = 0.8 with phi_f = 0.2) are no secondary wave, not an
    error that aborts the run."""
    x = np.arange(10, dtype=float)
    second = 20.0 - x / 2.0  # later pairs re-contact earlier
    assert secondary_wave(x, second, x) is None


def test_no_secondary_wave_when_no_recontacts():
    first, second = first_and_second_onsets([[1.0], [2.0, 0.5], [3.0]])
    np.testing.assert_allclose(first, [1.0, 0.5, 3.0])
    np.testing.assert_allclose(second[1], 2.0)
    assert secondary_wave(first, second, [0.0, 1.0, 2.0]) is None
