"""Bad input: a ValueError naming the parameter, the value and the valid range."""

from __future__ import annotations

import numpy as np
import pytest

from dominowave import theory as th

BETA, L, M, K, G = 0.4, 0.05, 0.008, 1e3, 9.81

CASES = [
    ("d_over_l", lambda: th.mclachlan_G(1.2), "1.2", "(0, 1)"),
    ("d_over_l", lambda: th.mclachlan_G(np.array([0.3, 0.0])), "0", "(0, 1)"),
    ("beta", lambda: th.omega_limit(np.pi / 2, L, G), "1.5708", "(0, 1.5708)"),
    ("beta", lambda: th.f_plus(-0.1), "-0.1", "(0, 1.5708)"),
    ("l", lambda: th.wave_speed(BETA, 0.0, M, K, G), "0", "(0, inf)"),
    ("l", lambda: th.fall_time_limit(BETA, -1.0, G), "-1", "(0, inf)"),
    ("g", lambda: th.omega_limit(BETA, L, 0.0), "0", "(0, inf)"),
    ("m", lambda: th.collision_time(K, -0.1, BETA), "-0.1", "(0, inf)"),
    ("m", lambda: th.peak_contact_force(BETA, L, 0.0, K, G), "0", "(0, inf)"),
    ("k", lambda: th.collision_time(0.0, M, BETA), "0", "(0, inf]"),
    ("k", lambda: th.wave_speed(BETA, L, M, -5.0, G), "-5", "(0, inf]"),
    ("k", lambda: th.pair_regime_holds(BETA, L, M, np.nan, G), "nan", "(0, inf]"),
    ("R", lambda: th.collision_time_from_material(0.0, 1e9, M, BETA), "0", "(0, inf)"),
    ("E", lambda: th.contact_stiffness_from_material(1e-3, -1e9), "-1e+09", "(0, inf)"),
    ("s", lambda: th.wave_speed_thick(BETA, L, M, K, -0.01, G), "-0.01", "[0, inf)"),
    ("mu", lambda: th.classify_regime(BETA, 1.0, -0.2, 0.1), "-0.2", "[0, inf)"),
    ("mu", lambda: th.regime_boundaries(BETA, -1.0, 0.1), "-1", "[0, inf)"),
    ("s_over_l", lambda: th.classify_regime(BETA, 1.0, 0.3, 1.5), "1.5", "[0, 1)"),
    ("fm_over_mg", lambda: th.classify_regime(BETA, -1.0, 0.3, 0.1), "-1", "[0, inf]"),
    ("omega_n", lambda: th.fall_time(0.0, BETA, L, G), "0", "(0, inf)"),
    ("omega_1", lambda: th.arrival_times(5, -1.0, BETA, L, G), "-1", "(0, inf)"),
    ("collision_time", lambda: th.arrival_times(5, 1.0, BETA, L, G, -1.0), "-1", "[0, inf)"),
    ("n", lambda: th.omega_n_squared(0, 1.0, BETA, L, G), "0", "[1, inf)"),
    ("omega_f", lambda: th.collision_map(np.nan, BETA), "nan", "[0, inf)"),
    ("omega_f", lambda: th.collision_map([1.0, -2.0], BETA), "-2", "[0, inf)"),
    ("omega_f", lambda: th.collision_map(np.inf, BETA), "inf", "[0, inf)"),
    ("fm_over_mg", lambda: th.sliding_rotation_sign(BETA, np.nan, 0.3, 0.1), "nan", "[0, inf]"),
    ("s_over_l", lambda: th.sliding_rotation_sign(BETA, 1.0, 0.3, -0.1), "-0.1", "[0, 1)"),
]


@pytest.mark.parametrize(("name", "call", "value", "interval"), CASES)
def test_bad_input_names_parameter_value_and_range(name, call, value, interval):
    with pytest.raises(ValueError) as info:
        call()
    message = str(info.value)
    assert message.startswith(f"{name} = {value} ")
    assert interval in message


def test_bad_integers_and_conventions():
    with pytest.raises(ValueError, match=r"n = .* integers"):
        th.omega_n_squared(1.5, 1.0, BETA, L, G)
    with pytest.raises(ValueError, match=r"n_dominoes = 2\.5 must be an integer"):
        th.arrival_times(2.5, 1.0, BETA, L, G)
    with pytest.raises(ValueError, match=r"n_dominoes = 0 is outside the valid range \[1, inf\)"):
        th.arrival_times(0, 1.0, BETA, L, G)
    with pytest.raises(ValueError, match="convention = 'yade' is not one of paper, contact"):
        th.wave_speed(BETA, L, M, K, G, convention="yade")
