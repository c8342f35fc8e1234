"""Validation of the rigid EJ theory (eqs 2-14) against independent computations."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import ellipk, ellipkinc

from dominowave import theory as th
from reference.rigid_chain import ej_chain_by_newton, ej_collision, ej_fall_time

L, G = 0.05, 9.81  # a real domino: 5 cm, standard gravity
BETAS = np.array([1e-4, 1e-3, 0.01, 0.1, 0.3, 0.6, 0.9, 1.2, 1.5, np.pi / 2 - 1e-6])


@pytest.mark.parametrize("omega_scale", [0.05, 0.5, 1.0, 5.0, 100.0])
def test_validate_fall_time_against_quadrature(omega_scale):
    """T_n (eq 12, elliptic integrals) equals direct quadrature of eq 11 to 1e-10."""
    omega_n = omega_scale * np.sqrt(G / L)
    exact = np.array([ej_fall_time(omega_n, b, L, G) for b in BETAS])
    rel = np.abs(th.fall_time(omega_n, BETAS, L, G) / exact - 1.0)
    assert rel.max() < 1e-10, rel


def test_validate_fall_time_limit_against_quadrature():
    """T (eq 13) at the limit velocity of eq 9, over beta in (0, pi/2), to 1e-10."""
    betas = np.concatenate([BETAS, np.linspace(0.02, 1.56, 40)])
    exact = np.array([ej_fall_time(th.omega_limit(b, L, G), b, L, G) for b in betas], dtype=float)
    rel = np.abs(th.fall_time_limit(betas, L, G) / exact - 1.0)
    assert rel.max() < 1e-10, rel.max()


def test_validate_eq12_literal_form_with_scipy_parameter():
    """The printed eq 12, K(kappa) - F((pi - beta)/2, kappa) with SciPy's m = kappa^2,
    agrees with our cancellation-free evaluation where K - F loses no precision."""
    omega_n, l, g = 3.0, 1.0, 1.0
    beta = np.linspace(0.2, 1.5, 14)
    a, c = omega_n**2 + 2 * g / l, 2 * g / l
    m = 2 * c / (a + c)  # kappa^2
    printed = 2 / np.sqrt(a + c) * (ellipk(m) - ellipkinc((np.pi - beta) / 2, m))
    np.testing.assert_allclose(th.fall_time(omega_n, beta, l, g), printed, rtol=1e-13)


@pytest.mark.parametrize("beta", [0.05, 0.3, 0.7, 1.2])
@pytest.mark.parametrize("omega_1", [0.1, 3.0])
def test_validate_iterated_collision_map_matches_eq8(beta, omega_1):
    """Solve eq 2 numerically and apply eq 5, 200 times: eq 8 holds for every n."""
    l, g = 1.0, 1.0
    omega = omega_1
    iterated = [omega**2]
    for _ in range(199):
        omega_f = np.sqrt(omega**2 + 2 * g / l * (1 - np.cos(beta)))  # eq 5
        omega, _ = ej_collision(omega_f, beta)
        iterated.append(omega**2)
    n = np.arange(1, 201)
    closed = th.omega_n_squared(n, omega_1, beta, l, g)
    np.testing.assert_allclose(closed, iterated, rtol=1e-11)
    # one step of eq 6 and the collision map of eq 3 give the same sequence
    np.testing.assert_allclose(
        th.omega_next_squared(np.sqrt(closed[:-1]), beta, l, g), closed[1:], rtol=1e-12
    )


@pytest.mark.parametrize("beta", [0.7, 1.0, 1.3])
def test_validate_collision_map_converges_to_eq9(beta):
    """The numerically iterated map converges to Omega of eq 9 from below and above."""
    l, g = 1.0, 1.0
    limit = th.omega_limit(beta, l, g)
    for omega in (0.3 * limit, 2.0 * limit):
        for _ in range(200):
            omega_f = np.sqrt(omega**2 + 2 * g / l * (1 - np.cos(beta)))
            omega, _ = ej_collision(omega_f, beta)
        assert omega == pytest.approx(limit, rel=1e-12)


def test_validate_collision_map_solves_eq2():
    """collision_map (eq 3-4) satisfies both conservation laws of eq 2."""
    beta = np.linspace(0.01, 1.56, 50)
    omega_f = 2.5
    omega_next, omega_back = th.collision_map(omega_f, beta)
    c = np.cos(beta) ** 2
    np.testing.assert_allclose(omega_back**2 + omega_next**2, omega_f**2, rtol=1e-14)
    np.testing.assert_allclose(omega_back * c + omega_next, omega_f * c, rtol=1e-13, atol=1e-15)
    assert np.all(omega_back < 0)  # the striking domino bounces back
    np.testing.assert_allclose(omega_next / th.f_minus(beta), omega_back, rtol=1e-13)
    np.testing.assert_allclose(
        th.f_plus(beta), 2 / (np.cos(beta) ** 2 + 1 / np.cos(beta) ** 2), rtol=1e-14
    )


def test_validate_eq9_limit_is_fixed_point_and_printed_form():
    """Omega^2 is the fixed point of eq 6 and equals the printed right side of eq 9."""
    beta = np.linspace(0.3, 1.5, 13)
    omega = th.omega_limit(beta, L, G)
    np.testing.assert_allclose(th.omega_next_squared(omega, beta, L, G), omega**2, rtol=1e-13)
    fp = th.f_plus(beta)
    printed = 2 * G / L * (1 - np.cos(beta)) * fp**2 / (1 - fp**2)  # eq 9, = Omega^2
    np.testing.assert_allclose(omega**2, printed, rtol=1e-12)


def test_validate_eq9a_energy_identity_at_the_limit():
    """At the limit I Omega_bn^2 / 2 = m g l (1 - cos beta): domino n returns upright."""
    beta = np.linspace(0.01, 1.56, 60)
    m = 0.01
    omega_f = th.omega_before_collision(th.omega_limit(beta, L, G), beta, L, G)
    omega_next, omega_back = th.collision_map(omega_f, beta)
    np.testing.assert_allclose(omega_next, th.omega_limit(beta, L, G), rtol=1e-12)
    kinetic = 0.5 * m * L**2 * omega_back**2
    potential = m * G * L * 2 * np.sin(beta / 2) ** 2
    np.testing.assert_allclose(kinetic, potential, rtol=1e-12)


def test_validate_small_beta_asymptotics():
    """f+ ~ 1 - b^4/2, Omega ~ sqrt(g/l)/b, T ~ b^2 sqrt(l/g), v ~ sqrt(g l)/b (O(b^2))."""
    s = np.sqrt(G / L)
    for beta in (1e-1, 1e-2, 1e-3):
        assert abs(1 - th.f_plus(beta) - beta**4 / 2) < beta**6 + 1e-16
        assert abs(th.omega_limit(beta, L, G) * beta / s - 1) < 0.25 * beta**2
        assert abs(th.fall_time_limit(beta, L, G) * s / beta**2 - 1) < 0.25 * beta**2
        assert abs(th.wave_speed_rigid(beta, L, G) * beta / np.sqrt(G * L) - 1) < 0.4 * beta**2


def test_wave_speed_scaling_and_mclachlan_G():
    """Unit test: v = d / T; G = v / sqrt(g l) depends on d/l only (rescaled l, g)."""
    d_over_l = np.array([0.1, 0.4, 0.8])
    beta = np.arcsin(d_over_l)
    v = th.wave_speed_rigid(beta, L, G)
    np.testing.assert_allclose(v, L * d_over_l / th.fall_time_limit(beta, L, G), rtol=1e-15)
    np.testing.assert_allclose(v / np.sqrt(G * L), th.mclachlan_G(d_over_l), rtol=1e-13)
    np.testing.assert_allclose(
        th.wave_speed_rigid(beta, 2.0, 3.0) / np.sqrt(6.0), v / np.sqrt(G * L)
    )


def test_validate_eq14_literal_form_and_reference_values():
    """Corrected eq 14 in its literal form, v = d sqrt(a+c) / (2 [K(m) - F((pi-beta)/2, m)]),
    SciPy's ellipk/ellipkinc with m = kappa^2, at moderate beta where K - F is well
    conditioned; and McLachlan's G pinned to values computed independently with mpmath."""
    l, g = 1.0, 1.0
    beta = np.linspace(0.2, 1.3, 12)
    a = th.omega_limit(beta, l, g) ** 2 + 2 * g / l
    c = 2 * g / l
    m = 2 * c / (a + c)  # kappa^2
    literal = (
        l * np.sin(beta) * np.sqrt(a + c) / (2 * (ellipk(m) - ellipkinc((np.pi - beta) / 2, m)))
    )
    np.testing.assert_allclose(th.wave_speed_rigid(beta, l, g), literal, rtol=1e-12)
    reference = {0.1: 9.9457571, 0.4: 2.2781026, 0.8: 0.75865848}  # mpmath, by the referee
    for d_over_l, value in reference.items():
        assert th.mclachlan_G(d_over_l) == pytest.approx(value, rel=1e-7)


@pytest.mark.parametrize("beta, omega_scale", [(0.6, 0.2), (1.1, 4.0)])
def test_validate_arrival_times_against_integrated_chain(beta, omega_scale):
    """t_n (cumulative T_n of eq 12 with Omega_n of eq 8) equals the integrated chain."""
    omega_1 = omega_scale * np.sqrt(G / L)
    simulated = ej_chain_by_newton(15, omega_1, beta, L, G)
    np.testing.assert_allclose(th.arrival_times(15, omega_1, beta, L, G), simulated, rtol=1e-9)


def test_arrival_times_compliant_shift_and_broadcast():
    """Each period grows by T_c/2 (eq 19); parameters broadcast to shape S + (N,)."""
    rigid = th.arrival_times(10, 30.0, 0.5, L, G)
    compliant = th.arrival_times(10, 30.0, 0.5, L, G, collision_time=1e-3)
    np.testing.assert_allclose(compliant - rigid, 0.5e-3 * np.arange(10), rtol=1e-10, atol=1e-15)
    grid = th.arrival_times(6, np.array([[10.0], [20.0]]), np.array([0.3, 0.6, 0.9]), L, G)
    assert grid.shape == (2, 3, 6)
    np.testing.assert_allclose(grid[1, 2], th.arrival_times(6, 20.0, 0.9, L, G))
    # late dominoes move at the limit pace: the last interval tends to T
    long = th.arrival_times(400, 30.0, 1.0, L, G)
    assert np.diff(long)[-1] == pytest.approx(th.fall_time_limit(1.0, L, G), rel=1e-12)


def test_validate_eq8_near_pi_over_2():
    """Eq 8 stays finite and exact as beta -> pi/2 (f_+ -> 0, 1 - f_+ rounds to 1): it
    equals eq 6 iterated from Omega_1 (f_plus**2, no logarithms) for n = 1 .. 6."""
    omega_1 = 2.0
    for beta in (np.pi / 2 - 1e-5, np.pi / 2 - 1e-8, np.pi / 2 - 1e-9, np.pi / 2 - 1e-12):
        n = np.arange(1, 7)
        closed = th.omega_n_squared(n, omega_1, beta, 1.0, 1.0)
        iterated = [omega_1**2]
        for _ in n[1:]:
            iterated.append(th.omega_next_squared(np.sqrt(iterated[-1]), beta, 1.0, 1.0))
        np.testing.assert_allclose(closed, iterated, rtol=1e-13)
        assert closed[0] == omega_1**2
    t = th.arrival_times(3, 2.0, np.pi / 2 - 1e-9, 1.0, 1.0)  # raised "omega_n = nan" before
    assert np.all(np.isfinite(t)) and np.all(np.diff(t) > 0)
    assert t[1] == pytest.approx(th.fall_time(2.0, np.pi / 2 - 1e-9, 1.0, 1.0), rel=1e-14)
