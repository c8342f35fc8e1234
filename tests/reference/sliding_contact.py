"""A rounded box driven at constant velocity over a fixed rounded box: the quasi-static
contact force of a single contact in full slip.

Box A (core centre x_A(t) [m], rotation R_A, core half-extents h_A, rounding r_A) moves
without turning at constant velocity v (3,) [m/s] past box B (c_B, R_B, h_B, r_B), which
is fixed. Their cores are D(t) apart (``box_distance.box_box_distance``: bounded least
squares, whatever feature pair -- vertex-face, vertex-edge, edge-edge -- attains it), so
they overlap by delta = r_A + r_B - D, along the unit normal n from B's closest core
point to A's. With a linear normal spring k_n and Coulomb friction mu in full slip (the
tangential spring saturated), the force of B on A is

    F = k_n delta n - mu k_n delta t,   t = v_t / |v_t|,  v_t = v - (v . n) n,      (F)

the friction opposing the tangential velocity of A relative to B, and the energy stored
in the contact is

    E = k_n delta^2 / 2 + (mu k_n delta)^2 / (2 k_t)                               (E)

(the normal spring, and the tangential spring k_t stretched to the Coulomb limit). Both
are continuous functions of x_A, since D is, and n turns continuously over the rounded
edges and corners of the bodies. A force history computed along the path is therefore
smooth: it changes by at most |dF/dx| |v| dt per step dt, whatever feature pair touches.

No import of dominowave. Units: SI.
"""

from __future__ import annotations

import numpy as np

from reference.box_distance import box_box_distance


def sliding_contact(centre_a, rotation_a, half_a, r_a, centre_b, rotation_b, half_b, r_b,
                    velocity, kn, kt, mu):  # fmt: skip
    """(force on A (3,) [N], stored energy [J], overlap [m]) of the single full-slip
    contact of eqs (F) and (E); zeros when the bodies are apart (delta <= 0). ``velocity``
    (3,) [m/s] is A's relative to B; it must have a tangential part at the contact."""
    dist, point_b, point_a = box_box_distance(
        centre_b, rotation_b, half_b, centre_a, rotation_a, half_a
    )
    delta = r_a + r_b - dist
    if delta <= 0.0:
        return np.zeros(3), 0.0, delta
    if dist == 0.0:
        raise ValueError("the cores intersect: the normal is undefined")
    n = (point_a - point_b) / dist
    v = np.asarray(velocity, float)
    v_t = v - (v @ n) * n
    speed = np.linalg.norm(v_t)
    if speed == 0.0:
        raise ValueError("velocity has no tangential part at the contact: slip undefined")
    fn = kn * delta
    force = fn * n - mu * fn * v_t / speed
    energy = 0.5 * kn * delta**2 + 0.5 * (mu * fn) ** 2 / kt
    return force, energy, delta
