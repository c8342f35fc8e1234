"""Mass properties of a uniform cuboid and of a rounded cuboid (a sphero-box).

A cuboid has half-extents (a, b, c) [m] along its principal axes x, y, z and density rho
[kg/m^3]. A rounded cuboid is the Minkowski sum of that box (its *core*) and a ball of
radius r [m] (Alonso-Marroquin 2008; Galindo-Torres et al. 2009): its outer half-extents
are (a + r, b + r, c + r). Both are centred at the origin and symmetric under x -> -x,
y -> -y, z -> -z, so the centre of mass is the origin, the products of inertia vanish and
the principal moments follow from the second moments S_x = int x^2 dV [m^5]:

    I_xx = rho (S_y + S_z),  I_yy = rho (S_z + S_x),  I_zz = rho (S_x + S_y).     (I)

The rounded body splits into disjoint pieces (the rounded rectangle of a planar domino
likewise, per unit length along y):

    core box 2a x 2b x 2c; six slabs of thickness r on the faces; twelve quarter
    cylinders of radius r along the edges (four per axis, together a full cylinder);
    eight ball octants at the corners (together a ball).

Each piece's volume and second moments are elementary: with u >= 0 the distance beyond
the face (x = a + u), int u dA over a quarter disc = r^3/3, int u^2 dA = pi r^4/16;
over a ball octant int dV = pi r^3/6, int u dV = pi r^4/16, int u^2 dV = pi r^5/30.
No import of dominowave. Units: SI.
"""

from __future__ import annotations

import math

import numpy as np


def box_mass_properties(a, b, c, rho):
    """Uniform cuboid of half-extents ``a, b, c`` [m], density ``rho`` [kg/m^3]:
    (mass [kg], principal moments (3,) about the centre [kg m^2]),

        m = 8 a b c rho,  I = (m/3) (b^2 + c^2, c^2 + a^2, a^2 + b^2)

    (the textbook m (L_y^2 + L_z^2) / 12 with full extents L = 2 a, ...)."""
    m = 8.0 * a * b * c * rho
    return m, m / 3.0 * np.array([b * b + c * c, c * c + a * a, a * a + b * b])


def parallel_axis(inertia_centre, m, distance):
    """Moment of inertia [kg m^2] about an axis parallel to a principal axis through the
    centre of mass, at ``distance`` [m] from it (Steiner): I = I_c + m distance^2."""
    return inertia_centre + m * distance * distance


def box_edge_inertia(a, b, c, rho):
    """Moment of inertia [kg m^2] of the uniform cuboid about one of its edges parallel to
    y (a domino tipping over its bottom front edge, thickness 2a, height 2c):

        I_edge = m (a^2 + c^2) / 3 + m (a^2 + c^2) = (4/3) m (a^2 + c^2)
               = m (s^2 + l^2) / 3 with s = 2a, l = 2c."""
    m, inertia = box_mass_properties(a, b, c, rho)
    return parallel_axis(inertia[1], m, math.hypot(a, c))


def _rounded_volume_and_second_moment(a, b, c, r):
    """Volume [m^3] and S_x = int x^2 dV [m^5] of the box (a, b, c) swept by radius r,
    summed piece by piece (module docstring)."""
    pi = math.pi
    volume = (
        8.0 * a * b * c  # core
        + 8.0 * r * (a * b + b * c + c * a)  # 6 slabs
        + 2.0 * pi * r * r * (a + b + c)  # 12 quarter cylinders
        + 4.0 / 3.0 * pi * r**3  # 8 octants
    )
    x2_core = 2.0 * a**3 / 3.0  # int_{-a}^{a} x^2 dx
    x2_out = 2.0 * ((a + r) ** 3 - a**3) / 3.0  # int over a < |x| < a + r
    # a quarter disc (or ball octant) at x = a + u, u >= 0, summed over the 4 (8) corners
    disc_x2 = pi * r * r * a * a + 8.0 * a * r**3 / 3.0 + pi * r**4 / 4.0
    s_x = (
        x2_core * 4.0 * b * c  # core
        + x2_out * 4.0 * b * c  # the two x-slabs
        + x2_core * 2.0 * r * 2.0 * c  # the two y-slabs
        + x2_core * 2.0 * b * 2.0 * r  # the two z-slabs
        + x2_core * pi * r * r  # the quarter cylinders along x: a full disc at each x
        + 2.0 * b * disc_x2  # along y: four quarter discs at x = +-a
        + 2.0 * c * disc_x2  # along z: likewise
        + 4.0 / 3.0 * pi * a * a * r**3
        + pi * a * r**4
        + 4.0 / 15.0 * pi * r**5  # octants
    )
    return volume, s_x


def rounded_box_mass_properties(a, b, c, r, rho):
    """Rounded cuboid: core half-extents ``a, b, c`` [m] swept by a ball of radius ``r``
    [m], uniform density ``rho`` [kg/m^3]. Returns (volume [m^3], mass [kg], principal
    moments (3,) about the centre [kg m^2]); the centre of mass is the core's centre.

        V = 8abc + 8r(ab + bc + ca) + 2 pi r^2 (a + b + c) + (4/3) pi r^3,

    the moments by eq (I) from the piece-wise S_x, S_y, S_z (exact; r = 0 is the box,
    a = b = c = 0 the ball m (2/5) r^2)."""
    volume, s_x = _rounded_volume_and_second_moment(a, b, c, r)
    _, s_y = _rounded_volume_and_second_moment(b, c, a, r)
    _, s_z = _rounded_volume_and_second_moment(c, a, b, r)
    inertia = rho * np.array([s_y + s_z, s_z + s_x, s_x + s_y])
    return volume, rho * volume, inertia


def rounded_rectangle_mass_properties(a, c, r, sigma):
    """Planar rounded rectangle (a domino in the xz plane): core half-extents ``a``
    (along x) and ``c`` (along z) [m] swept by a disc of radius ``r`` [m], areal density
    ``sigma`` [kg/m^2] (density x width). Returns (area [m^2], mass [kg], polar moment
    I_yy = sigma int (x^2 + z^2) dA about the centre [kg m^2]):

        A = 4ac + 4r(a + c) + pi r^2,
        int x^2 dA = (2a^3/3)(2c + 2r) + (2/3)((a + r)^3 - a^3) 2c
                     + pi r^2 a^2 + 8 a r^3/3 + pi r^4/4 (four quarter discs at x = +-a),

    and int z^2 dA with a and c exchanged."""

    def x2(a, c):
        pi = math.pi
        return (
            2.0 * a**3 / 3.0 * (2.0 * c + 2.0 * r)  # core and the two z-slabs
            + 2.0 * ((a + r) ** 3 - a**3) / 3.0 * 2.0 * c  # the two x-slabs
            + pi * r * r * a * a
            + 8.0 * a * r**3 / 3.0
            + pi * r**4 / 4.0  # corners
        )

    area = 4.0 * a * c + 4.0 * r * (a + c) + math.pi * r * r
    return area, sigma * area, sigma * (x2(a, c) + x2(c, a))
