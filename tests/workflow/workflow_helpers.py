"""Test-only scenarios for the workflow tests (imported by the tests and by dask workers).

* ``slow_theory``: the theory scenario plus a sleep (so a sweep can be killed mid-run)
  and a deliberate failure above a given spacing (so failure records can be checked);
* ``toy_pendulums``: a steppable chain of coupled pendulums (velocity Verlet), the
  stand-in for the simulations in the checkpoint/resume tests.
"""

from __future__ import annotations

import math
import time
from typing import Literal

import numpy as np

from dominowave.io.kinds import register_kind
from dominowave.io.models import TheoryScenario
from dominowave.io.results import RunResult
from dominowave.io.schema import ScenarioModel, quantity
from dominowave.sweep.registry import register_stepper
from dominowave.sweep.run_theory import run_theory


class SlowTheory(TheoryScenario):
    """Theory scenario that sleeps ``delay`` s and fails for spacing > ``fail_above``."""

    kind: Literal["slow_theory"] = "slow_theory"
    delay: float = quantity(0.0, "s", "sleep before returning", ge=0)
    fail_above: float = quantity(
        math.inf, "m", "fail for spacing above this", gt=0, allow_inf_nan=True
    )


def run_slow_theory(cfg: SlowTheory, ctx=None) -> RunResult:
    time.sleep(cfg.delay)
    if cfg.spacing > cfg.fail_above:
        raise RuntimeError(f"deliberate failure at spacing {cfg.spacing}")
    return run_theory(cfg, ctx)


register_kind(SlowTheory, run_slow_theory)


@register_kind
class ToyPendulums(ScenarioModel):
    """Coupled pendulums integrated by velocity Verlet (a deterministic long run)."""

    kind: Literal["toy_pendulums"] = "toy_pendulums"
    n: int = quantity(16, "", "pendulums", ge=2)
    dt: float = quantity(1e-3, "s", "time step", gt=0)
    n_steps: int = quantity(4000, "", "steps to run", ge=1)
    coupling: float = quantity(3.0, "1/s^2", "spring between neighbours", ge=0)
    delay: float = quantity(0.0, "s", "sleep per advance call (to be killable)", ge=0)


SAMPLE_EVERY = 100
"""Steps between energy samples of the toy."""


class PendulumStepper:
    """theta'' = -sin(theta) + coupling * (discrete Laplacian of theta)."""

    def __init__(self, cfg: ToyPendulums):
        self.cfg = cfg
        self.theta = np.linspace(0.0, 1.0, cfg.n) ** 2
        self.omega = np.zeros(cfg.n)
        self.steps = 0
        self.energy_trace = np.zeros(0)

    @property
    def time(self) -> float:
        return self.steps * self.cfg.dt

    @property
    def end_time(self) -> float:
        return self.cfg.n_steps * self.cfg.dt

    @property
    def toppled(self) -> int:
        return int(np.sum(np.abs(self.theta) > 0.5))

    def _accel(self, th):
        lap = np.zeros_like(th)
        lap[1:-1] = th[2:] - 2 * th[1:-1] + th[:-2]
        return -np.sin(th) + self.cfg.coupling * lap

    def advance(self, n_steps: int) -> bool:
        time.sleep(self.cfg.delay)
        dt = self.cfg.dt
        n = min(n_steps, self.cfg.n_steps - self.steps)
        a = self._accel(self.theta)
        for _ in range(n):
            half = self.omega + 0.5 * dt * a
            self.theta = self.theta + dt * half
            a = self._accel(self.theta)
            self.omega = half + 0.5 * dt * a
            self.steps += 1
            if self.steps % SAMPLE_EVERY == 0:  # fixed sampling: independent of chunking
                self.energy_trace = np.append(self.energy_trace, self.energy())
        return self.steps >= self.cfg.n_steps

    def energy(self) -> float:
        spring = 0.5 * self.cfg.coupling * np.sum(np.diff(self.theta) ** 2)
        return float(np.sum(0.5 * self.omega**2 + 1 - np.cos(self.theta)) + spring)

    def get_state(self) -> dict:
        return {
            "theta": self.theta,
            "omega": self.omega,
            "steps": np.array(self.steps),
            "energy_trace": self.energy_trace,
        }

    def set_state(self, state: dict) -> None:
        self.theta = state["theta"].copy()
        self.omega = state["omega"].copy()
        self.steps = int(state["steps"])
        self.energy_trace = state["energy_trace"].copy()

    def result(self) -> RunResult:
        import xarray as xr

        ds = xr.Dataset(
            {
                "theta": ("pendulum", self.theta),
                "omega": ("pendulum", self.omega),
                "energy": ("sample", self.energy_trace),
            }
        )
        return RunResult(summary={"energy": self.energy(), "steps": self.steps}, timeseries=ds)


register_stepper("toy_pendulums", PendulumStepper)
