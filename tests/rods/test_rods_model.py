"""Inputs, failure reporting and the thick-domino statics of the rod model."""

import math

import numpy as np
import pytest

from dominowave.rods import RodChain, block, custom_mass, first_collisions, point_mass, simulate

G = 9.81
K_STAR = G  # m = l = 1


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"n": 1}, r"n = 1 is outside the valid range \[2, inf\)"),
        ({"d": 1.2}, r"d = 1\.2 is outside the valid range \(0, 1\)"),
        ({"s": -0.1}, r"s = -0\.1 is outside the valid range \[0, 1\)"),
        ({"k": 0.0}, r"k = 0 is outside the valid range"),
        ({"law": "cubic"}, r"law = 'cubic' is not one of"),
        ({"normal": "xi", "mu": 0.0}, r"normal = 'xi' is not one of"),
        ({"normal": "head-on", "mu": 0.3}, r"mu = 0\.3 is outside the valid range \[0, 0\]"),
        ({"damping_ratio": 1.0}, r"damping_ratio = 1 is outside the valid range \[0, 1\)"),
        ({"floor_restitution": 1.5}, r"floor_restitution = 1\.5 is outside"),
        ({"g": -1.0}, r"g = -1 is outside the valid range \[0, inf\)"),
    ],
)
def test_bad_chain_parameters_are_named(kwargs, message):
    params = {"n": 5, "l": 1.0, "d": 0.4} | kwargs
    with pytest.raises(ValueError, match=message):
        RodChain(**params)


def test_mass_distribution_obeys_parallel_axis_theorem():
    with pytest.raises(ValueError, match=r"inertia = 0\.1 is outside the valid range"):
        custom_mass(1.0, 0.1, 0.0, 0.5)


def test_mass_centre_must_lie_in_the_domino():
    with pytest.raises(ValueError, match=r"mass centre"):
        RodChain(n=3, l=1.0, d=0.4, s=0.0, mass=block(1.0, 1.0, 0.2))


def test_blow_up_is_reported_not_returned():
    chain = RodChain(n=5, l=1.0, d=0.4, mass=point_mass(1, 1), k=1e8 * K_STAR)
    with pytest.raises(FloatingPointError, match="energy balance broke down"):
        simulate(chain, push=5.0, dt=2e-3, t_max=5.0)


def test_under_resolved_contacts_warn():
    chain = RodChain(n=4, l=1.0, d=0.4, mass=point_mass(1, 1), k=1e4 * K_STAR / 2)
    with pytest.warns(RuntimeWarning, match="time steps"):
        simulate(chain, push=7.0, steps_per_contact=5)


def test_time_step_resolves_the_stiffest_possible_contact():
    chain = RodChain(n=3, l=1.0, d=0.4, s=0.1, mass=block(1, 1, 0.1), k=1e6)
    reduced = chain.mass.inertia / (2 * (1.0 + 0.01))
    assert chain.time_step(100) == pytest.approx(math.pi * math.sqrt(reduced / 1e6) / 100)


@pytest.mark.parametrize("factor", [0.99, 1.01])
def test_validate_thick_domino_topples_only_above_critical_push(factor):
    """A block (s > 0) on its front edge is stable: it topples only if the push lifts its
    centre of mass over the edge, 1/2 I W^2 > m g (sqrt(cm_u^2 + cm_w^2) - cm_w)."""
    s = 0.2
    mass = block(1.0, 1.0, s)
    chain = RodChain(n=2, l=1.0, d=0.5, s=s, mass=mass, k=1e4 * K_STAR / 2)
    lift = math.hypot(mass.cm_u, mass.cm_w) - mass.cm_w
    critical = math.sqrt(2 * mass.m * G * lift / mass.inertia)
    run = simulate(chain, push=factor * critical, stall_time=10.0, t_max=12.0)
    if factor < 1:
        assert np.isnan(run.arrival[1])
        assert run.status == "stalled"
        assert run.theta[0] == 0.0  # back on its base, held by the floor
    else:
        assert np.isfinite(run.arrival[1])
        assert run.status == "wave passed"


def test_collision_table_reports_each_pair_once():
    chain = RodChain(n=20, l=1.0, d=0.4, mass=point_mass(1, 1), k=1e4 * K_STAR / 2)
    run = simulate(chain, push=7.0)
    col = first_collisions(run)
    assert col.t_on.shape == (19,)
    assert np.all(np.diff(col.t_on) > 0)
    assert np.all(col.n_contacts >= 1)
    # arrival of domino n+1 = onset of the first collision of pair (n, n+1)
    np.testing.assert_array_equal(run.arrival[1:], col.t_on)


def test_frames_record_the_angles_for_animation():
    chain = RodChain(n=6, l=1.0, d=0.4, mass=point_mass(1, 1), k=1e4 * K_STAR / 2)
    run = simulate(chain, push=7.0, frame_every=50)
    assert run.frame_theta.shape == (run.frame_times.size, 6)
    assert run.frame_times.size == run.n_steps // 50 + 1
    np.testing.assert_allclose(np.diff(run.frame_times), 50 * run.dt)
    assert run.frame_omega[0, 0] == 7.0  # the push, at t = 0
    assert simulate(chain, push=7.0).frame_theta.shape == (0, 6)
