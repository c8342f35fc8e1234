"""Fixtures of the DEM tests."""

import pytest
from dem_scenes import RHO, R

from dominowave.dem import Material, Scene


@pytest.fixture
def two_sphere_scene():
    """Factory: two equal spheres approaching head-on along x, no gravity."""

    def make(velocity=0.1, gap=0.001, restitution=None, kn=1e4):
        scene = Scene(gravity=(0.0, 0.0, 0.0))
        m = scene.add_material(Material(density=RHO, kn=kn, restitution=restitution))
        scene.add_sphere((0.0, 0.0, 0.0), R, m, velocity=(velocity, 0.0, 0.0))
        scene.add_sphere((2 * R + gap, 0.0, 0.0), R, m, velocity=(-velocity, 0.0, 0.0))
        return scene

    return make
