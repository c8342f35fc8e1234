"""The layout of a saved simulation state is versioned (``state_format``).

A state of the current format round-trips as it is; a format-1 state (written before the
key existed, without the planar switch, the shear kinematics, the material-pair tables
and the Hertz tables, and possibly without the boxes' held flags at the list build and
the box-sphere list), a format-2 state (without the sleep settings and the rows of
resting boxes), a format-3 state (one stiffness column for E or k_n), a format-4 state
(sphere contacts without their rows' points, normals and multiplicities), a format-5
state (sphere contacts with a flag ``active``) and a format-6 state (the box-sphere rows
in a table of their own) are read with
the values their scene had implicitly and resume bit for bit (the older layouts:
older_states.py); a state of a newer format, or of the current one with a key missing,
is refused in one line.
"""

from __future__ import annotations

import numpy as np
import pytest
from older_states import older_state

from dominowave.dem import Material, Scene, Simulation
from dominowave.dem.material_pairs import RULE_GIVEN
from dominowave.dem.simulation import STATE_FORMAT


def _bouncing_ball():
    scene = Scene()
    m = scene.add_material(Material(density=1000.0, kn=1e5, friction=0.3, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_sphere((0.0, 0.0, 0.0051), 0.005, m, velocity=(0.1, 0.0, -0.2))
    return scene.build()


def test_a_state_carries_its_format():
    sim = _bouncing_ball()
    state = sim.get_state()
    assert int(state["state_format"]) == STATE_FORMAT
    restored = Simulation.from_state(state)
    assert int(restored.get_state()["state_format"]) == STATE_FORMAT


@pytest.mark.parametrize("version", [1, 2, 3, 4, 5, 6])
def test_an_older_state_resumes_bit_identically(version):
    sim = _bouncing_ball()
    sim.run(n_steps=500)
    restored = Simulation.from_state(older_state(sim.get_state(), version))
    assert restored.planar_kernels
    assert restored.mats.rule[0] == RULE_GIVEN  # (format 1: the flag mats.given_kn)
    np.testing.assert_array_equal(restored.mats.kn, sim.mats.kn)
    assert np.isnan(restored.mats.young).all()
    if version <= 2:
        assert restored.settings.sleep_speed == 0.0  # (never sleeps)
    sim.run(n_steps=3000)
    restored.run(n_steps=3000)
    for name in ("pos", "vel", "quat", "omega"):
        np.testing.assert_array_equal(getattr(restored.bodies, name), getattr(sim.bodies, name))
    np.testing.assert_array_equal(restored.rec.ledger, sim.rec.ledger)  # (the contact power)
    assert restored.energy() == sim.energy()
    assert sim.bodies.vel_full[0, 2] > 0  # it bounced


def test_a_format_3_state_of_young_moduli_gets_its_modulus_column():
    scene = Scene(stiffness_rule="yade")
    m = scene.add_material(Material(density=1000.0, young=2e7, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    scene.add_sphere((0.0, 0.0, 0.0051), 0.005, m)
    state = scene.build().get_state()
    assert state["mats.young"][0] == 2e7 and np.isnan(state["mats.kn"]).all()
    old = older_state(state, 3)
    assert old["mats.stiffness"][0] == 2e7 and "mats.young" not in old
    restored = Simulation.from_state(old)
    assert restored.mats.young[0] == 2e7 and np.isnan(restored.mats.kn).all()


def _box_on_a_box():
    """A box dropped edge first onto a box lying on the floor (3D, friction): box rows with
    both the floor and the other box, shear springs loaded."""
    scene = Scene(gravity=(0.0, 0.0, -9.81))
    m = scene.add_material(Material(density=1000.0, kn=2e4, friction=0.4, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    half = np.array([0.0125, 0.0125, 0.0025])
    scene.add_box((0.0, 0.0, 0.0026), half, 0.0005, m)
    tilt = np.array([[1.0, 0.0, 0.0], [0.0, 0.8, -0.6], [0.0, 0.6, 0.8]])
    scene.add_box((0.002, 0.0, 0.02), half, 0.0005, m, orientation=tilt, velocity=(0.05, 0, 0))
    return scene.build(safety=0.2)


def _resume_alike(sim, old):
    restored = Simulation.from_state(old)
    sim.run(n_steps=2000)
    restored.run(n_steps=2000)
    for name in ("pos", "vel", "quat", "omega"):
        np.testing.assert_array_equal(getattr(restored.bodies, name), getattr(sim.bodies, name))
    np.testing.assert_array_equal(restored.rec.ledger, sim.rec.ledger)
    assert restored.energy() == sim.energy()


@pytest.mark.parametrize("version", [1, 2, 3, 4, 5, 6])
def test_an_older_box_state_resumes_bit_identically(version):
    sim = _box_on_a_box()
    sim.run(n_steps=1500)
    assert sim.boxes.rows.n[0] >= 2  # (lying on the floor, struck by the other)
    _resume_alike(sim, older_state(sim.get_state(), version))


@pytest.mark.parametrize("version", [1, 5, 6])
def test_an_older_state_of_boxes_and_balls_resumes_bit_identically(version):
    """Formats 1 to 6 kept the box-sphere rows in a table of their own: read into the one
    table of the box rows, after the others, they continue bit for bit."""
    scene = Scene(gravity=(0.0, 0.0, -9.81))
    m = scene.add_material(Material(density=1000.0, kn=2e4, friction=0.4, restitution=0.5))
    scene.add_wall((0.0, 0.0, 0.0), (0.0, 0.0, 1.0), m)
    half = np.array([0.0125, 0.0125, 0.0025])
    scene.add_box((0.0, 0.0, 0.0026), half, 0.0005, m)
    scene.add_sphere((0.004, 0.0, 0.0092), 0.004, m, velocity=(0.05, 0.0, 0.0))
    scene.add_sphere((-0.006, 0.003, 0.0092), 0.004, m)
    sim = scene.build(safety=0.2)
    sim.run(n_steps=2000)
    rows = sim.boxes.rows
    partners = rows.j[: rows.n[0]]
    assert (partners < 0).any() and (partners >= 1).sum() == 2  # the floor, both balls
    old = older_state(sim.get_state(), version)
    assert old["boxes.sphere_rows.j"].tolist() == [0, 1]
    _resume_alike(sim, old)


def test_a_box_state_missing_a_key_is_refused():
    state = _box_on_a_box().get_state()
    del state["boxes.held_at_build"]
    with pytest.raises(ValueError, match=r"state is missing 'boxes\.held_at_build'"):
        Simulation.from_state(state)


@pytest.mark.parametrize("version", [STATE_FORMAT + 1, 0])
def test_a_state_of_an_unknown_format_is_refused(version):
    state = _bouncing_ball().get_state()
    state["state_format"] = np.array(version)
    with pytest.raises(ValueError, match=f"state_format = {version}: this version of dominowave"):
        Simulation.from_state(state)
    with pytest.raises(ValueError, match=f"state_format = {version}"):
        _bouncing_ball().set_state(state)
