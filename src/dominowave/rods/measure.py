"""Measurements per collision and per domino from the contact table of a run."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dominowave.rods import kernel as _k

__all__ = ["Collisions", "first_collisions", "struck_omega"]


@dataclass(frozen=True)
class Collisions:
    """The first collision of each neighbour pair ``(n, n+1)``, arrays of shape ``(N-1,)``.

    NaN where the pair never touched. Times [s], forces [N], angular velocities [rad/s]
    in the paper's notation: ``omega_f`` = Omega_fn (striker before), ``omega_b`` =
    Omega_bn (striker after), ``omega_next`` = Omega_{n+1} (struck domino after).
    ``n_contacts``: distinct contacts of the pair over the whole run (both slot kinds);
    ``n_skip_contacts``: contacts of ``n`` with ``n+2``; ``hv_struck``: peak |H|/V of
    domino ``n+1`` during the first collision; ``delta_max`` peak overlap [m];
    ``rebound``: the smallest angle of ``n`` after it struck ``n+1`` [rad].
    """

    t_on: np.ndarray
    t_off: np.ndarray
    peak_force: np.ndarray
    omega_f: np.ndarray
    omega_b: np.ndarray
    omega_next: np.ndarray
    n_contacts: np.ndarray
    n_skip_contacts: np.ndarray
    hv_struck: np.ndarray
    delta_max: np.ndarray
    rebound: np.ndarray

    @property
    def duration(self) -> np.ndarray:
        """Duration of the first collision of each pair [s]."""
        return self.t_off - self.t_on

    @property
    def transfer(self) -> np.ndarray:
        """Measured ``Omega_{n+1} / Omega_fn`` (compare with f_+, eq 3)."""
        return self.omega_next / self.omega_f

    @property
    def rebound_ratio(self) -> np.ndarray:
        """Measured ``Omega_bn / Omega_fn`` (compare with f_+/f_-, eq 3)."""
        return self.omega_b / self.omega_f


def first_collisions(run) -> Collisions:
    """Per-pair first-collision table of a :class:`~dominowave.rods.RodRun`."""
    n_pairs = run.chain.n - 1
    ev = run.events
    lower = ev[:, _k.EV_LOWER].astype(np.int64)
    upper = ev[:, _k.EV_UPPER].astype(np.int64)
    neighbour = upper == lower + 1
    cols = (
        _k.EV_T_ON,
        _k.EV_T_OFF,
        _k.EV_F_MAX,
        _k.EV_W_LO_ON,
        _k.EV_W_LO_OFF,
        _k.EV_W_UP_OFF,
        _k.EV_HV_UP,
        _k.EV_DELTA_MAX,
    )
    table = np.full((len(cols), n_pairs), np.nan)
    # events are stored in onset order: the first row of each pair is its first collision
    rows = np.nonzero(neighbour)[0]
    pairs, first = np.unique(lower[rows], return_index=True)
    for c, col in enumerate(cols):
        table[c, pairs] = ev[rows[first], col]
    # a contact still on at the end of the run has no end: no post-collision values
    n_contacts = np.bincount(lower[neighbour], minlength=n_pairs)[:n_pairs]
    n_skip = np.bincount(lower[upper == lower + 2], minlength=n_pairs)[:n_pairs]
    return Collisions(
        t_on=table[0],
        t_off=table[1],
        peak_force=table[2],
        omega_f=table[3],
        omega_b=table[4],
        omega_next=table[5],
        n_contacts=n_contacts,
        n_skip_contacts=n_skip,
        hv_struck=table[6],
        delta_max=table[7],
        rebound=run.theta_min_after[:n_pairs].copy(),
    )


def struck_omega(run) -> np.ndarray:
    """``Omega_n``: angular velocity of domino ``n`` just after it was first struck.

    Shape ``(N,)`` [rad/s]; entry 0 is the push. Compare with eq 8.
    """
    out = np.full(run.chain.n, np.nan)
    out[0] = run.push
    out[1:] = first_collisions(run).omega_next
    return out
