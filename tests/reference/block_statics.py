"""Statics of a block pushed on its back face: signed moments about its centre of mass.

The block of the paper's section 2.4 (eqs 38-42), in units of its height l and weight
m g: height 1, thickness s/l, base from x = -s/2 to s/2 on the floor, centre of mass
G at (0, 1/2). x points forwards (the wave's direction), y up. The contact force of
the falling domino, f in units of m g, acts on the back face at height cos(beta); its
horizontal part is f cos(beta). The floor holds the block with a normal force 1 at x_N
and kinetic friction mu along -x (the base slides forwards) or +x (backwards).

Each regime boundary is the force f at which a signed moment (a cross product, linear
in f) changes sign, found by brentq. No import of dominowave.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq


def moment(point, force, about):
    """Signed z component of (point - about) x force [in units of m g l]: negative means
    clockwise, the top of the block turning forwards. 2D points and forces (x, y)."""
    r = np.subtract(point, about)
    return r[0] * force[1] - r[1] * force[0]


def block_moment_about_com(f, beta, mu, s_over_l, friction, x_normal):
    """Signed moment about G of the push f cos(beta) at (-s/2, cos beta), the friction
    ``friction`` * mu (``friction`` = +1: along +x, the base sliding backwards; -1: along
    -x, forwards) and the normal force 1, both at (x_normal, 0)."""
    s = s_over_l
    centre = (0.0, 0.5)
    push = moment((-s / 2, np.cos(beta)), (f * np.cos(beta), 0.0), centre)
    floor = moment((x_normal, 0.0), (friction * mu, 0.0), centre)
    normal = moment((x_normal, 0.0), (0.0, 1.0), centre)
    return push + floor + normal


def sign_change_force(moment_of_f):
    """The force f in (-1e7, 1e7) at which ``moment_of_f`` (linear in f) changes sign,
    by brentq to 1e-14."""
    return brentq(moment_of_f, -1e7, 1e7, xtol=1e-14, rtol=1e-14)
