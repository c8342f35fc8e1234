"""The ``theory`` scenario: the closed-form wave of the paper for one chain.

Summary: the limit wave speeds (eqs 14, 20, 34), the P-wave bounds (eqs 33, 35),
the collision time (eq 31), the peak contact force and regime (eqs 37-42), and the
steady speed measured on the theory's own arrival times (transient from eq 8).
Events: one row per domino -- start time, Omega_n (eq 8), free-fall time T_n
(eq 12), first contact time. Trajectory: see :func:`theory_trajectory`.
"""

from __future__ import annotations

import numpy as np

from dominowave import theory
from dominowave.chain.wave import local_speeds, steady_speed
from dominowave.checks import check_memory
from dominowave.io.models import TheoryScenario
from dominowave.io.results import RunResult
from dominowave.io.trajectory import ChainTrajectory
from dominowave.sweep.context import RunContext

__all__ = ["lean_angle", "run_theory", "theory_trajectory"]

_THETA_EPS = 1e-9  # fall_time needs an angle strictly inside (0, pi/2)


def lean_angle(theta_next, pitch, thickness, height):
    """Angle [rad] of a domino whose top front edge rests on the back face of the next.

    Pivots (front bottom edges) ``pitch = d + s`` apart, the next domino at
    ``theta_next``: ``l sin(theta - theta_next) = pitch cos(theta_next) - s``.
    At ``theta_next = 0`` this is ``beta = asin(d / l)``; a domino lying flat
    (``pi/2``) holds its predecessor at ``pi/2 - asin(s/l)``.
    """
    ratio = np.clip((pitch * np.cos(theta_next) - thickness) / height, -1.0, 1.0)
    return np.minimum(theta_next + np.arcsin(ratio), np.pi / 2)


TRAJECTORY_FIELDS = 6
"""(n_frames, N) float arrays a theory trajectory holds at its peak (angles, spins,
pivot positions and the temporaries of one domino's fall)."""


def theory_trajectory(cfg: TheoryScenario, start, omega, t_c, n_frames) -> ChainTrajectory:
    """Side-view kinematics of the theory's wave, for drawing (not a prediction).

    Domino ``n`` starts upright at ``start[n]`` with ``omega[n]`` and falls freely
    (eq 10: the time to reach an angle is :func:`dominowave.theory.fall_time`,
    inverted by interpolation). Once it reaches ``beta`` it rests on domino ``n+1``
    (:func:`lean_angle`), as dominoes do in a real chain; the EJ model itself has it
    bounce back (eq 9a), which matters for the next wave, not for the primary one
    this picture shows. The last domino falls to the floor.
    """
    l, s, g = cfg.height, cfg.thickness, cfg.g
    pitch = cfg.spacing + s
    beta = np.arcsin(cfg.d_over_l)
    n = start.size
    check_memory(
        8.0 * n_frames * n * TRAJECTORY_FIELDS,
        "its trajectory",
        f"n_dominoes = {n}, n_frames = {n_frames}",
    )
    # free-fall time to reach each angle of a grid, per domino (N, M)
    grid = np.linspace(_THETA_EPS, np.pi / 2 - _THETA_EPS, 400)
    tau = theory.fall_time(omega[:, None], grid[None, :], l, g)
    t_end = start[-1] + tau[-1, -1]
    time = np.linspace(0.0, t_end, n_frames)
    angle = np.zeros((n_frames, n))

    def free_fall(i):
        since = time - start[i]
        theta = np.interp(since, np.concatenate([[0.0], tau[i]]), np.concatenate([[0.0], grid]))
        return np.where(since > 0, theta, 0.0)

    angle[:, -1] = free_fall(n - 1)
    for i in range(n - 2, -1, -1):
        falling = free_fall(i)
        leaning = lean_angle(angle[:, i + 1], pitch, s, l)
        hit = start[i] + theory.fall_time(omega[i], beta, l, g)
        angle[:, i] = np.where(time < hit, np.minimum(falling, beta), leaning)
    base_x = np.arange(n) * pitch
    return ChainTrajectory(time=time, base_x=base_x, angle=angle, height=l, thickness=s)


def run_theory(cfg: TheoryScenario, ctx: RunContext | None = None) -> RunResult:
    """Evaluate the theory for the chain ``cfg`` (SI units in and out)."""
    l, m, s, g = cfg.height, cfg.mass, cfg.thickness, cfg.g
    d, k, conv = cfg.spacing, cfg.contact_stiffness, cfg.stiffness_convention
    beta = float(np.arcsin(cfg.d_over_l))
    t_c = float(theory.collision_time(k, m, beta, conv))
    fm = float(theory.peak_contact_force(beta, l, m, k, g, conv))
    regime = theory.classify_regime(beta, fm / (m * g), cfg.friction_floor, s / l)
    n_dom = cfg.n_dominoes
    start = theory.arrival_times(n_dom, cfg.push_omega, beta, l, g, collision_time=t_c)
    omega = np.sqrt(theory.omega_n_squared(np.arange(1, n_dom + 1), cfg.push_omega, beta, l, g))
    fall = theory.fall_time(omega, beta, l, g)
    contact = np.concatenate([[0.0], start[1:] - t_c / 2.0])  # first touch by the previous one
    position = np.arange(n_dom) * (d + s)
    measured = steady_speed(contact, position)
    summary = {
        "kind": "theory",
        "d_over_l": cfg.d_over_l,
        "beta": beta,
        "stiffness": k,
        "stiffness_over_kstar": k / cfg.k_star,
        "collision_time": t_c,
        "fall_time_limit": float(theory.fall_time_limit(beta, l, g)),
        "omega_limit": float(theory.omega_limit(beta, l, g)),
        "speed_rigid": float(theory.wave_speed_rigid(beta, l, g)),
        "speed_compliant": float(theory.wave_speed(beta, l, m, k, g, conv)),
        "speed": float(theory.wave_speed_thick(beta, l, m, k, s, g, conv)),
        "speed_p_wave": float(theory.p_wave_speed_thick(beta, l, m, k, s, conv)),
        "pair_regime": bool(theory.pair_regime_holds(beta, l, m, k, g, conv)),
        "peak_force": fm,
        "peak_force_over_weight": fm / (m * g),
        "regime": str(regime.name),
        "measured_speed": measured.speed,
        "measured_speed_err": measured.speed_err,
        "dominoes_toppled": n_dom,
    }
    events = {
        "domino": np.arange(1, n_dom + 1),
        "position": position,
        "arrival_time": contact,
        "start_time": start,
        "omega": omega,
        "fall_time": fall,
        "local_speed": np.concatenate([local_speeds(contact, position), [np.nan]]),
    }
    trajectory = theory_trajectory(cfg, start, omega, t_c, cfg.n_frames)
    return RunResult(
        summary=summary,
        events=events,
        trajectory=trajectory,
        may_be_nan=("measured_speed", "measured_speed_err"),
    )
