"""Planar rigid dominoes with linear contact springs: an independent simulation of a chain.

Each domino is a rigid body of spheres moving in the xz plane, state (x, z, theta) of its
centre of mass; sphere k sits at com + Rot(theta) local_k. Every overlapping sphere pair of
neighbouring dominoes, and every sphere below z = r (the floor), pushes with a linear
spring k_n * overlap along the centre line / the vertical; no friction, no damping.
Newton's and Euler's laws for each body are integrated with scipy's DOP853 (rtol 1e-11,
atol 1e-14), the contact onsets located by events. It shares no code with the DEM engine
it checks. Units: SI (m, s, rad, kg, N/m).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

from .rigid_chain import G


@dataclass(frozen=True)
class PlanarBodies:
    """B identical rigid bodies of S spheres in the xz plane, state
    y = (x_0, z_0, theta_0, ..., x_{B-1}, z_{B-1}, theta_{B-1}, then their rates) (6B,).

    ``local`` (S, 2) sphere offsets (x, z) from the centre of mass at theta = 0 [m];
    ``radii`` (S,) [m]; ``mass`` [kg] and ``inertia`` about the centre of mass's y axis
    [kg m^2] of one body; ``kn`` linear contact stiffness [N/m]; ``g`` gravity [m/s^2].
    Body i touches only bodies i - 1, i + 1 and the floor z = 0.
    """

    local: np.ndarray
    radii: np.ndarray
    mass: float
    inertia: float
    kn: float
    g: float = G

    def spheres(self, y):
        """Sphere centres (px, pz), each (B, S) [m]: com + Rot(theta) local (positive
        theta turns +z towards +x, a rotation about +y)."""
        nb = y.size // 6
        x, z, th = y[0 : 3 * nb : 3], y[1 : 3 * nb : 3], y[2 : 3 * nb : 3]
        c, s = np.cos(th)[:, None], np.sin(th)[:, None]
        px = x[:, None] + c * self.local[None, :, 0] + s * self.local[None, :, 1]
        pz = z[:, None] - s * self.local[None, :, 0] + c * self.local[None, :, 1]
        return px, pz

    def pair_overlaps(self, px, pz, i):
        """Centre differences (dx, dz), distances and overlaps (S, S) of bodies i, i + 1."""
        dx = px[i][:, None] - px[i + 1][None, :]
        dz = pz[i][:, None] - pz[i + 1][None, :]
        d = np.sqrt(dx * dx + dz * dz)
        return dx, dz, d, self.radii[:, None] + self.radii[None, :] - d

    def rhs(self, _t, y):
        """y' (6B,): Newton for the centres of mass, Euler about y for the tilts."""
        nb = y.size // 6
        kn = self.kn
        px, pz = self.spheres(y)
        fx = np.zeros_like(px)
        fz = np.zeros_like(pz)
        pen = self.radii[None, :] - pz  # floor
        fz += np.where(pen > 0, kn * pen, 0.0)
        for i in range(nb - 1):
            dx, dz, d, ov = self.pair_overlaps(px, pz, i)
            f = np.where(ov > 0, kn * ov / d, 0.0)
            fx[i] += (f * dx).sum(axis=1)
            fz[i] += (f * dz).sum(axis=1)
            fx[i + 1] -= (f * dx).sum(axis=0)
            fz[i + 1] -= (f * dz).sum(axis=0)
        x, z = y[0 : 3 * nb : 3], y[1 : 3 * nb : 3]
        torque = ((pz - z[:, None]) * fx - (px - x[:, None]) * fz).sum(axis=1)
        dy = np.empty_like(y)
        dy[: 3 * nb] = y[3 * nb :]
        acc = np.empty(3 * nb)
        acc[0::3] = fx.sum(axis=1) / self.mass
        acc[1::3] = fz.sum(axis=1) / self.mass - self.g
        acc[2::3] = torque / self.inertia
        dy[3 * nb :] = acc
        return dy

    def energy(self, y):
        """Total energy [J]: kinetic (translation and rotation), gravitational (m g z) and
        elastic (k_n overlap^2 / 2 for each floor and sphere-pair contact). The springs
        are conservative, so it is constant along an exact solution."""
        nb = y.size // 6
        v = y[3 * nb :]
        kinetic = 0.5 * self.mass * np.sum(v[0::3] ** 2 + v[1::3] ** 2)
        kinetic += 0.5 * self.inertia * np.sum(v[2::3] ** 2)
        gravity = self.mass * self.g * np.sum(y[1 : 3 * nb : 3])
        px, pz = self.spheres(y)
        pen = np.maximum(self.radii[None, :] - pz, 0.0)
        elastic = 0.5 * self.kn * np.sum(pen**2)
        for i in range(nb - 1):
            ov = np.maximum(self.pair_overlaps(px, pz, i)[3], 0.0)
            elastic += 0.5 * self.kn * np.sum(ov**2)
        return kinetic + gravity + elastic

    def solve(self, centres0, vel0, t_end, max_step=5e-5, dense_output=False):
        """Integrate from centres of mass ``centres0`` (B, 2) [m] (theta = 0) and velocities
        ``vel0`` (B, 3) (vx, vz, omega_y) over [0, ``t_end``] s: scipy DOP853, rtol 1e-11,
        atol 1e-14, step at most ``max_step`` [s]; event i is the first touch of bodies
        i and i + 1 (the smallest sphere gap crossing zero downwards)."""
        nb = centres0.shape[0]

        def gap_event(i):
            def ev(t, y):
                return float(np.min(-self.pair_overlaps(*self.spheres(y), i)[3]))

            ev.terminal = False
            ev.direction = -1
            return ev

        y0 = np.concatenate([np.column_stack([centres0, np.zeros(nb)]).ravel(), vel0.ravel()])
        return solve_ivp(
            self.rhs,
            (0.0, t_end),
            y0,
            method="DOP853",
            rtol=1e-11,
            atol=1e-14,
            max_step=max_step,
            events=[gap_event(i) for i in range(nb - 1)],
            dense_output=dense_output,
        )


def planar_chain_collisions(
    local, radii, masses_total, inertia_cm, kn, centres0, vel0, g=G, t_end=0.2, max_step=5e-5
):
    """First-contact time [s] of body n with body n - 1 for n = 1..B-1 (NaN if none before
    ``t_end``), shape (B - 1,), of the planar rigid bodies (:class:`PlanarBodies`).

    local (S, 2) sphere offsets (x, z) from the COM at theta = 0; radii (S,);
    masses_total, inertia_cm: body mass [kg] and inertia about the COM's y axis [kg m^2];
    centres0 (B, 2) initial COM (x, z); vel0 (B, 3) initial (vx, vz, omega_y).
    """
    bodies = PlanarBodies(
        np.asarray(local, dtype=float),
        np.asarray(radii, dtype=float),
        masses_total,
        inertia_cm,
        kn,
        g,
    )
    sol = bodies.solve(centres0, vel0, t_end, max_step)
    return np.array([e[0] if e.size else np.nan for e in sol.t_events])


def chain_collisions(chain, push, t_end, max_step=5e-5):
    """:func:`planar_chain_collisions` for the initial state of a 2D ``DominoChain`` pushed
    by ``push``: the chain supplies only geometry, masses, k_n and the push velocities
    (COM at rest on the sink of its base, domino 0 with the push's (vx, vz, omega_y));
    the integration is independent of the engine."""
    p, shape = chain.params, chain.shape
    com = shape.centre_of_mass
    centres0 = np.array([[x + com[0], com[2] - chain._sink()] for x in chain.positions])
    v0, w0, _ = chain._push_velocities(push)
    vel0 = np.zeros((len(chain.positions), 3))
    vel0[0] = [v0[0], v0[2], w0[1]]
    return planar_chain_collisions(
        (shape.centres - com)[:, [0, 2]],
        shape.radii,
        shape.mass,
        shape.inertia_about_y(com),
        p.contact_stiffness,
        centres0,
        vel0,
        g=p.g,
        t_end=t_end,
        max_step=max_step,
    )
