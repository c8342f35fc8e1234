"""Energy bookkeeping.

At a full step ``t_n`` (positions ``x_n``, velocities ``v_n = (v_{n-1/2} + v_{n+1/2}) / 2``):

* kinetic translational ``sum m |v|^2 / 2``; rotational ``omega . L / 2``;
* gravitational ``- sum m g . x`` (zero at the origin);
* elastic normal ``sum k_n delta^2 / 2`` and tangential ``sum k_t |u_s|^2 / 2`` over active
  contacts;
* dissipated by Coulomb slip, by the viscous dashpots and by local damping, accumulated
  every step in the ledger (see contact_rows.py and integrate.py).

``total`` is the sum of all of them and is constant up to the integration error.
"""

from __future__ import annotations

from numba import njit

from dominowave.dem.contact_rows import rows_elastic_energy

__all__ = ["ENERGY_NAMES", "energies"]

ENERGY_NAMES = (
    "kinetic_translational",
    "kinetic_rotational",
    "gravitational",
    "elastic_normal",
    "elastic_tangential",
    "dissipated_friction",
    "dissipated_viscous",
    "dissipated_damping",
    "total",
)
# indices of the ENERGY_NAMES vectors (energies, engine.Recorder.energy_*)
E_KINETIC_TRANSLATIONAL = 0
E_KINETIC_ROTATIONAL = 1
E_GRAVITATIONAL = 2
E_ELASTIC_NORMAL = 3
E_ELASTIC_TANGENTIAL = 4
E_DISSIPATED_FRICTION = 5
E_DISSIPATED_VISCOUS = 6
E_DISSIPATED_DAMPING = 7
E_TOTAL = 8
N_ENERGIES = 9
N_MECHANICAL = 5  # the first entries: kinetic, gravitational and elastic energy

# the engine's (3,) dissipation ledger (engine.Recorder.ledger) [J]
LEDGER_FRICTION = 0
LEDGER_VISCOUS = 1
LEDGER_DAMPING = 2

# the engine's (3,) record of the last step's powers (engine.Recorder.power) [W]
LAST_POWER_VISCOUS = 0
LAST_POWER_DAMPING = 1
LAST_POWER_FRICTION = 2


@njit(cache=True, error_model="numpy", _nrt=False)
def kinetic_energy(bodies, out):
    """Translational and rotational kinetic energy [J] at the last full step into
    ``out[E_KINETIC_TRANSLATIONAL]``, ``out[E_KINETIC_ROTATIONAL]``."""
    et = 0.0
    er = 0.0
    for b in range(bodies.mass.shape[0]):
        v = bodies.vel_full[b]
        w = bodies.omega_full[b]
        L = bodies.angmom_full[b]
        et += 0.5 * bodies.mass[b] * (v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        er += 0.5 * (w[0] * L[0] + w[1] * L[1] + w[2] * L[2])
    out[E_KINETIC_TRANSLATIONAL] = et
    out[E_KINETIC_ROTATIONAL] = er


@njit(cache=True, error_model="numpy", _nrt=False)
def energies(bodies, contacts, gravity, ledger, out):
    """All entries of ``ENERGY_NAMES`` [J] into ``out`` (length N_ENERGIES), the elastic
    ones of the sphere contacts ``contacts`` (the box contacts' are added by
    boxes.box_energies)."""
    kinetic_energy(bodies, out)
    eg = 0.0
    for b in range(bodies.mass.shape[0]):
        x = bodies.pos[b]
        eg -= bodies.mass[b] * (gravity[0] * x[0] + gravity[1] * x[1] + gravity[2] * x[2])
    en, es = rows_elastic_energy(contacts, False)
    out[E_GRAVITATIONAL] = eg
    out[E_ELASTIC_NORMAL] = en
    out[E_ELASTIC_TANGENTIAL] = es
    out[E_DISSIPATED_FRICTION] = ledger[LEDGER_FRICTION]
    out[E_DISSIPATED_VISCOUS] = ledger[LEDGER_VISCOUS]
    out[E_DISSIPATED_DAMPING] = ledger[LEDGER_DAMPING]
    total = 0.0
    for k in range(E_TOTAL):  # (every entry before the total, in order)
        total += out[k]
    out[E_TOTAL] = total
