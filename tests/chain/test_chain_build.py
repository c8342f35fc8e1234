"""Domino geometry, parameters and the point-mass -> clump theory mapping."""

from __future__ import annotations

import math

import numpy as np
import pytest

from dominowave import theory
from dominowave.chain.build import ChainParams, chain_positions, domino_shape, place_domino
from dominowave.chain.compare import (
    effective_domino,
    theory_first_contacts,
    theory_speed,
)
from dominowave.units import beta_from_spacing
from reference.rolling_column import rolling_column_time


def test_default_2d_domino_is_a_column_of_ten_touching_spheres():
    p = ChainParams()
    shape = domino_shape(p)
    assert shape.centres.shape == (10, 3)
    np.testing.assert_allclose(np.diff(shape.centres[:, 2]), p.thickness)
    assert shape.centres[0, 2] == pytest.approx(p.radius)
    assert shape.centres[-1, 2] + p.radius == pytest.approx(p.height)
    assert shape.mass == pytest.approx(p.mass)
    assert shape.bottom.sum() == 1
    np.testing.assert_allclose(chain_positions(p)[1], p.spacing + p.thickness)


def test_validate_column_inertia_against_closed_form():
    """Pivot inertia of 10 touching spheres: sum of 2/5 m R^2 + m z_j^2 (parallel axes)."""
    p = ChainParams()
    shape = domino_shape(p)
    m1, r = p.sphere_mass, p.radius
    z = r + p.thickness * np.arange(10)
    expected = np.sum(0.4 * m1 * r**2 + m1 * z**2)
    assert shape.inertia_about_y([0.0, 0.0, 0.0]) == pytest.approx(expected, rel=1e-14)


@pytest.mark.parametrize("changes", [{"spheres_per_column": 19}, {"base": "two"}, {"model": "3d"}])
def test_resolution_base_and_3d_keep_mass_and_height(changes):
    p = ChainParams(**changes)
    shape = domino_shape(p)
    assert shape.mass == pytest.approx(p.mass, rel=1e-12)
    top = (shape.centres[:, 2] + shape.radii).max()
    assert top == pytest.approx(p.height)
    assert (shape.centres[:, 2] - shape.radii).min() == pytest.approx(0.0, abs=1e-15)
    if p.model == "3d":
        assert p.n_across == 5
        assert shape.mass == pytest.approx(5 * ChainParams().mass)
        np.testing.assert_allclose(shape.centres[:, 1].mean(), 0.0, atol=1e-15)


def test_place_domino_yaw_and_sink():
    shape = domino_shape(ChainParams(model="3d"))
    c = place_domino(shape, 1.0, yaw=math.pi / 2, sink=1e-3)
    np.testing.assert_allclose(c[:, 0] - 1.0, -shape.centres[:, 1], atol=1e-15)
    np.testing.assert_allclose(c[:, 2], shape.centres[:, 2] - 1e-3)


def test_stiffness_conventions():
    p = ChainParams(stiffness_ratio=1e4)
    assert p.stiffness_over_kstar == pytest.approx(1e4)
    r = p.radius
    assert ChainParams(young=1e7).contact_stiffness == pytest.approx(math.pi * r * 1e7 / 2)
    assert ChainParams(young=1e7, young_rule="yade").contact_stiffness == pytest.approx(1e7 * r)
    assert ChainParams(kn=123.0).contact_stiffness == 123.0
    assert p.with_(kn=5.0).contact_stiffness == 5.0


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"d_over_l": 1.2}, "d_over_l"),
        ({"n_dominoes": 1}, "n_dominoes"),
        ({"kn": 1.0, "young": 1.0}, "stiffness once"),
        ({"damping": 1.0}, "damping"),
        ({"model": "4d"}, "model"),
        ({"thickness": 0.03}, "thickness"),
        ({"friction_floor": -0.1}, "friction_floor"),
    ],
)
def test_bad_parameters_are_rejected(kwargs, match):
    with pytest.raises(ValueError, match=match):
        ChainParams(**kwargs)


def test_clump_mapping_of_a_thin_column():
    """For thin columns the mapping tends to the uniform rod: m_tip -> m/3, g_eff -> 3g/2."""
    p = ChainParams(height=0.05, thickness=0.0005)
    eff = effective_domino(p, "clump")
    assert eff.tip_mass / eff.mass == pytest.approx(1.0 / 3.0, rel=0.02)
    assert eff.g_eff / p.g == pytest.approx(1.5, rel=0.02)
    pt = effective_domino(p, "point")
    assert pt.tip_mass == eff.mass and pt.g_eff == p.g


@pytest.mark.parametrize("s_over_l", [0.1, 0.05, 0.025])
def test_validate_clump_mapping_fall_time_against_rolling_column(s_over_l):
    """Fall time 0 -> beta of the mapped rod (eq 12 with g_eff) vs the exact energy
    quadrature of the clump rolling without slip on its base sphere: the mapping's
    neglect of the rolling is an O(R/l) error (documented in chain.compare)."""
    p = ChainParams(thickness=0.05 * s_over_l, d_over_l=0.4)
    shape = domino_shape(p)
    eff = effective_domino(p, "clump")
    beta = float(beta_from_spacing(p.d_over_l))
    omega0 = 0.5 * math.sqrt(p.g / p.height)
    t_map = float(theory.fall_time(omega0, beta, p.height, eff.g_eff))
    t_exact = rolling_column_time(
        shape.masses, shape.centres[:, 2], shape.radii, p.radius, omega0, beta
    )
    assert abs(t_map / t_exact - 1.0) < 0.03 * s_over_l  # measured 0.017 s/l


def test_theory_transient_contacts_approach_the_limit_speed():
    p = ChainParams(n_dominoes=200, d_over_l=0.6)
    t = theory_first_contacts(p, omega_1=10.0)
    tail = p.pitch / np.diff(t)[-20:]
    np.testing.assert_allclose(tail, theory_speed(p), rtol=1e-6)
    assert theory_speed(p, rigid=True) > theory_speed(p)


def test_3d_domino_has_the_2d_contact_stiffness_and_collision_time():
    """Same material in 2D and 3D: k_n per contact equal, and n_across parallel contacts
    on n_across times the mass give the same theory collision time."""
    from dominowave.chain.compare import theory_collision_time

    p2, p3 = ChainParams(), ChainParams(model="3d")
    assert p3.contact_stiffness == pytest.approx(p2.contact_stiffness)
    assert p3.pair_stiffness == pytest.approx(5 * p2.contact_stiffness)
    assert p3.stiffness_over_kstar == pytest.approx(1e4)
    assert theory_collision_time(p3) == pytest.approx(theory_collision_time(p2))
