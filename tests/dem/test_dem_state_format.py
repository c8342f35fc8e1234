"""The layout of a saved simulation state is versioned (``state_format``).

A state of the current format round-trips as it is; a format-1 state (written before the
key existed, without the planar switch, the shear kinematics, the material-pair tables
and the Hertz tables) and a format-2 state (without the sleep settings) are read with the
values their scene had implicitly and resume bit for bit; a state of a newer format is
refused in one line.
"""

from __future__ import annotations

import numpy as np
import pytest

from dominowave.dem import Material, Scene, Simulation
from dominowave.dem.simulation import STATE_FORMAT

FORMAT_2_KEYS = (
    "state_format",
    "settings.planar",
    "planar_kernels",
    "mats.shear_kinematics",
    "mats.pair_friction",
    "mats.pair_restitution",
    "mats.poisson",
    "mats.hertz_damping",
)
"""The keys a format-1 state lacks (with :data:`FORMAT_3_KEYS`)."""
FORMAT_3_KEYS = ("settings.sleep_speed", "settings.sleep_time", "bodies.calm_since")
"""The keys a format-2 state lacks."""


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


def test_a_format_1_state_resumes_bit_identically():
    sim = _bouncing_ball()
    sim.run(n_steps=500)
    old = {k: v for k, v in sim.get_state().items() if k not in FORMAT_2_KEYS + FORMAT_3_KEYS}
    restored = Simulation.from_state(old)
    assert restored.planar_kernels
    sim.run(n_steps=3000)
    restored.run(n_steps=3000)
    for name in ("pos", "vel", "quat", "omega"):
        np.testing.assert_array_equal(getattr(restored.bodies, name), getattr(sim.bodies, name))
    assert sim.bodies.vel_full[0, 2] > 0  # it bounced


def test_a_format_2_state_resumes_bit_identically_and_never_sleeps():
    sim = _bouncing_ball()
    sim.run(n_steps=500)
    old = {k: v for k, v in sim.get_state().items() if k not in FORMAT_3_KEYS}
    old["state_format"] = np.array(2)
    restored = Simulation.from_state(old)
    assert restored.settings.sleep_speed == 0.0
    sim.run(n_steps=3000)
    restored.run(n_steps=3000)
    for name in ("pos", "vel", "quat", "omega"):
        np.testing.assert_array_equal(getattr(restored.bodies, name), getattr(sim.bodies, name))


@pytest.mark.parametrize("version", [STATE_FORMAT + 1, 0])
def test_a_state_of_an_unknown_format_is_refused(version):
    state = _bouncing_ball().get_state()
    state["state_format"] = np.array(version)
    with pytest.raises(ValueError, match=f"state_format = {version}: this version of dominowave"):
        Simulation.from_state(state)
    with pytest.raises(ValueError, match=f"state_format = {version}"):
        _bouncing_ball().set_state(state)
