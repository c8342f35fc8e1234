"""The leaning-train reference (``reference.leaning_train``) checked against closed forms:
the free fall of one domino, hand-solved two-domino impacts, the leaning geometry, the
kinetic-metric projection of a frictionless impact and the energy balance."""

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.linalg import null_space

from reference.leaning_train import Train, contacts, impact, simulate_train

H, S, GAP, G = 0.048, 0.0075, 0.00938, 9.81
LAM = GAP + S
INERTIA = (H**2 + S**2) / 3.0  # m = 1 kg
OMEGA0 = math.sqrt(G / H)
BETA = math.asin(GAP / H)  # the striker's tilt at a hit


def _run(mu, n, omega0=OMEGA0):
    return simulate_train(height=H, thickness=S, gap=GAP, friction=mu, omega0=omega0,
                          n_dominoes=n, g=G)  # fmt: skip


def _omega_squared(theta, omega0):
    """Energy integral of a domino hinged at its front-bottom edge (m = 1 kg):
    I omega^2 / 2 = I omega0^2 / 2 - g (s sin theta + h (cos theta - 1)) / 2."""
    return omega0**2 - G * (S * math.sin(theta) + H * (math.cos(theta) - 1.0)) / INERTIA


def _fall_time(omega0):
    """Physical pendulum over its pivot: t = int_0^beta dtheta / omega(theta) [s]."""
    value, _ = quad(lambda th: _omega_squared(th, omega0) ** -0.5, 0.0, BETA,
                    epsabs=0.0, epsrel=1e-13, limit=200)  # fmt: skip
    return value


def _threshold():
    """The smallest push [rad/s] that carries a domino over its tipping point."""
    return math.sqrt(G * (math.hypot(H, S) - H) / INERTIA)


@pytest.mark.parametrize("mu", [0.0, 0.5])
@pytest.mark.parametrize("omega0", [1.05 * _threshold(), OMEGA0, 3.0 * OMEGA0])
def test_validate_single_fall_is_the_pendulum_quadrature(omega0, mu):
    """Until its first hit domino 0 is a free physical pendulum about its front edge:
    the hit time is the quadrature of the energy integral, the angular velocity there is
    the energy integral at beta = asin(gap / h); friction plays no part. Measured
    agreement at the default rtol 1e-10: <= 5e-11 (time), <= 1.4e-10 (angular velocity,
    the slowest push)."""
    result = _run(mu, 2, omega0)
    assert result["hit_times"][0] == pytest.approx(_fall_time(omega0), rel=1e-9)
    omega_hit = math.sqrt(_omega_squared(BETA, omega0))
    assert result["omega_front_before"][0] == pytest.approx(omega_hit, rel=1e-9)


def test_a_push_below_the_tipping_point_raises():
    with pytest.raises(ValueError, match="tipping point"):
        _run(0.0, 3, 0.99 * _threshold())


def test_validate_frictionless_two_domino_impact():
    """mu = 0, striker at beta, struck domino upright: the normal impulse P is horizontal
    and acts at lever arm h cos(beta) on both (equal inertias), and the contact closes:
    I (w+ - w-) = -P h cos(beta), I W+ = P h cos(beta), w+ = W+, so w+ = W+ = w- / 2 and
    half the kinetic energy is lost."""
    result = _run(0.0, 2)
    before = result["omega_front_before"][0]
    assert result["omega_front_after"][0] == pytest.approx(before / 2, rel=1e-13)
    assert result["omega_striker_after"][0] == pytest.approx(before / 2, rel=1e-13)
    assert result["energy"]["collision_loss"] == pytest.approx(INERTIA * before**2 / 4, rel=1e-12)
    impulse = INERTIA * before / (2 * H * math.cos(BETA))
    assert result["normal_impulses"][0][0] == pytest.approx(impulse, rel=1e-12)


@pytest.mark.parametrize("mu", [0.1, 0.3, 0.8])
def test_validate_two_domino_impact_with_friction(mu):
    """With friction the corner slides down the struck face (slip -gap w - s W < 0), so
    the tangential impulse mu P on the struck domino points down its back face (lever arm
    s) and up on the striker's corner (lever arm gap): I (w+ - w-) = -P (h cos b + mu gap),
    I W+ = P (h cos b - mu s), w+ = W+, hence
    W+ = w- (h cos b - mu s) / (2 h cos b + mu (gap - s))."""
    result = _run(mu, 2)
    before = result["omega_front_before"][0]
    arm = H * math.cos(BETA)
    after = before * (arm - mu * S) / (2 * arm + mu * (GAP - S))
    assert result["omega_front_after"][0] == pytest.approx(after, rel=1e-12)
    assert result["omega_striker_after"][0] == pytest.approx(after, rel=1e-12)
    assert result["normal_impulses"][0][0] == pytest.approx(INERTIA * after / (arm - mu * S))
    loss = INERTIA * (before**2 - 2 * after**2) / 2
    assert result["energy"]["collision_loss"] == pytest.approx(loss, rel=1e-12)


def _gap_function(a, b):
    """phi(a, b) = lam cos b - s - h sin(a - b): zero when the rear domino's (tilt a)
    top-front corner is on the back face of the front one (tilt b); positive apart."""
    return LAM * math.cos(b) - S - H * math.sin(a - b)


def test_validate_contact_kinematics_are_the_gap_function_derivatives():
    """The vector kinematics (lever arms, normals) against the scalar gap function:
    delta = -phi, G_n = -grad phi, G_t = grad w with w = h cos(a - b) - lam sin b the
    contact's height on the face, and kappa = -omega^T Hess(phi) omega."""
    p = Train(H, S, GAP, 0.3)
    rng = np.random.default_rng(7)
    a, b = 0.9, 0.5
    wa, wb = rng.normal(size=2) * 10
    kin = contacts(p, np.array([a, b]), np.array([wa, wb]))
    assert kin.delta[0] == pytest.approx(-_gap_function(a, b), abs=1e-17)
    grad_phi = [-H * math.cos(a - b), -LAM * math.sin(b) + H * math.cos(a - b)]
    np.testing.assert_allclose(kin.g_n[0], -np.array(grad_phi), rtol=1e-14)
    grad_w = [-H * math.sin(a - b), H * math.sin(a - b) - LAM * math.cos(b)]
    np.testing.assert_allclose(kin.g_t[0], grad_w, rtol=1e-14)
    assert kin.w[0] == pytest.approx(H * math.cos(a - b) - LAM * math.sin(b), rel=1e-14)
    hess = H * math.sin(a - b) * (wa - wb) ** 2 - LAM * math.cos(b) * wb**2
    assert kin.kappa[0] == pytest.approx(-hess, rel=1e-13)


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_validate_the_final_train_has_the_leaning_geometry(mu):
    """Right after the last hit the train lies on the closed-form constraint manifold
    h sin(theta_i - theta_{i+1}) = lam cos(theta_{i+1}) - s, the striker at beta and the
    struck domino upright: a configuration fixed by geometry alone, the same for every mu."""
    theta = _run(mu, 8)["theta_final"]
    a, b = theta[:-1], theta[1:]
    np.testing.assert_allclose(H * np.sin(a - b), LAM * np.cos(b) - S, rtol=0, atol=1e-13)
    assert theta[-1] == 0.0 and theta[-2] == pytest.approx(BETA, rel=1e-12)


def _train_state(n, seed):
    """A train of ``n`` dominoes at a hit (the configuration of ``simulate_train``'s end)
    with random pre-impact angular velocities (the last at rest) obeying its n - 2 closed
    contacts: (theta (n,), omega (n,))."""
    theta = _run(0.0, n)["theta_final"]
    rows = contacts(Train(H, S, GAP, 0.0), theta[:-1], np.zeros(n - 1)).g_n
    basis = null_space(rows) if n > 2 else np.eye(1)
    rng = np.random.default_rng(seed)
    omega = basis @ rng.normal(size=basis.shape[1])
    omega *= 10.0 * np.sign(omega[-1])  # the striker moves forward
    return theta, np.append(omega, 0.0)


@pytest.mark.parametrize("n", [2, 5])
def test_validate_frictionless_impact_is_the_kinetic_metric_projection(n):
    """mu = 0: the post-impact velocity is the projection of the pre-impact one onto the
    null space Z of all contact rows in the kinetic-energy metric,
    omega+ = Z (Z^T M Z)^-1 Z^T M omega-, and Carnot's theorem gives the loss
    (1/2) (omega- - omega+)^T M (omega- - omega+)."""
    theta, before = _train_state(n, seed=n)
    p = Train(H, S, GAP, 0.0)
    after, impulse, _, _ = impact(p, theta, before)
    z = null_space(contacts(p, theta, before).g_n)
    projected = z @ np.linalg.solve(z.T @ z, z.T @ before)  # M = I 1
    np.testing.assert_allclose(after, projected, rtol=1e-12, atol=1e-12)
    loss = 0.5 * INERTIA * (before @ before - after @ after)
    jump = before - after
    assert loss == pytest.approx(0.5 * INERTIA * jump @ jump, rel=1e-12)
    assert impulse.min() > 0.0


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_impacts_close_every_contact(mu):
    """After an impact every contact, old and new, has zero normal velocity, compressive
    impulse, and slides the way its friction assumed; along a whole run the same holds."""
    theta, before = _train_state(6, seed=3)
    p = Train(H, S, GAP, mu)
    after, impulse, sigma, _ = impact(p, theta, before)
    kin = contacts(p, theta, after)
    np.testing.assert_allclose(kin.v_n, 0.0, atol=1e-14)
    assert impulse.min() > 0.0
    np.testing.assert_array_equal(np.sign(kin.v_t), sigma)
    result = _run(mu, 8)
    assert result["max_post_impact_v_n"] < 1e-14
    assert result["min_normal_impulse"] > 0.0 and result["min_normal_force"] > 0.0
    assert result["max_penetration"] < 1e-13


@pytest.mark.parametrize("mu", [0.0, 0.3])
def test_validate_energy_balance(mu):
    """Potential released + the push = final kinetic + collision loss + friction loss
    (the friction loss integrated as mu N |slip| alongside the motion), to 1e-10 of the
    potential released (measured ~1e-12); without friction, no friction loss."""
    energy = _run(mu, 10)["energy"]
    assert abs(energy["residual"]) < 1e-10 * energy["potential_released"]
    assert abs(energy["constraint_work"]) < 1e-12 * energy["potential_released"]
    assert energy["collision_loss"] > 0.0
    assert (energy["friction_loss"] > 0.0) == (mu > 0.0)
