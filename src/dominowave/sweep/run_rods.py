"""The ``rods`` scenario: the paper's hinged compliant dominoes, simulated.

The chain is built by :func:`dominowave.chain.theory_vs_rods.paper_chain` (the
paper's per-particle stiffness ``k`` becomes the contact spring ``k/2``, eq 24)
and run by :func:`dominowave.rods.simulate`. The wave speed is fitted to the
first-contact times by :func:`dominowave.chain.wave.steady_speed` (NaN if the wave
did not settle within the chain); the theory's ``v^s`` (eq 34) for the same
parameters is stored beside it. Warnings of the simulation (e.g. an
under-resolved contact) are kept in the summary.

The angles and angular velocities of every domino are recorded as frames (at the
interval :func:`frame_schedule` chooses) and returned as the side-view
:class:`~dominowave.io.trajectory.ChainTrajectory` (:func:`rods_trajectory`) that
``dominowave animate`` and ``--vtk`` draw.

The run is checkpointable: :class:`RodsScenarioStepper` advances
:class:`dominowave.rods.RodStepper` in pieces, and :func:`run_rods` drives it through
:func:`dominowave.sweep.longrun.run_stepping` (checkpoints, resume, Ctrl-C, progress).
The recorded frames are part of the stepper's state, so a resumed run has the frames of
an uninterrupted one, bit for bit.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from dominowave import theory
from dominowave.chain.theory_vs_rods import paper_chain
from dominowave.chain.wave import local_speeds, steady_speed, unsettled_reason
from dominowave.io.models import RodsScenario
from dominowave.io.results import RunResult
from dominowave.io.trajectory import ChainTrajectory
from dominowave.rods import RodChain, RodRun, RodStepper
from dominowave.sweep.context import RunContext
from dominowave.sweep.longrun import ScenarioStepper, run_stepping

__all__ = [
    "FRAME_INTERVAL",
    "FRAME_VALUES",
    "RodsScenarioStepper",
    "frame_schedule",
    "rods_chain",
    "rods_result",
    "rods_trajectory",
    "run_rods",
]

_ENERGY_COLUMNS = ("kinetic", "gravitational", "elastic", "dissipated", "floor")

FRAME_INTERVAL = 0.02
"""Time between trajectory frames in units of ``sqrt(l/g)`` (~450 frames for the
default 30-domino run, which lasts ~9 ``sqrt(l/g)``; the chain kind uses 0.01)."""

FRAME_VALUES = 2_500_000
"""At most this many angles (frames x dominoes) fit the frame buffer (40 MB with the
angular velocities); long chains get a coarser interval instead of a truncated film."""

TIME_LIMIT = 5.0
"""The run ends at ``t_max = TIME_LIMIT N sqrt(l/g)`` at the latest (RodStepper's own
default, given explicitly because the frame buffer is sized from it)."""


def run_rods(cfg: RodsScenario, ctx: RunContext | None = None) -> RunResult:
    """Simulate the chain ``cfg`` and measure its wave (SI units); checkpointable."""
    return run_stepping(cfg, ctx, factory=RodsScenarioStepper)


def rods_chain(cfg: RodsScenario) -> RodChain:
    """The hinged-domino chain of ``cfg`` (the paper's ``k`` becomes the spring ``k/2``)."""
    return paper_chain(
        cfg.d_over_l,
        cfg.contact_stiffness / cfg.k_star,
        cfg.n_dominoes,
        normal=cfg.normal,
        mass_model=cfg.mass_model,
        s_over_l=cfg.thickness / cfg.height,
        l=cfg.height,
        m=cfg.mass,
        g=cfg.g,
        damping_ratio=cfg.damping_ratio,
        mu=cfg.friction_dominoes,
        floor_restitution=cfg.restitution_floor,
    )


def frame_schedule(t_max: float, dt: float, n: int, time_scale: float) -> tuple[int, int]:
    """Steps between frames and frame-buffer rows for a run of ``n`` dominoes.

    The interval is ``FRAME_INTERVAL * time_scale`` [s] (``time_scale = sqrt(l/g)``),
    widened where needed so that frames over the whole ``t_max`` [s] hold at most
    ``FRAME_VALUES`` angles: no run, however long, outgrows its buffer (with the
    scenario's ``t_max = TIME_LIMIT N sqrt(l/g)`` the interval grows as ``N^2`` beyond
    100 dominoes: fewer frames per domino toppled). ``dt`` [s] is the time step.
    Returns ``(every, max_frames)``: frames are taken at the steps that are multiples
    of ``every``, frame 0 included, into a buffer of ``max_frames`` rows.
    """
    interval = max(FRAME_INTERVAL * time_scale, t_max * n / FRAME_VALUES)
    every = max(1, round(interval / dt))
    max_frames = (math.ceil(t_max / dt) + 1) // every + 2
    return every, max_frames


class RodsScenarioStepper(ScenarioStepper):
    """The rods run of ``cfg`` in resumable pieces (protocol: :mod:`dominowave.sweep.longrun`).

    Everything but :meth:`result` is that of :class:`dominowave.rods.RodStepper`, which
    records frames as :func:`frame_schedule` says; :meth:`result` measures the run so far
    into a :class:`RunResult` with the trajectory.
    """

    def __init__(self, cfg: RodsScenario):
        self.cfg = cfg
        chain = rods_chain(cfg)
        dt = chain.time_step(cfg.steps_per_contact)
        time_scale = math.sqrt(chain.l / chain.g)
        t_max = TIME_LIMIT * chain.n * time_scale
        every, max_frames = frame_schedule(t_max, dt, chain.n, time_scale)
        self.stepper = RodStepper(
            chain, cfg.push_omega, dt=dt, t_max=t_max, frame_every=every, max_frames=max_frames
        )

    def result(self) -> RunResult:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            run = self.stepper.result()
        return rods_result(self.cfg, run, [str(w.message) for w in caught])


def rods_trajectory(run: RodRun) -> ChainTrajectory:
    """Side view of ``run``: its frames, plus the final state if later than the last frame.

    The rods model and :class:`ChainTrajectory` share the geometry: domino ``i`` turns
    about its front bottom edge at ``x_i = i (d + s)`` on the floor, its angle positive
    towards +x (:mod:`dominowave.rods.contact`), so the pivots and angles pass unchanged.
    """
    chain = run.chain
    time, theta, omega = run.frame_times, run.frame_theta, run.frame_omega
    if time.size == 0 or run.t_end > time[-1]:
        time = np.append(time, run.t_end)
        theta = np.vstack([theta, run.theta])
        omega = np.vstack([omega, run.omega])
    return ChainTrajectory(
        time=time,
        base_x=run.positions,
        angle=theta,
        height=chain.l,
        thickness=chain.s,
        omega=omega,
    )


def speed_note(cfg: RodsScenario, run: RodRun) -> str:
    """Why the run's wave did not settle ("" if it did), for ``summary.json``.

    The face-normal contact without damping or friction passes the whole push on at
    each collision (f+ -> 1): that wave has no limit speed at any chain length.
    """
    reason = unsettled_reason(run.arrival, run.positions)
    elastic = cfg.damping_ratio == 0 and cfg.friction_dominoes == 0
    if reason and cfg.normal == "geometric" and elastic:
        reason += (
            "; with normal = geometric and neither damping_ratio nor friction_dominoes, each"
            " collision passes on the whole push (f+ -> 1) and the wave has no limit speed:"
            ' normal = "head-on" is the theory\'s collision rule'
        )
    return reason


def rods_result(cfg: RodsScenario, run: RodRun, warned: list[str]) -> RunResult:
    """Summary, per-domino events, energy/contact time series and trajectory of ``run``."""
    import xarray as xr

    l, m, s, g = cfg.height, cfg.mass, cfg.thickness, cfg.g
    positions = run.positions
    fit = steady_speed(run.arrival, positions)
    beta = float(np.arcsin(cfg.d_over_l))
    k = cfg.contact_stiffness
    energy = run.total_energy
    summary = {
        "kind": "rods",
        "d_over_l": cfg.d_over_l,
        "stiffness": k,
        "stiffness_over_kstar": k / cfg.k_star,
        "status": run.status,
        "end_time": run.t_end,
        "n_steps": run.n_steps,
        "dt": run.dt,
        "speed": fit.speed,
        "speed_err": fit.speed_err,
        "speed_settled": bool(fit.settled),
        "speed_note": speed_note(cfg, run),
        "dominoes_toppled": int(fit.reached),
        "speed_theory": float(theory.wave_speed_thick(beta, l, m, k, s, g)),
        "pair_regime_theory": bool(theory.pair_regime_holds(beta, l, m, k, g)),
        "energy_drift": float((energy[-1] - energy[0]) / abs(energy[0])) if energy.size else 0.0,
        "min_steps_per_contact": run.min_steps_per_contact,
        "warnings": "; ".join(warned),
    }
    events = {
        "domino": np.arange(1, run.chain.n + 1),
        "position": positions,
        "arrival_time": run.arrival,
        "local_speed": np.concatenate([local_speeds(run.arrival, positions), [np.nan]]),
        "peak_h_over_v": run.hv_max,
        "lift_steps": run.lift_steps,
        "rebound_angle": run.theta_min_after,
    }
    samples = run.samples
    timeseries = xr.Dataset(
        {
            f"energy_{name}": ("time", samples[:, i + 1], {"units": "J"})
            for i, name in enumerate(_ENERGY_COLUMNS)
        },
        coords={"time": ("time", samples[:, 0], {"units": "s"})},
    )
    timeseries["contacts"] = (("contact", "contact_column"), run.events)
    return RunResult(
        summary=summary,
        events=events,
        timeseries=timeseries,
        trajectory=rods_trajectory(run),
        may_be_nan=("speed", "speed_err"),
    )
