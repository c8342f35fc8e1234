"""Validation of the leaning-train theory (``dominowave.theory.leaning``)."""

from __future__ import annotations

import re

import numpy as np
import pytest

from dominowave.theory import leaning
from reference.leaning_frictionless import frictionless_steady_speed
from reference.leaning_train import simulate_train

L, S, G = 0.048, 0.0075, 9.81  # the standard toppling domino
GAPS = np.array([0.002, 0.00938, 0.01509, 0.025, 0.04])
FRICTIONS = np.array([0.0, 0.1, 0.3, 0.525, 1.0])


def test_validate_steady_energy_budget_closes_to_round_off():
    """Per domino, the energy released equals the collision loss plus the work of
    friction (the kinetic energy repeats): the force sweep, the collision's impulse
    sweep and the fixed point agree with energy conservation to round-off."""
    st = leaning.steady_state(L, S, GAPS[:, None], FRICTIONS)
    assert st.exists.sum() == st.exists.size - 1  # mu = 1 at 2 mm: the losses win
    residual = (st.released - st.collision_loss - st.friction_loss)[st.exists]
    assert np.abs(residual / st.released[st.exists]).max() < 1e-12


@pytest.mark.parametrize("friction", [0.0, 0.3, 0.525])
def test_validate_transient_energy_budget_closes_to_round_off(friction):
    """From the push on: push + released = kinetic + collision loss + friction loss."""
    tr = leaning.transient(L, S, 0.00938, friction, n_dominoes=25)
    residual = tr.push + tr.released - tr.kinetic - tr.collision_loss - tr.friction_loss
    assert np.abs(residual / tr.released).max() < 1e-12


@pytest.mark.parametrize("gap", [0.002, 0.00938, 0.025, 0.04])
def test_validate_frictionless_limit_against_conservation_laws(gap):
    """Without friction the steady speed follows from the geometry alone: generalised
    momentum in the collision and energy in the fall (reference: brentq tilts, finite
    difference velocities, Gauss-Legendre fall time; no contact force computed)."""
    expected = frictionless_steady_speed(L, S, gap, G)
    got = leaning.limit_speed(height=L, thickness=S, gap=gap, friction=0.0, g=G)
    assert got == pytest.approx(expected, rel=2e-9)


def test_validate_thin_dominoes_at_small_gaps_run_at_the_fallen_rod_tip_speed():
    """s = 0, no friction: v -> sqrt(3 g l) as d/l -> 0, with an error of order (d/l)^2."""
    ratios = np.array([0.2, 0.1, 0.05, 0.025])
    speed = leaning.limit_speed(height=1.0, thickness=0.0, gap=ratios, g=G)
    error = 1.0 - speed / leaning.thin_small_gap_speed(1.0, G)
    assert np.all(error > 0)
    assert error[-1] < 1e-4
    np.testing.assert_allclose(error[:-1] / error[1:], 4.0, rtol=0.05)  # second order


def test_validate_gap_limits_are_the_geometric_limits_without_friction():
    """Without friction the train runs from the gap where a fallen domino is as high as a
    standing one, 2 s^3 / (l^2 - s^2), to the gap where the fallen dominoes lie flat,
    sqrt(l^2 + s^2) - s."""
    lower, upper = leaning.gap_limits(L, S, 0.0, xtol=1e-10)
    assert upper == pytest.approx(np.hypot(L, S) - S, abs=1e-9)
    # the energy bound is a bound: just above it the train must first lift its centre of
    # mass, and its front stops half-way (0.02 % above the bound for this domino)
    energetic = 2 * S**3 / (L**2 - S**2)
    assert energetic < lower < energetic * (1 + 5e-4)
    assert "front stops" in leaning.steady_state(L, S, 0.5 * (energetic + lower)).reason


def test_friction_raises_the_smallest_gap_and_keeps_the_flat_limit():
    lower0, upper0 = leaning.gap_limits(L, S, 0.0)
    lower, upper = leaning.gap_limits(L, S, 0.3)
    assert lower > 2 * lower0
    assert upper == pytest.approx(upper0, abs=1e-8)
    just_below = leaning.steady_state(L, S, 0.9 * lower, 0.3)
    assert not just_below.exists and "losses exceed" in just_below.reason
    beyond = leaning.steady_state(L, S, 1.01 * upper, 0.3)
    assert not beyond.exists and "lie flat" in beyond.reason
    assert np.isnan(leaning.limit_speed(height=L, thickness=S, gap=1.01 * upper))


@pytest.mark.parametrize("friction", [0.0, 0.525])
def test_validate_asymptotic_speed_does_not_depend_on_the_push(friction):
    """Pushes from just over the tipping point to 10 sqrt(g/l) give trains whose
    collision-to-collision speed tends to the steady speed."""
    steady = leaning.steady_state(L, S, 0.00938, friction)
    lam = 0.00938 + S
    for omega0 in (8.0, 14.3, 143.0):
        tr = leaning.transient(L, S, 0.00938, friction, n_dominoes=120, omega0=omega0)
        assert lam / np.diff(tr.hit_times)[-1] == pytest.approx(steady.speed, rel=1e-6)
        assert tr.omega_after[-1] == pytest.approx(steady.omega_after, rel=1e-6)


def test_validate_spectral_quadrature_has_converged(monkeypatch):
    """The Chebyshev quadrature of the leaning phase: 48 nodes against 96."""
    coarse = leaning.steady_state(L, S, GAPS, 0.3)
    monkeypatch.setattr(leaning, "NODES", 96)
    fine = leaning.steady_state(L, S, GAPS, 0.3)
    np.testing.assert_allclose(coarse.speed, fine.speed, rtol=1e-12)
    np.testing.assert_allclose(coarse.friction_loss, fine.friction_loss, rtol=1e-11)


def test_friction_slows_the_wave_and_broadcasts():
    speed = leaning.limit_speed(height=L, thickness=S, gap=GAPS[:, None], friction=FRICTIONS)
    assert speed.shape == (GAPS.size, FRICTIONS.size)
    slower = np.diff(speed, axis=1) < 0
    assert np.all(slower | np.isnan(speed[:, 1:]))
    scalar = leaning.limit_speed(height=L, thickness=S, gap=0.00938, friction=0.3)
    assert np.ndim(scalar) == 0 and scalar == pytest.approx(speed[1, 2], rel=1e-14)


def test_collision_angle_and_rest_angle():
    assert leaning.collision_angle(L, 0.00938) == pytest.approx(np.arcsin(0.00938 / L))
    assert np.cos(leaning.rest_angle(S, 0.00938)) == pytest.approx(S / (S + 0.00938))


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"gap": 0.05}, "gap = 0.05 is outside the valid range (0, height)"),
        ({"gap": 0.0}, "gap = 0 is outside the valid range (0, inf)"),
        ({"friction": -0.1}, "friction = -0.1 is outside the valid range [0, inf)"),
        ({"thickness": -1e-3}, "thickness = -0.001 is outside the valid range [0, inf)"),
        ({"height": np.nan}, "height = nan is outside the valid range (0, inf)"),
    ],
)
def test_bad_input_names_the_parameter(kwargs, message):
    args = {"height": L, "thickness": S, "gap": 0.00938, "friction": 0.3} | kwargs
    with pytest.raises(ValueError, match=re.escape(message)):
        leaning.limit_speed(**args)


def test_a_push_too_weak_to_tip_the_first_domino_is_refused():
    with pytest.raises(ValueError, match="omega0 = 1 is outside the valid range"):
        leaning.transient(L, S, 0.00938, 0.3, n_dominoes=5, omega0=1.0)


@pytest.mark.parametrize(("gap", "friction"), [(0.00938, 0.3), (0.00938, 0.525), (0.025, 0.3)])
def test_validate_transient_against_direct_multibody_integration(gap, friction):
    """Each domino its own body, contact forces as Lagrange multipliers solved with the
    accelerations, impacts as impulse problems over the whole train (reference:
    solve_ivp DOP853 with events): the same hits, angular velocities and losses."""
    ref = simulate_train(
        height=L, thickness=S, gap=gap, friction=friction, omega0=np.sqrt(G / L), n_dominoes=12
    )
    tr = leaning.transient(L, S, gap, friction, n_dominoes=12)
    np.testing.assert_allclose(tr.hit_times, ref["hit_times"], rtol=1e-8)
    np.testing.assert_allclose(tr.omega_after, ref["omega_front_after"], rtol=1e-8)
    np.testing.assert_allclose(tr.omega_before, ref["omega_front_before"], rtol=1e-8)
    energy = ref["energy"]
    assert tr.friction_loss[-1] == pytest.approx(energy["friction_loss"], rel=1e-7)
    assert tr.collision_loss[-1] == pytest.approx(energy["collision_loss"], rel=1e-7)
