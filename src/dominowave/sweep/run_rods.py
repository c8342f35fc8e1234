"""The ``rods`` scenario: the paper's hinged compliant dominoes, simulated (issue 5).

The chain is built by :func:`dominowave.chain.theory_vs_rods.paper_chain` (the
paper's per-particle stiffness ``k`` becomes the contact spring ``k/2``, eq 24)
and run by :func:`dominowave.rods.simulate`. The wave speed is fitted to the
first-contact times by :func:`dominowave.chain.wave.steady_speed` (NaN if the wave
did not settle within the chain); the theory's ``v^s`` (eq 34) for the same
parameters is stored beside it. Warnings of the simulation (e.g. an
under-resolved contact) are kept in the summary.

The run is checkpointable: :class:`RodsScenarioStepper` advances
:class:`dominowave.rods.RodStepper` in pieces, and :func:`run_rods` drives it through
:func:`dominowave.sweep.longrun.run_stepping` (checkpoints, resume, Ctrl-C, progress).
"""

from __future__ import annotations

import warnings

import numpy as np

from dominowave import theory
from dominowave.chain.theory_vs_rods import paper_chain
from dominowave.chain.wave import local_speeds, steady_speed
from dominowave.io.models import RodsScenario
from dominowave.io.results import RunResult
from dominowave.rods import RodChain, RodRun, RodStepper
from dominowave.sweep.longrun import run_stepping
from dominowave.sweep.registry import RunContext

__all__ = ["RodsScenarioStepper", "rods_chain", "rods_result", "run_rods"]

_ENERGY_COLUMNS = ("kinetic", "gravitational", "elastic", "dissipated", "floor")


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
        g=cfg.gravity,
        damping_ratio=cfg.damping_ratio,
        mu=cfg.contact_friction,
        floor_restitution=cfg.floor_restitution,
    )


class RodsScenarioStepper:
    """The rods run of ``cfg`` in resumable pieces (protocol: :mod:`dominowave.sweep.longrun`).

    Everything but :meth:`result` is that of :class:`dominowave.rods.RodStepper`;
    :meth:`result` measures the run so far into a :class:`RunResult`.
    """

    def __init__(self, cfg: RodsScenario):
        self.cfg = cfg
        self.stepper = RodStepper(
            rods_chain(cfg), cfg.push_omega, steps_per_contact=cfg.steps_per_contact
        )

    @property
    def time(self) -> float:
        return self.stepper.time

    @property
    def end_time(self) -> float:
        return self.stepper.end_time

    @property
    def steps(self) -> int:
        return self.stepper.steps

    @property
    def toppled(self) -> int:
        return self.stepper.toppled

    def advance(self, n_steps: int) -> bool:
        return self.stepper.advance(n_steps)

    def get_state(self) -> dict[str, np.ndarray]:
        return self.stepper.get_state()

    def set_state(self, state: dict[str, np.ndarray]) -> None:
        self.stepper.set_state(state)

    def result(self) -> RunResult:
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            run = self.stepper.result()
        return rods_result(self.cfg, run, [str(w.message) for w in caught])


def rods_result(cfg: RodsScenario, run: RodRun, warned: list[str]) -> RunResult:
    """Summary, per-domino events and energy/contact time series of ``run`` (SI units)."""
    import xarray as xr

    l, m, s, g = cfg.height, cfg.mass, cfg.thickness, cfg.gravity
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
        may_be_nan=("speed", "speed_err"),
    )
