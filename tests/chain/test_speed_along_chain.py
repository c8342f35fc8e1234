"""The window speed and the long-chain figure (plots.long_chains)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.stats import hmean

from dominowave.chain.wave import local_speeds
from dominowave.plots.long_chains import SpeedPanel, plot_speed_along_chain, window_speed
from dominowave.theory import arrival_times


def test_validate_window_speed_is_the_harmonic_mean_of_the_local_speeds():
    """Equal pitches: (x[n+w] - x[n]) / (t[n+w] - t[n]) = w p / sum(p / v_k), the harmonic
    mean of the w local speeds; checked on the theory's transient (eqs 8, 12), where the
    local speeds change from domino to domino."""
    beta, length = math.asin(0.3), 0.05
    t = arrival_times(40, math.sqrt(9.81 / length), beta, length)
    x = 0.02 * np.arange(t.size)
    v = local_speeds(t, x)
    w = 7
    expected = np.array([hmean(v[n : n + w]) for n in range(t.size - w)])
    np.testing.assert_allclose(window_speed(t, x, w), expected, rtol=1e-12)
    assert np.ptp(expected) > 0.1 * expected.mean()  # a transient, not a constant speed


def test_window_speed_of_a_constant_speed_front_is_that_speed():
    x = 0.015 * np.arange(20)
    np.testing.assert_allclose(window_speed(x / 1.7, x, 5), 1.7, rtol=1e-13)


def test_window_speed_is_nan_where_the_wave_did_not_arrive():
    x = 0.01 * np.arange(10)
    t = x / 2.0
    t[6:] = np.nan
    v = window_speed(t, x, 3)
    assert np.all(np.isfinite(v[:3])) and np.all(np.isnan(v[3:]))


@pytest.mark.parametrize(
    ("window", "match"),
    [(0, r"window = 0 .*\[1, 9\]"), (10, r"window = 10 .*\[1, 9\]"), (2.5, "whole number")],
)
def test_bad_window_names_the_parameter(window, match):
    x = 0.01 * np.arange(10)
    with pytest.raises(ValueError, match=match):
        window_speed(x, x, window)


def test_mismatched_shapes_are_refused():
    with pytest.raises(ValueError, match="same shape"):
        window_speed(np.zeros(5), np.zeros(6), 2)


def test_plot_speed_along_chain_writes_a_png(tmp_path):
    x = 0.02 * np.arange(30)
    members = np.vstack([x / 1.0, x / 1.1])
    panel = SpeedPanel("2d, d/l = 0.3", x, members, x / 1.2, 1.5, 0.7)
    out = plot_speed_along_chain([panel, panel, panel], tmp_path / "speed.png", 5, ncols=2)
    assert out.stat().st_size > 1000
    with pytest.raises(ValueError, match=r"ncols = 4 .*\[1, 3\]"):
        plot_speed_along_chain([panel, panel, panel], tmp_path / "bad.png", 5, ncols=4)
    with pytest.raises(ValueError, match="panels is empty"):
        plot_speed_along_chain([], tmp_path / "none.png")
