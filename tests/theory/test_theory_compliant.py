"""Validation of the compliant-domino theory (eqs 15-35)."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from dominowave import theory as th
from dominowave.units import k_star
from reference.compliant_collision import head_on_contact, thick_chain_speed

L, M, G = 0.05, 0.008, 9.81
K_STAR = float(k_star(M, L, G))


@pytest.mark.parametrize("beta", [0.1, 0.5, 1.0, 1.4])
@pytest.mark.parametrize("convention", ["paper", "contact"])
def test_validate_collision_against_integrated_contact(beta, convention):
    """Integrated spring contact: duration T_c (eq 31), outgoing velocities (eq 3, the
    compliant collision reproduces EJ's rule), eq 17 (psi(T_c) = Omega_{n+1} T_c/2) and
    the peak force F_m (eq 37) at the limit velocity."""
    k = 1e4 * K_STAR
    k_r = th.contact_stiffness(k, convention)
    omega_f = th.omega_before_collision(th.omega_limit(beta, L, G), beta, L, G)
    duration, omega_back, omega_next, psi_end, peak = head_on_contact(omega_f, beta, k_r, M, L)
    t_c = th.collision_time(k, M, beta, convention)
    assert duration == pytest.approx(t_c, rel=1e-9)
    expected_next, expected_back = th.collision_map(omega_f, beta)
    assert omega_next == pytest.approx(expected_next, rel=1e-9)
    assert omega_back == pytest.approx(expected_back, rel=1e-8)
    assert omega_next == pytest.approx(th.omega_limit(beta, L, G), rel=1e-9)
    assert psi_end == pytest.approx(omega_next * t_c / 2, rel=1e-8)  # eq 17 -> eq 19
    fm = th.peak_contact_force(beta, L, M, k, G, convention)
    assert peak == pytest.approx(fm, rel=1e-6)


def test_validate_eq32_equals_eq31_with_k_pi_R_E():
    """Eq 32 is eq 31 with the per-particle stiffness k = pi R E (eq 23)."""
    beta = np.linspace(0.05, 1.5, 20)
    R, E = 1e-3, 3e9
    t32 = th.collision_time_from_material(R, E, M, beta)
    printed_32 = np.sqrt(2 * np.pi * M / (R * E * (1 + np.cos(beta) ** 4)))
    printed_31 = np.pi * np.sqrt(2 * M / (np.pi * R * E * (1 + np.cos(beta) ** 4)))
    np.testing.assert_allclose(t32, printed_32, rtol=1e-14)
    np.testing.assert_allclose(t32, printed_31, rtol=1e-14)
    np.testing.assert_allclose(t32, th.collision_time(np.pi * R * E, M, beta), rtol=1e-14)


def test_stiffness_conventions():
    """ "paper": k per particle, k_r = k/2; "contact": YADE k_n = 2E1R1E2R2/(E1R1+E2R2)."""
    R, E = 2e-3, 1e8
    yade = 2 * E * R * E * R / (E * R + E * R)
    assert th.contact_stiffness_from_material(R, E, "contact") == pytest.approx(yade)
    assert th.contact_stiffness_from_material(R, E) == pytest.approx(np.pi * R * E / 2)
    assert th.contact_stiffness(10.0) == 5.0
    assert th.contact_stiffness(10.0, "contact") == 10.0
    assert th.collision_time(5.0, M, 0.3, "contact") == th.collision_time(10.0, M, 0.3)
    with pytest.raises(ValueError, match="convention"):
        th.collision_time(5.0, M, 0.3, "yade")


@pytest.mark.parametrize("beta", [0.2, 0.8, 1.3])
def test_validate_effective_masses_from_integrated_contact(beta):
    """m'' = m / cos^4 b (eq 29): a spring k_r pressed by a striker of infinite inertia
    against domino n+1 (Newton about its hinge, arm l cos^2 b from the cross product)
    opens after half a period pi sqrt(m''/k_r); the struck point leaves at twice the
    striker's speed. The two-body contact then lasts pi sqrt(m_r/k_r) with eq 30."""
    k_r = 1e4 * K_STAR
    omega_f = 3.0
    duration, _, omega_next, _, _ = head_on_contact(omega_f, beta, k_r, M, L, striker_fixed=True)
    m_struck = k_r * (duration / np.pi) ** 2
    assert m_struck == pytest.approx(th.struck_effective_mass(M, beta), rel=1e-9)
    assert omega_next * L * np.cos(beta) ** 2 == pytest.approx(2 * L * omega_f, rel=1e-9)
    duration, *_ = head_on_contact(omega_f, beta, k_r, M, L)
    assert k_r * (duration / np.pi) ** 2 == pytest.approx(th.reduced_mass(M, beta), rel=1e-9)


@pytest.mark.parametrize("beta", [0.3, 1.1])
def test_validate_paper_convention_from_spheres_in_series(beta):
    """The paper's convention k_r = k/2: each sphere a spring E (pi R^2) / R = pi R E
    (eq 23), two in series (eq 22); the integrated contact with that spring lasts
    collision_time(pi R E, ..., "paper") = eq 32, not the YADE contact spring E R."""
    R = 1e-3
    E = 1e4 * K_STAR / (np.pi * R)  # per-sphere stiffness 1e4 k*
    k_sphere = E * np.pi * R**2 / R
    k_series = 1.0 / (1.0 / k_sphere + 1.0 / k_sphere)
    omega_f = th.omega_before_collision(th.omega_limit(beta, L, G), beta, L, G)
    duration, *_ = head_on_contact(omega_f, beta, k_series, M, L)
    assert duration == pytest.approx(th.collision_time(np.pi * R * E, M, beta), rel=1e-9)
    assert duration == pytest.approx(th.collision_time_from_material(R, E, M, beta), rel=1e-9)
    yade = th.collision_time_from_material(R, E, M, beta, "contact")
    assert abs(duration / yade - 1) > 0.1  # k_n = E R is a different spring


def test_validate_rigid_limit_recovered():
    """k -> inf recovers EJ: T_c -> 0, v -> d/T, with v(k) - v(inf) = O(T_c / T)."""
    beta = np.linspace(0.02, 1.55, 40)
    v_rigid = th.wave_speed_rigid(beta, L, G)
    np.testing.assert_array_equal(th.wave_speed(beta, L, M, np.inf, G), v_rigid)
    assert np.all(th.collision_time(np.inf, M, beta) == 0)
    assert np.all(th.pair_regime_holds(beta, L, M, np.inf, G))
    gaps = [
        np.max(np.abs(th.wave_speed(beta, L, M, ratio * K_STAR, G) / v_rigid - 1))
        for ratio in (1e12, 1e14, 1e16)
    ]
    # T_c ~ k^(-1/2): the relative gap shrinks tenfold per factor 100 in k
    assert gaps[0] / gaps[1] == pytest.approx(10, rel=0.01)
    assert gaps[1] / gaps[2] == pytest.approx(10, rel=0.002)
    assert gaps[2] < 1e-4


def test_validate_wave_slower_than_p_wave():
    """v < v_w wherever the pair regime holds -- in fact everywhere: v/v_w < 2/pi because
    v = d/(T + T_c/2) < 2d/T_c and v_w = pi d / T_c. The bound is reached as T/T_c -> 0."""
    beta = np.geomspace(1e-4, 1.57, 200)
    for ratio in (1.0, 1e4, 1e8):
        k = ratio * K_STAR
        v = th.wave_speed(beta, L, M, k, G)
        v_w = th.p_wave_speed(beta, L, M, k)
        pair = th.pair_regime_holds(beta, L, M, k, G)
        assert np.all(v[pair] < v_w[pair])
        assert np.all(v / v_w < 2 / np.pi)
        np.testing.assert_allclose(
            v_w, np.pi * L * np.sin(beta) / th.collision_time(k, M, beta), rtol=1e-13
        )
    tiny = th.wave_speed(1e-4, L, M, K_STAR, G) / th.p_wave_speed(1e-4, L, M, K_STAR)
    assert tiny == pytest.approx(2 / np.pi, rel=1e-6)


def test_thickness_ratio():
    """Unit test: v^s / v = v_w^s / v_w = (d + s) / d (eqs 34, 35)."""
    beta = np.linspace(0.05, 1.5, 20)
    s = 0.1 * L
    ratio = (L * np.sin(beta) + s) / (L * np.sin(beta))
    k = 1e4 * K_STAR
    v, vs = th.wave_speed(beta, L, M, k, G), th.wave_speed_thick(beta, L, M, k, s, G)
    np.testing.assert_allclose(vs / v, ratio, rtol=1e-14)
    vw, vws = th.p_wave_speed(beta, L, M, k), th.p_wave_speed_thick(beta, L, M, k, s)
    np.testing.assert_allclose(vws / vw, ratio, rtol=1e-14)


@pytest.mark.parametrize("beta, s_over_l", [(0.4, 0.1), (1.0, 0.25)])
def test_validate_thick_chain_speed_from_integrated_contacts(beta, s_over_l):
    """Eq 34 against the simulated thick chain. Eq 19 neglects gravity during the
    contact, an error O(g T_c^2 / l) ~ 1/k: measured 3.7e-4 (beta = 0.4) and 2.0e-4
    (beta = 1.0) at k = 1e4 k*, 100 times smaller at k = 1e6 k*."""
    errors = []
    for ratio in (1e4, 1e6):
        k = ratio * K_STAR
        omega_1 = th.omega_limit(beta, L, G)
        simulated = thick_chain_speed(beta, s_over_l, th.contact_stiffness(k), omega_1, M, L, G)
        errors.append(abs(simulated / th.wave_speed_thick(beta, L, M, k, s_over_l * L, G) - 1))
    assert errors[0] < 1e-3 and errors[1] < 1e-5
    assert 80 < errors[0] / errors[1] < 120  # ~ 1/k


def test_validate_p_wave_speed_is_long_wave_sound_speed():
    """Eq 35 (and 33 for s = 0): v_w^s is the long-wave sound speed of a periodic chain of
    masses m_r joined by springs k_r at pitch d + s, from the lowest non-zero eigenvalue
    of its dynamical matrix (numpy.linalg.eigvalsh)."""
    beta, s, k = 0.7, 0.1 * L, 1e4 * K_STAR
    pitch = L * np.sin(beta) + s
    n = 200
    laplacian = 2 * np.eye(n) - np.roll(np.eye(n), 1, axis=0) - np.roll(np.eye(n), -1, axis=0)
    dynamical = th.contact_stiffness(k) / th.reduced_mass(M, beta) * laplacian
    omega_1 = np.sqrt(np.sort(np.linalg.eigvalsh(dynamical))[1])
    sound = omega_1 / (2 * np.pi / (n * pitch))
    assert sound == pytest.approx(th.p_wave_speed_thick(beta, L, M, k, s), rel=1e-4)


def test_pair_regime_boundary():
    """T > T_c/2 fails at small beta for finite k. At small beta T ~ beta^2 sqrt(l/g) and
    T_c = pi sqrt(m/k) = pi 1e-4 sqrt(l/g) for k = 1e8 k*: crossover at sqrt(pi/2 1e-4)."""
    beta = np.geomspace(1e-3, 1.5, 2000)
    k = 1e8 * K_STAR
    pair = th.pair_regime_holds(beta, L, M, k, G)
    assert not pair[0] and pair[-1]
    crossover = beta[np.argmax(pair)]
    assert crossover == pytest.approx(np.sqrt(np.pi / 2 * 1e-4), rel=0.05)
    assert np.all(np.diff(pair.astype(int)) >= 0)  # a single crossover


finite_beta = st.floats(1e-3, np.pi / 2 - 1e-3)
ratios = st.floats(1e-2, 1e12)


@settings(max_examples=60, deadline=None)
@given(beta=finite_beta, ratio=ratios, factor=st.floats(1.01, 100.0), s_over_l=st.floats(1e-3, 0.5))
def test_validate_properties_monotone(beta, ratio, factor, s_over_l):
    """Finite and positive; T_c decreases and v increases with k; v^s > v; v < v_w."""
    k1, k2 = ratio * K_STAR, factor * ratio * K_STAR
    t1, t2 = th.collision_time(k1, M, beta), th.collision_time(k2, M, beta)
    v1, v2 = th.wave_speed(beta, L, M, k1, G), th.wave_speed(beta, L, M, k2, G)
    vs = th.wave_speed_thick(beta, L, M, k1, s_over_l * L, G)
    for x in (t1, t2, v1, v2, vs):
        assert np.isfinite(x) and x > 0
    assert t2 < t1
    assert v2 > v1
    assert v2 < th.wave_speed_rigid(beta, L, G)
    assert vs > v1
    assert v1 < th.p_wave_speed(beta, L, M, k1)


@settings(max_examples=60, deadline=None)
@given(beta=finite_beta, delta=st.floats(1e-3, 0.3))
def test_validate_properties_rigid(beta, delta):
    """Omega, T and v of EJ: positive, finite; T grows and v, Omega fall with beta."""
    beta2 = min(beta + delta, np.pi / 2 - 1e-4)
    for b in (beta, beta2):
        for value in (th.omega_limit(b, L, G), th.fall_time_limit(b, L, G)):
            assert np.isfinite(value) and value > 0
    assert th.fall_time_limit(beta2, L, G) > th.fall_time_limit(beta, L, G)
    assert th.wave_speed_rigid(beta2, L, G) < th.wave_speed_rigid(beta, L, G)
    assert th.omega_limit(beta2, L, G) < th.omega_limit(beta, L, G)
    assert 0 < th.f_plus(beta) < 1 and th.f_minus(beta) < 0
