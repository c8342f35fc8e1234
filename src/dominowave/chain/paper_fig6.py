"""One member of the paper's Fig 6 (B-E) ensembles: build, push, run, measure.

Each *configuration* is a set of ``ChainParams`` changes from the 2D default chain
(s/l = 0.1, k/k* = 1e4, phi_f = 0.3, phi_d = 0, no damping, held until touched):

====================  ==========================================  ==========
name                  change                                      panels
====================  ==========================================  ==========
2d                    none                                        B C D E
3d                    model="3d" (w/l = 0.5, free in 6 DOF)       B
3d_asym               3d with a seeded random yaw (lateral asym.) B
k1e3, k1e5            stiffness_ratio = 1e3, 1e5                  C
damp_small/large      local damping 0.02 / 0.1                    D E
mu0.6                 floor friction 0.6                          D
====================  ==========================================  ==========

:func:`run_member` runs one ensemble member of one (configuration, d/l): member ``i``
scales the push by ``1 + jitter N(0,1)`` from ``default_rng([seed, i])``
(:func:`~dominowave.chain.scenario.member_push_factor`, the ``DominoChain.ensemble``
rule), and returns its measurements as one row. The sweep over configurations,
spacings and members, and the ensemble statistics, are a study:
:mod:`dominowave.sweep.fig6`.

``shape = "box"`` builds every configuration of rounded cuboids instead of clumps
(``ChainParams(shape="box")``: the same l, s, w and density, the cuboid's own mass,
k/k* per box with ``k_n = k/4`` per contact point, the same friction and local damping;
docs/shape.md). The box chain of this preset is not held until touched: its data
(docs/fig6/box) were measured with every box free, and a held box chain equals the free
one to round-off (docs/shape.md, "Holding a box until it is touched").
"""

from __future__ import annotations

import numpy as np

from dominowave.chain.build import ChainParams, Shape
from dominowave.chain.compare import theory_speed
from dominowave.chain.scenario import DominoChain, member_push_factor

__all__ = ["CONFIGS", "MEMBER_FIELDS", "fig6_params", "run_member"]

CONFIGS: dict[str, dict] = {
    "2d": {},
    "3d": {"model": "3d"},
    "3d_asym": {"model": "3d", "lateral_asymmetry": 0.02},
    "k1e3": {"stiffness_ratio": 1e3},
    "k1e5": {"stiffness_ratio": 1e5},
    "damp_small": {"damping": 0.02},
    "damp_large": {"damping": 0.1},
    "mu0.6": {"friction_floor": 0.6},
}
"""Configuration name -> ``ChainParams`` changes (see the module docstring)."""

MEMBER_FIELDS = (
    "n_dominoes",
    "push_omega",
    "speed",
    "speed_err",
    "settled",
    "first",
    "last",
    "reached",
    "theory_speed",
    "theory_speed_point",
    "theory_speed_rigid",
    "theory_window_speed",
    "multiple_collision_fraction",
    "mean_hits_in_passage",
    "mean_abs_slip",
    "forward_slip_fraction",
    "wall_time",
    "n_steps",
)
"""What :func:`run_member` measures, in this order (SI units: rad/s, m/s, m, s)."""


def fig6_params(
    config: str, d_over_l: float, n_dominoes: int, shape: Shape = "clump"
) -> ChainParams:
    """The chain of configuration ``config`` (a key of :data:`CONFIGS`) at gap ``d/l``,
    of ``shape`` dominoes (``"clump"``, the paper's, held until touched, or ``"box"``,
    not held: module docstring)."""
    if config not in CONFIGS:
        raise ValueError(f"config = {config!r} is not one of {', '.join(CONFIGS)}")
    return ChainParams(
        n_dominoes=n_dominoes, d_over_l=d_over_l, shape=shape, held=shape == "clump",
        **CONFIGS[config],
    )  # fmt: skip


def run_member(
    config: str,
    d_over_l: float,
    member: int,
    n_dominoes: int,
    seed: int,
    jitter: float,
    shape: Shape = "clump",
) -> dict:
    """Run ensemble member ``member`` of ``(config, d/l)`` of ``shape`` dominoes and
    measure its wave.

    The push is the chain's default push (``omega = sqrt(g/l)``) scaled by
    :func:`member_push_factor` ``(seed, member, jitter)``. Returns
    :data:`MEMBER_FIELDS` -> value: the measured push ``push_omega`` [rad/s], the
    steady speed and its error [m/s] (NaN if the wave did not settle; ``settled``
    0/1, ``first``/``last`` the dominoes of the fit, ``reached`` the dominoes
    toppled), the theory's limit speeds eq 34 with the clump mapping, the paper's
    point-mass usage and the rigid limit eq 14 [m/s], the theory's transient over
    the fitted dominoes [m/s], the fraction of interior pairs hit more than once
    before the next arrival and their mean hits, the mean |base slip| [m], the
    fraction of dominoes in mechanism II (forward rotation + slip, Fig 5A), and the
    engine's wall time [s] and steps.
    """
    p = fig6_params(config, d_over_l, n_dominoes, shape)
    chain = DominoChain(p, sleep=False)  # (the box preset's data were measured awake)
    base = chain.resolve(None)
    run = chain.run(base.scaled(member_push_factor(seed, member, jitter)))
    ev = run.events
    interior = slice(1, p.n_dominoes - 2)  # pairs whose passage is defined
    hits = ev.n_hits_in_passage[interior]
    return {
        "n_dominoes": p.n_dominoes,
        "push_omega": run.omega_1,
        "speed": run.wave.speed,
        "speed_err": run.wave.speed_err,
        "settled": int(run.wave.settled),
        "first": run.wave.first,
        "last": run.wave.last,
        "reached": run.wave.reached,
        "theory_speed": run.theory_speed,
        "theory_speed_point": theory_speed(p, "point"),
        "theory_speed_rigid": theory_speed(p, rigid=True),
        "theory_window_speed": run.theory_window_speed,
        "multiple_collision_fraction": float(np.mean(hits > 1)),
        "mean_hits_in_passage": float(np.mean(hits)),
        "mean_abs_slip": float(np.mean(np.abs(ev.slip_final[:-1]))),
        "forward_slip_fraction": float(np.mean(ev.mechanism[1:] == 2)),
        "wall_time": run.wall_time,
        "n_steps": run.n_steps,
    }
