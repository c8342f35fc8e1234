"""The reduced rod model against the theory of section 2 (``dominowave compare-rods``).

The rod model (:mod:`dominowave.rods`) obeys Newton's laws only; the theory
(:mod:`dominowave.theory`) is the paper's closed forms. This module builds the rod
model of ONE paper parameter point, runs it, and puts the measurements beside the
formulas (the grid over many points is a study, :mod:`dominowave.sweep.compare_rods`;
its figures are drawn by :mod:`dominowave.plots.compare_rods`):

* collision duration of the first collision vs ``T_c`` (eq 31), peak force vs ``F_m`` (eq 37);
* collision map ``Omega_{n+1}/Omega_fn`` vs ``f_+`` and ``Omega_bn/Omega_fn`` vs ``f_+/f_-`` (eq 3);
* steady wave speed vs eq 20 / eq 34 and the P-wave bound (eq 33 / 35);
* ``Omega_n`` against eq 8 for pushes below and above the limit (Fig 1D);
* whether consecutive collisions overlap in time (pair regime ``T > T_c/2``).

Stiffness map (explicit): the paper's ``k`` is the stiffness *per particle*, the
contact spring is ``k_r = k/2`` (eq 24, convention ``"paper"`` of the theory); the rod
model takes the contact spring itself, so ``RodChain.k = k_r = k/2``.

Units: SI; the defaults ``l = m = 1`` and ``g = 9.81`` make ``k* = m g / l = 9.81 N/m``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from dominowave import theory
from dominowave.chain.wave import first_and_second_onsets, secondary_wave, steady_speed
from dominowave.checks import check_in_range, check_positive
from dominowave.rods import RodChain, block, first_collisions, point_mass, simulate, struck_omega
from dominowave.rods import kernel as rods_kernel
from dominowave.rods import thin_rod as thin_rod_mass
from dominowave.units import G_STANDARD, beta_from_spacing, k_star, speed_scale

__all__ = ["Comparison", "OmegaProfile", "compare_point", "omega_profile", "paper_chain"]

MASS_MODELS = ("point", "rod", "block")


def paper_chain(
    d_over_l: float,
    k_over_kstar: float,
    n: int,
    *,
    normal: str = "geometric",
    mass_model: str = "point",
    s_over_l: float = 0.0,
    law: str = "linear",
    l: float = 1.0,
    m: float = 1.0,
    g: float = G_STANDARD,
    **options,
) -> RodChain:
    """The rod model of a paper parameter point ``(d/l, k/k*)``.

    The paper's per-particle stiffness ``k = (k/k*) m g / l`` becomes the contact
    spring ``k_r = k/2`` (eq 24, "paper" convention). ``mass_model``: ``"point"``
    (the paper's), ``"rod"`` (uniform thin rod) or ``"block"``. Extra ``options`` go
    to :class:`~dominowave.rods.RodChain` (damping_ratio, mu, floor_restitution).
    """
    check_in_range("d_over_l", d_over_l, 0.0, 1.0)
    check_positive("k_over_kstar", k_over_kstar)
    if mass_model not in MASS_MODELS:
        raise ValueError(f"mass_model = {mass_model!r} is not one of {MASS_MODELS}")
    s = s_over_l * l
    mass = {
        "point": lambda: point_mass(m, l),
        "rod": lambda: thin_rod_mass(m, l, s),
        "block": lambda: block(m, l, s),
    }[mass_model]()
    k_r = float(theory.contact_stiffness(k_over_kstar * k_star(m, l, g), "paper"))
    return RodChain(
        n=n, l=l, d=d_over_l * l, s=s, mass=mass, k=k_r, law=law, normal=normal, g=g, **options
    )


@dataclass(frozen=True)
class Comparison:
    """One parameter point: measured (rods) beside theory, SI units.

    ``*_first``: the first collision (dominoes 1 -> 2, pushed at the theory's limit
    ``Omega``, so it is the theory's steady collision); ``*_median``: median over all
    first collisions of neighbour pairs that ended. Speeds [m/s] (``speed_scale`` =
    ``sqrt(g l)``): ``speed`` fitted over
    the settled part (NaN if the profile never settled), ``speed_end`` the median local
    speed over the last 10 % of the chain. ``overlap_fraction``: share of consecutive
    first collisions that overlap in time (0 = pair-wise). ``max_contacts``: most
    contacts any neighbour pair had. ``hv_median``: median peak |H|/V of struck dominoes
    during their first collision (large when V passes near 0); ``slip_fraction``: share of
    struck dominoes whose peak |H|/V in that collision exceeds the floor friction
    ``floor_mu`` (they would slide if the hinge were a frictional floor), beside the motion
    the theory predicts from ``F_m`` (eqs 38-42, ``regime_theory``); ``lift_fraction``: share of
    struck dominoes whose base reaction V became <= 0 at some time (the hinge had to pull).
    ``secondary_*``: the wave of second contacts of neighbour pairs
    (:func:`dominowave.chain.wave.secondary_wave`, merged = lag below one collision
    time): whether it gains on the primary wave, and the pair where it caught it (-1).
    """

    d_over_l: float
    k_over_kstar: float
    normal: str
    mass_model: str
    n: int
    status: str
    push: float
    tc_theory: float
    tc_first: float
    tc_median: float
    fm_theory: float
    f_first: float
    f_median: float
    f_plus: float
    transfer_first: float
    transfer_median: float
    rebound_theory: float
    rebound_first: float
    rebound_median: float
    speed_scale: float
    speed_theory: float
    speed_rigid: float
    speed_p_wave: float
    speed: float
    speed_err: float
    speed_end: float
    settled_from: int
    pair_regime_theory: bool
    overlap_fraction: float
    max_contacts: int
    hv_median: float
    floor_mu: float
    slip_fraction: float
    regime_theory: str
    lift_fraction: float
    secondary_catching_up: bool
    secondary_merged_pair: int
    n_steps: int


def compare_point(
    d_over_l: float,
    k_over_kstar: float,
    *,
    n: int = 60,
    normal: str = "geometric",
    mass_model: str = "point",
    push_factor: float = 1.0,
    steps_per_contact: float = 100.0,
    floor_mu: float = 0.3,
    **chain_options,
) -> Comparison:
    """Run the rod model at ``(d/l, k/k*)`` and compare with the theory.

    Domino 0 is pushed with ``push_factor`` times the theory's limit angular velocity
    ``Omega`` (eq 9) -- only the initial condition comes from the theory. ``floor_mu``
    (default the paper's 0.3) is the floor friction the base reaction is compared with;
    the model itself is hinged. A run whose
    energy ledger breaks down is repeated once with a 4x finer step (a second failure
    raises ``FloatingPointError``).
    """
    chain = paper_chain(
        d_over_l, k_over_kstar, n, normal=normal, mass_model=mass_model, **chain_options
    )
    l, m, g = chain.l, chain.mass.m, chain.g
    beta = float(beta_from_spacing(d_over_l))
    k_paper = k_over_kstar * float(k_star(m, l, g))
    omega_lim = float(theory.omega_limit(beta, l, g))
    push = push_factor * omega_lim
    try:
        run = simulate(chain, push=push, steps_per_contact=steps_per_contact)
    except FloatingPointError:
        # a point the fixed step does not resolve: retry once with a 4x finer step
        run = simulate(chain, push=push, steps_per_contact=4 * steps_per_contact)
    col = first_collisions(run)
    ended = np.isfinite(col.t_off)
    f_plus = float(theory.f_plus(beta))

    def first_and_median(values):
        v = values[ended]
        first = float(values[1]) if ended.size > 1 and ended[1] else math.nan
        return first, float(np.median(v)) if v.size else math.nan

    tc_first, tc_median = first_and_median(col.duration)
    f_first, f_median = first_and_median(col.peak_force)
    tr_first, tr_median = first_and_median(col.transfer)
    rb_first, rb_median = first_and_median(col.rebound_ratio)
    fit = steady_speed(run.arrival, run.positions)
    local = np.diff(run.positions) / np.diff(run.arrival)
    tail = local[np.isfinite(local)][-max(2, n // 10) :]
    # consecutive first collisions overlapping in time: (n, n+1) still on when (n+1, n+2) starts
    both = ended[:-1] & np.isfinite(col.t_on[1:])
    overlaps = col.t_off[:-1][both] > col.t_on[1:][both]
    second = _secondary(run, tc_median)
    fm_theory = float(theory.peak_contact_force(beta, l, m, k_paper, g, "paper"))
    regime = theory.classify_regime(beta, fm_theory / (m * g), floor_mu, chain.s / l)
    hv_struck = col.hv_struck[ended]
    return Comparison(
        d_over_l=d_over_l,
        k_over_kstar=k_over_kstar,
        normal=normal,
        mass_model=mass_model,
        n=n,
        status=run.status,
        push=push,
        tc_theory=float(theory.collision_time(k_paper, m, beta, "paper")),
        tc_first=tc_first,
        tc_median=tc_median,
        fm_theory=fm_theory,
        f_first=f_first,
        f_median=f_median,
        f_plus=f_plus,
        transfer_first=tr_first,
        transfer_median=tr_median,
        rebound_theory=f_plus / float(theory.f_minus(beta)),
        rebound_first=rb_first,
        rebound_median=rb_median,
        speed_scale=float(speed_scale(l, g)),
        speed_theory=float(theory.wave_speed_thick(beta, l, m, k_paper, chain.s, g, "paper")),
        speed_rigid=float(theory.wave_speed_rigid(beta, l, g)),
        speed_p_wave=float(theory.p_wave_speed_thick(beta, l, m, k_paper, chain.s, "paper")),
        speed=fit.speed,
        speed_err=fit.speed_err,
        speed_end=float(np.median(tail)) if tail.size else math.nan,
        settled_from=fit.first,
        pair_regime_theory=bool(theory.pair_regime_holds(beta, l, m, k_paper, g, "paper")),
        overlap_fraction=float(np.mean(overlaps)) if overlaps.size else math.nan,
        max_contacts=int(col.n_contacts.max()),
        hv_median=float(np.median(hv_struck)) if hv_struck.size else math.nan,
        floor_mu=floor_mu,
        slip_fraction=float(np.mean(hv_struck > floor_mu)) if hv_struck.size else math.nan,
        regime_theory=str(regime.name),
        lift_fraction=float(np.mean(run.lift_steps[1:] > 0)),
        secondary_catching_up=bool(second is not None and second.catching_up),
        secondary_merged_pair=-1
        if second is None or second.merged_pair is None
        else int(second.merged_pair),
        n_steps=run.n_steps,
    )


def _secondary(run, merge_lag):
    """Secondary wave of re-contacts of neighbour pairs (None if there is none)."""
    ev = run.events
    lower = ev[:, rods_kernel.EV_LOWER].astype(np.int64)
    neighbour = ev[:, rods_kernel.EV_UPPER].astype(np.int64) == lower + 1
    onsets = [[] for _ in range(run.chain.n - 1)]
    for pair, t_on in zip(lower[neighbour], ev[neighbour, rods_kernel.EV_T_ON], strict=True):
        onsets[pair].append(t_on)
    first, second = first_and_second_onsets(onsets)
    lag = merge_lag if math.isfinite(merge_lag) else 0.0
    return secondary_wave(first, second, run.positions[1:], merge_lag=lag)


@dataclass(frozen=True)
class OmegaProfile:
    """``Omega_n`` measured (rods) and from eq 8, shape ``(N,)`` each [rad/s]."""

    push: float
    omega_limit: float
    measured: np.ndarray
    theory: np.ndarray


def omega_profile(
    d_over_l: float,
    k_over_kstar: float,
    push_factor: float,
    *,
    n: int = 30,
    normal: str = "head-on",
    **kwargs,
) -> OmegaProfile:
    """``Omega_n`` (angular velocity just after domino n is struck) vs eq 8 (Fig 1D).

    The pushed domino is the paper's domino 1 (``Omega_1`` = push = ``push_factor Omega``).
    """
    chain = paper_chain(d_over_l, k_over_kstar, n, normal=normal, **kwargs)
    beta = float(beta_from_spacing(d_over_l))
    omega_lim = float(theory.omega_limit(beta, chain.l, chain.g))
    push = push_factor * omega_lim
    run = simulate(chain, push=push)
    index = np.arange(1, n + 1)
    predicted = np.sqrt(theory.omega_n_squared(index, push, beta, chain.l, chain.g))
    return OmegaProfile(push, omega_lim, struck_omega(run), np.asarray(predicted, dtype=float))
