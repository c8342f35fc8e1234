"""Chains of box dominoes (``ChainParams(shape="box")``): parameters, push, validation."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave import dem
from dominowave.chain.build import ChainParams, domino_shape
from dominowave.chain.scenario import DominoChain, Push
from reference.rounded_tipping import rounded_first_contact_time

# a box chain whose floor holds the rolling edge (high floor friction)
STICKY = dict(shape="box", friction_floor=10.0)


# --- parameters ----------------------------------------------------------------------------
def test_clump_defaults_unchanged():
    p = ChainParams()
    assert p.shape == "clump" and p.base_layout == "one" and p.held
    assert p.contact_stiffness == ChainParams(base="one", held=True).contact_stiffness


@pytest.mark.parametrize("model", ["2d", "3d"])
def test_box_mass_and_stiffness_meaning(model):
    """Box mass rho l w s; k/k* = 4 k_n / (m g / l), pair spring 2 k_n = k / 2 (eq 24)."""
    p = ChainParams(shape="box", model=model, stiffness_ratio=1e4)
    m = p.density * p.height * p.width * p.thickness
    assert p.mass == pytest.approx(m, rel=1e-15)
    k = 1e4 * m * p.g / p.height
    assert p.contact_stiffness == pytest.approx(k / 4, rel=1e-14)
    assert p.pair_stiffness == pytest.approx(k / 2, rel=1e-14)
    assert p.stiffness_over_kstar == pytest.approx(1e4, rel=1e-14)
    assert p.rounding_radius == p.thickness / 20 and p.held


def test_box_stiffness_from_young_uses_the_rounding():
    p = ChainParams(shape="box", young=2e9, rounding=2e-4)
    assert p.contact_stiffness == pytest.approx(math.pi * 2e-4 * 2e9 / 2, rel=1e-14)


def test_same_collision_time_as_the_2d_clump():
    """Same k/k*: the pair stiffness over the domino mass is that of the 2D clump."""
    clump, box = ChainParams(), ChainParams(shape="box")
    assert box.pair_stiffness / box.mass == pytest.approx(
        clump.pair_stiffness / clump.mass, rel=1e-14
    )


@pytest.mark.parametrize(
    ("changes", "fragments"),
    [
        ({"shape": "cube"}, ["shape = 'cube'", "'clump', 'box'"]),
        ({"shape": "box", "base": "two"}, ["base = 'two'", "shape = 'clump' only"]),
        ({"shape": "box", "spheres_per_column": 12}, ["spheres_per_column = 12", "'clump'"]),
        ({"rounding": 1e-4}, ["rounding = 0.0001", "shape = 'box' only"]),
        ({"restitution_floor": 0.5}, ["restitution_floor = 0.5", "'box' only"]),
        ({"restitution_dominoes": 0.5}, ["restitution_dominoes = 0.5", "'box' only"]),
        ({"shape": "box", "rounding": 0.0025}, ["rounding = 0.0025", "(0, 0.0025)"]),
        ({"shape": "box", "rounding": -1e-4}, ["rounding = -0.0001"]),
        ({"shape": "box", "restitution_floor": 1.5}, ["restitution_floor = 1.5", "(0, 1]"]),
        ({"shape": "box", "restitution_dominoes": 0.0}, ["restitution_dominoes = 0", "(0, 1]"]),
    ],
)
def test_bad_shape_options(changes, fragments):
    with pytest.raises(ValueError) as err:
        ChainParams(**changes)
    message = str(err.value)
    assert "\n" not in message
    for fragment in fragments:
        assert fragment in message


def test_the_clump_shape_of_a_box_domino_is_refused():
    with pytest.raises(ValueError, match=r"shape = 'box'.*domino_box"):
        domino_shape(ChainParams(shape="box"))


def test_changing_shape_drops_the_other_shapes_options():
    p = ChainParams(base="two", spheres_per_column=12).with_(shape="box")
    assert p.base is None and p.spheres_per_column is None
    q = ChainParams(shape="box", rounding=1e-4, restitution_floor=0.5).with_(shape="clump")
    assert q.rounding is None and q.restitution_floor is None


def test_materials_by_pair_and_held_boxes():
    """Domino-domino and domino-floor friction and restitution reach their own contact
    pairs (not the min rule); held boxes wait for the wave."""
    p = ChainParams(
        shape="box",
        n_dominoes=3,
        friction_dominoes=0.1,
        friction_floor=0.6,
        restitution_dominoes=0.8,
        restitution_floor=0.3,
        held=True,
    )
    sim, _ = DominoChain(p).build(Push(omega=10.0))
    box, floor = 0, 1  # material ids: the boxes', the floor's
    assert sim.mats.pair_friction[box, box] == 0.1
    assert sim.mats.pair_friction[box, floor] == sim.mats.pair_friction[floor, box] == 0.6
    assert sim.mats.pair_restitution[box, box] == 0.8
    assert sim.mats.pair_restitution[box, floor] == 0.3
    assert list(sim.bodies.held) == [0, 1, 1]


# --- push ----------------------------------------------------------------------------------
@pytest.mark.parametrize("model", ["2d", "3d"])
def test_push_rotates_about_the_front_bottom_edge(model):
    """Push(omega): the floor contact below the front bottom edge is at rest."""
    p = ChainParams(n_dominoes=2, model=model, **STICKY)
    chain = DominoChain(p)
    omega = 17.0
    sim, omega_1 = chain.build(Push(omega=omega))
    assert omega_1 == omega
    b = sim.bodies
    # the floor contact below the edge, from the centre (the box stands sunk by m g / 4 k_n)
    arm = np.array([p.thickness / 2 - p.rounding_radius, 0.0, -p.height / 2])
    v_contact = b.vel[0] + np.cross(b.omega[0], arm)
    assert np.abs(v_contact).max() < 1e-12 * omega * p.height
    assert b.omega[0] == pytest.approx([0.0, omega, 0.0], abs=0.0)
    assert np.all(b.vel[1] == 0.0) and np.all(b.omega[1] == 0.0)


def test_impulse_push_on_a_free_box():
    """A horizontal impulse J at height h on the free box: v = J/m, omega = (h - l/2) J /
    I_cm with I_cm = m (l^2 + s^2)/12; the theory's Omega_1 = J h / I_A about the edge."""
    p = ChainParams(n_dominoes=2, shape="box", rounding=1e-4)
    chain = DominoChain(p)
    impulse, h = 2e-3, 0.04
    sim, omega_1 = chain.build(Push(impulse=impulse, height=h))
    m, l, s, r = p.mass, p.height, p.thickness, p.rounding
    i_cm = m * (l**2 + s**2) / 12
    assert sim.bodies.vel[0] == pytest.approx([impulse / m, 0.0, 0.0], rel=1e-14)
    assert sim.bodies.omega[0, 1] == pytest.approx((h - l / 2) * impulse / i_cm, rel=1e-12)
    i_edge = i_cm + m * ((s / 2 - r) ** 2 + (l / 2) ** 2)
    assert omega_1 == pytest.approx(impulse * h / i_edge, rel=1e-12)


# --- validation ----------------------------------------------------------------------------
@pytest.mark.parametrize("model", ["2d", "3d"])
def test_validate_box_first_touch_against_energy_quadrature(model):
    """Domino 0 of a two-box chain, pushed with omega = sqrt(g/l) about its front bottom
    edge, first touches domino 1 at the time of the energy integral of a rigid rounded
    cuboid rolling on that edge (tests/reference/rounded_tipping.py: quadrature of (E) up
    to the tilt (C) where its top front edge reaches domino 1's back face): relative
    error <= 1e-3 at k/k* = 1e6 with floor friction 10 (measured 2026-11-25: -3.9e-6 in
    2D and 3D)."""
    p = ChainParams(n_dominoes=2, model=model, stiffness_ratio=1e6, **STICKY)
    chain = DominoChain(p)
    omega = math.sqrt(p.g / p.height)
    run = chain.run(Push(omega=omega))
    t_ref, _ = rounded_first_contact_time(
        p.height, p.thickness, p.rounding_radius, p.spacing, omega, p.g
    )
    assert abs(run.arrival[1] / t_ref - 1.0) <= 1e-3
    # the engine's own onset of the box-box contact is that arrival
    sim, _ = chain.build(Push(omega=omega))
    res = sim.run(until=1.0, stop=dem.StopCondition(touched_body=1))
    onset = (res.events.kind == dem.ONSET) & (res.events.body_j == 1)
    assert res.events.time[onset][0] == pytest.approx(run.arrival[1], rel=1e-12)


@pytest.mark.parametrize("rounding", [2.5e-5, 2.4e-3])
@pytest.mark.parametrize("d_over_l", [0.2, 0.6])
def test_validate_box_first_touch_any_rounding_and_gap(rounding, d_over_l):
    """The same first touch for a nearly sharp (r = s/200) and a nearly fully rounded
    (r = 0.96 s/2) box at d/l = 0.2 and 0.6 (2D): <= 1e-3 (measured 2026-11-25: -1.6e-6 to
    -4.8e-6)."""
    p = ChainParams(
        n_dominoes=2, stiffness_ratio=1e6, rounding=rounding, d_over_l=d_over_l, **STICKY
    )
    omega = math.sqrt(p.g / p.height)
    run = DominoChain(p).run(Push(omega=omega))
    t_ref, _ = rounded_first_contact_time(p.height, p.thickness, rounding, p.spacing, omega, p.g)
    assert abs(run.arrival[1] / t_ref - 1.0) <= 1e-3


@pytest.mark.parametrize("model", ["2d", "3d"])
def test_validate_box_wave_runs_through(model):
    """A 12-box chain at the paper's default k/k* = 1e4: every domino is hit in order and
    topples past its balance tilt, the fitted front speed is positive and finite (the
    events and wave analysis read box contacts like sphere ones), and the arrival times
    increase with the position."""
    asym = 0.01 if model == "3d" else 0.0
    p = ChainParams(
        n_dominoes=12,
        model=model,
        lateral_asymmetry=asym,
        shape="box",
        friction_dominoes=0.3,
        friction_floor=0.3,
    )
    run = DominoChain(p).run()
    assert run.reached_all
    assert np.all(np.diff(run.arrival) > 0.0)
    assert np.all(np.isfinite(run.events.topple_time))
    assert np.all(run.events.max_forward > DominoChain(p).critical_angle)
    assert run.wave.settled and 0.0 < run.wave.speed < math.inf


def test_study_fields_are_the_box_parameters():
    """A study's [scenario] takes the box fields (derived from ChainParams)."""
    from dominowave.io.models import ChainScenario

    given = dict(shape="box", rounding=1e-4, restitution_floor=0.5, friction_dominoes=0.3)
    cfg = ChainScenario(**given)
    assert cfg.params() == ChainParams(**given)
    with pytest.raises(ValueError, match="base = 'two' is an option of shape = 'clump' only"):
        ChainScenario(shape="box", base="two")
