"""Measuring like an experiment: the front speed from domino K on, and placement errors."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave import dem
from dominowave.chain.build import ChainParams, placement
from dominowave.chain.scenario import DominoChain, Push
from dominowave.chain.wave import speed_from
from reference.rolling_column import rolling_column_contact_angle, rolling_column_time

# --------------------------------------------------------------------------- fit_from


def test_validate_speed_from_recovers_a_known_speed_past_a_transient():
    """A synthetic arrival series: a slow start (dominoes 0..4) then exactly 1.7 m/s with
    zero-mean timing noise. The fit from K = 5 on recovers 1.7 m/s within its own
    standard error (x3); the fit from K = 1 is biased low by the start."""
    pitch, v, n = 0.0168, 1.7, 40
    x = pitch * np.arange(n)
    t = x / v
    t[:5] = t[5] - (x[5] - x[:5]) / 1.0  # the push transient: the first five at 1 m/s
    rng = np.random.default_rng(1)
    noisy = t + 2e-4 * rng.standard_normal(n)
    exact = speed_from(t, x, 5)
    assert exact.speed == pytest.approx(v, rel=1e-12)
    assert (exact.first, exact.last, exact.reached) == (5, n - 1, n)
    fit = speed_from(noisy, x, 5)
    assert abs(fit.speed - v) < 3.0 * fit.speed_err
    assert speed_from(t, x, 1).speed < 0.99 * v


def test_speed_from_a_wave_that_died_and_bad_values():
    x = 0.01 * np.arange(10)
    t = x / 2.0
    t[6:] = np.nan  # reached 0..5
    assert speed_from(t, x, 3).last == 5
    dead = speed_from(t, x, 5)  # one arrival time left: no fit
    assert math.isnan(dead.speed) and not dead.settled
    for bad in (0, -1, 9, 2.5, True, "3"):
        with pytest.raises(ValueError, match=r"fit_from = .*(outside \[1, 8\]|integer)"):
            speed_from(t, x, bad)


def test_ensemble_fit_from_on_a_short_chain_is_the_least_squares_slope():
    """A real short chain: each member's speed is 1 / slope of a straight line through
    (x_n, t_n), n >= K (numpy.polyfit, an independent fit), on the pitch positions."""
    chain = DominoChain(ChainParams(n_dominoes=8, d_over_l=0.5))
    ens = chain.ensemble(members=2, seed=1, fit_from=3)
    assert ens.fit_from == 3
    for run, fit in zip(ens.runs, ens.fits, strict=True):
        reached = run.wave.reached
        assert reached == 8
        slope = np.polyfit(run.positions[3:reached], run.arrival[3:reached], 1)[0]
        assert fit.speed == pytest.approx(1.0 / slope, rel=1e-10)
        np.testing.assert_allclose(np.diff(run.positions), chain.params.pitch)
    assert ens.speed.mean == pytest.approx(np.mean([f.speed for f in ens.fits]))
    with pytest.raises(ValueError, match=r"fit_from = 7 is outside \[1, 6\]"):
        chain.ensemble(members=2, fit_from=7)


# --------------------------------------------------------------------------- placement


def test_placement_is_off_by_default_and_reproducible_by_seed():
    p = ChainParams(n_dominoes=12, model="3d")
    off = placement(p)
    assert not off.along.any() and not off.across.any() and not off.yaw.any()
    assert off.push_factor == 1.0
    on = dict(placement_along=1e-3, placement_across=2e-3, lateral_asymmetry=0.02, push_error=0.05)
    a, b = placement(p.with_(**on)), placement(p.with_(**on))
    np.testing.assert_array_equal(a.along, b.along)
    np.testing.assert_array_equal(a.across, b.across)
    assert a.push_factor == b.push_factor
    c = placement(p.with_(asymmetry_seed=1, **on))
    assert not np.array_equal(a.along, c.along) and a.push_factor != c.push_factor
    assert np.abs(a.along).max() <= 1e-3 and np.abs(a.across).max() <= 2e-3
    # the yaw keeps the draws the lateral asymmetry always had, whatever else is on
    legacy = 0.02 * np.random.default_rng(0).uniform(-1.0, 1.0, 12)
    np.testing.assert_array_equal(a.yaw, legacy)
    np.testing.assert_array_equal(placement(p.with_(lateral_asymmetry=0.02)).yaw, legacy)


@pytest.mark.parametrize("shape", ["clump", "box"])
def test_placement_moves_the_built_dominoes_and_scales_the_push(shape):
    p = ChainParams(n_dominoes=4, model="3d", width=0.01, shape=shape)
    moved = p.with_(placement_along=1e-3, placement_across=5e-4, push_error=0.1)
    base, errs = DominoChain(p), DominoChain(moved)
    sim0, _ = base.build(base.resolve(None))
    sim1, _ = errs.build(errs.resolve(None))
    shift = sim1.bodies.pos - sim0.bodies.pos
    np.testing.assert_allclose(shift[:, 0], errs.placement.along, atol=1e-15)
    np.testing.assert_allclose(shift[:, 1], errs.placement.across, atol=1e-15)
    np.testing.assert_array_equal(errs.positions, base.positions)  # measured on the pitch
    assert errs.stepper().push.omega == pytest.approx(
        base.resolve(None).omega * errs.placement.push_factor, rel=1e-15
    )


def test_validate_along_error_sets_the_first_collision_of_the_moved_gap():
    """Domino 1 moved by the placement error ``a_1 - a_0``: domino 0 meets it when the
    exact rolling motion of a rigid column (energy quadrature) reaches the contact angle
    of the pitch ``d + s + a_1 - a_0``; the DEM agrees to 1e-4 (as without errors)."""
    p = ChainParams(n_dominoes=2, d_over_l=0.4, stiffness_ratio=1e6, placement_along=4e-3)
    chain = DominoChain(p, max_time=1.0, steps_per_collision=200)
    gap_change = chain.placement.along[1] - chain.placement.along[0]
    assert abs(gap_change) > 1e-3  # the seed moves the pair noticeably
    omega = math.sqrt(p.g / p.height)
    sim, _ = chain.build(Push(omega=omega))
    res = sim.run(until=1.0, stop=dem.StopCondition(touched_body=1))
    ev = res.events
    t_dem = float(ev.time[(ev.kind == dem.ONSET) & (ev.body_j == 1)][0])
    shape = chain.shape
    theta_c = rolling_column_contact_angle(shape.centres[:, 2], p.radius, p.pitch + gap_change)
    t_ref = rolling_column_time(
        shape.masses, shape.centres[:, 2], shape.radii, p.radius, omega, theta_c
    )
    assert abs(t_dem / t_ref - 1.0) < 1e-4


def test_ensemble_vary_placement_stands_each_member_anew():
    p = ChainParams(n_dominoes=5, d_over_l=0.5, placement_along=5e-4)
    chain = DominoChain(p)
    a = chain.ensemble(members=2, seed=2, vary_placement=True)
    b = chain.ensemble(members=2, seed=2, vary_placement=True)
    for ra, rb in zip(a.runs, b.runs, strict=True):
        np.testing.assert_array_equal(ra.arrival, rb.arrival)
    seeds = {r.params.asymmetry_seed for r in a.runs}
    assert len(seeds) == 2 and 0 not in seeds


@pytest.mark.parametrize(
    ("changes", "message"),
    [
        (dict(placement_along=-1e-3), r"placement_along = -0\.001 is outside"),
        (dict(placement_along=0.02), r"placement_along = 0\.02 is outside .*\[0, 0\.01\)"),
        (dict(placement_across=1e-3), r"placement_across = 0\.001 m needs model = '3d'"),
        (dict(push_error=-0.1), r"push_error = -0\.1 is outside"),
        (dict(lateral_asymmetry=0.2), r"lateral_asymmetry = 0\.2 is outside"),
    ],
)
def test_bad_placement_errors_are_refused(changes, message):
    with pytest.raises(ValueError, match=message):
        ChainParams(d_over_l=0.4, height=0.05, **changes)


# --------------------------------------------------------------------------- study files


def test_study_fields_fit_from_and_placement_reach_the_run():
    """``fit_from`` and the placement errors are fields of the TOML ``chain`` scenario;
    the summary's ``speed_fit_from`` is the fit of the stored arrival times from K on."""
    from dominowave.io.models import ChainScenario
    from dominowave.sweep.run_chain import run_chain

    cfg = ChainScenario(
        n_dominoes=7, d_over_l=0.5, fit_from=2, placement_along=2e-4, push_error=0.01
    )
    assert cfg.params().placement_along == 2e-4 and cfg.params().push_error == 0.01
    result = run_chain(cfg)
    events = result.events
    fit = speed_from(events["arrival_time"], events["position"], 2)
    assert result.summary["fit_from"] == 2
    assert result.summary["speed_fit_from"] == fit.speed and math.isfinite(fit.speed)
    plain = run_chain(ChainScenario(n_dominoes=7, d_over_l=0.5)).summary
    assert plain["fit_from"] == -1 and math.isnan(plain["speed_fit_from"])
    with pytest.raises(ValueError, match=r"fit_from = 6 is outside \[1, 5\]"):
        ChainScenario(n_dominoes=7, fit_from=6)
