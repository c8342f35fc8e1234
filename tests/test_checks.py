"""The shared parameter checks: messages name the parameter, value and range."""

import math

import numpy as np
import pytest

from dominowave.checks import (
    check_finite,
    check_format,
    check_in_range,
    check_nonnegative,
    check_positive,
)
from dominowave.units import beta_from_spacing, k_star, spacing_from_beta, speed_scale


def test_in_range_message_names_parameter_value_and_interval():
    with pytest.raises(ValueError, match=r"d_over_l = 1\.2 is outside the valid range \(0, 1\)"):
        check_in_range("d_over_l", 1.2, 0.0, 1.0)


def test_in_range_reports_first_bad_array_element():
    with pytest.raises(ValueError, match=r"x = -3 is outside the valid range \[0, inf\)"):
        check_nonnegative("x", np.array([1.0, -3.0, -4.0]))


def test_positive_rejects_zero_and_nan_but_accepts_inf():
    check_positive("k", math.inf)
    for bad in (0.0, -1.0, math.nan):
        with pytest.raises(ValueError, match="k = "):
            check_positive("k", bad)


def test_finite_and_non_numbers():
    with pytest.raises(ValueError, match="is not a finite number"):
        check_finite("dt", math.inf)
    with pytest.raises(ValueError, match="is not a number"):
        check_in_range("mu", "abc", 0.0, 1.0)


def test_units_round_trip_and_scales():
    d = np.array([0.1, 0.4, 0.9])
    np.testing.assert_allclose(spacing_from_beta(beta_from_spacing(d)), d, rtol=1e-15)
    assert k_star(0.01, 0.05, g=9.81) == pytest.approx(0.01 * 9.81 / 0.05)
    assert speed_scale(0.05, g=9.81) == pytest.approx(math.sqrt(9.81 * 0.05))
    with pytest.raises(ValueError, match="d_over_l"):
        beta_from_spacing(1.0)


def test_first_bad_element_of_a_2d_array_is_reported():
    grid = np.array([[0.5, 0.2], [1.5, -1.0]])
    with pytest.raises(ValueError, match=r"d_over_l = 1\.5 is outside the valid range \(0, 1\)"):
        check_in_range("d_over_l", grid, 0.0, 1.0)


def test_check_format_reads_the_versions_it_knows_and_names_a_newer_one():
    assert check_format("state_format", 2, 4) == 2
    with pytest.raises(ValueError, match=r"state_format = 5: .* formats 1 to 4 \(a newer"):
        check_format("state_format", 5, 4)
    with pytest.raises(ValueError, match=r"state_format = 0: .* formats 1 to 4$"):
        check_format("state_format", 0, 4)
