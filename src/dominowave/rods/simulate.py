"""Run the hinged-domino chain: push the first domino, integrate, return what happened.

:class:`RodStepper` is one run in resumable pieces (``advance``, ``get_state``,
``set_state``, ``result``: the checkpoint protocol of :mod:`dominowave.sweep.longrun`);
:func:`simulate` is that run taken to its end in one piece.
"""

from __future__ import annotations

import math
import sys
import warnings
from dataclasses import dataclass

import numpy as np

from dominowave.checks import check_finite, check_in_range, check_memory, check_positive
from dominowave.rods import kernel as _k
from dominowave.rods.model import RodChain

__all__ = ["RodRun", "RodStepper", "simulate"]

_STATUS = {
    _k.STATUS_WAVE_PASSED: "wave passed",
    _k.STATUS_TIME_LIMIT: "time limit",
    _k.STATUS_STALLED: "stalled",
    _k.STATUS_BLOW_UP: "blow-up",
    _k.STATUS_RUNNING: "running",
}


@dataclass(frozen=True)
class RodRun:
    """Result of one run (SI units).

    Attributes
    ----------
    chain : the model that was run.
    push : initial angular velocity of domino 0 [rad/s].
    dt : time step [s]; ``n_steps`` steps up to ``t_end`` [s].
    status : ``"wave passed"``, ``"time limit"`` or ``"stalled"`` (``"running"``: the
        result so far of a :class:`RodStepper` that has not ended).
    events : ``(E, 13)`` contact table, one row per contact, columns ``kernel.EV_*``:
        lower and upper domino, slot kind (0 = the lower's top edge on the upper's back
        face, 1 = the upper's top edge on the lower's front face, 2 = top edge on the back
        face of the domino after next), onset and end time [s] (end NaN if still on),
        peak force [N], angular velocities of both dominoes at onset and end [rad/s],
        peak |H|/V of the upper domino during the contact, steps, peak overlap [m].
    samples : ``(S, 6)`` energy samples ``t, E_kin, E_grav, E_elastic, E_dissipated,
        E_floor`` [s, J] (``E_dissipated`` by dashpots and friction, ``E_floor`` lost at
        floor stops).
    arrival : ``(N,)`` first contact time of each domino with a lower one [s] (NaN never).
    hv_max : ``(N,)`` peak |H|/V of the base reaction over the run.
    lift_steps : ``(N,)`` steps with a non-positive vertical base reaction (lift-off).
    theta_min_after : ``(N,)`` smallest angle after first striking the next domino [rad]
        (the rebound angle; NaN if it never struck).
    theta, omega : ``(N,)`` final state [rad], [rad/s].
    frame_times, frame_theta, frame_omega : ``(F,)``, ``(F, N)``, ``(F, N)`` angles and
        angular velocities every ``frame_every`` steps (``F = 0`` unless requested).
    """

    chain: RodChain
    push: float
    dt: float
    status: str
    t_end: float
    n_steps: int
    events: np.ndarray
    samples: np.ndarray
    arrival: np.ndarray
    hv_max: np.ndarray
    lift_steps: np.ndarray
    theta_min_after: np.ndarray
    theta: np.ndarray
    omega: np.ndarray
    frame_times: np.ndarray
    frame_theta: np.ndarray
    frame_omega: np.ndarray

    @property
    def positions(self) -> np.ndarray:
        """Hinge abscissae ``(N,)`` [m] (pitch ``d + s``)."""
        return np.arange(self.chain.n) * self.chain.pitch

    @property
    def total_energy(self) -> np.ndarray:
        """``E_kin + E_grav + E_elastic`` at the samples, shape ``(S,)`` [J]."""
        return self.samples[:, 1] + self.samples[:, 2] + self.samples[:, 3]

    @property
    def min_steps_per_contact(self) -> float:
        """Fewest time steps a first collision of a neighbour pair lasted (resolution check).

        Later contacts (grazing re-contacts, leaning) may be arbitrarily short and weak;
        the collisions that carry the wave are the ones that must be resolved.
        """
        ev = self.events
        rows = np.nonzero(ev[:, _k.EV_UPPER] == ev[:, _k.EV_LOWER] + 1)[0]
        _, first = np.unique(ev[rows, _k.EV_LOWER], return_index=True)
        rows = rows[first]
        rows = rows[np.isfinite(ev[rows, _k.EV_T_OFF])]
        return float(np.min(ev[rows, _k.EV_STEPS])) if rows.size else math.inf


def _check_energy_ledger(run: RodRun, tolerance: float = 0.05) -> None:
    """Raise ``FloatingPointError`` if the energy ledger broke down (unstable step).

    ``E_kin + E_grav + E_elastic + E_dissipated + E_floor`` is constant up to the
    integration error; a change beyond ``tolerance`` times the energy scale (initial
    kinetic energy plus the potential energy N dominoes can release) means the fixed
    step did not resolve the contacts. Skipped when gravity is switched off in contacts
    (the ledger does not close by construction).
    """
    chain = run.chain
    if not chain.gravity_in_contact or run.samples.shape[0] < 2:
        return
    ledger = run.total_energy + run.samples[:, _k.SA_DISSIPATED] + run.samples[:, _k.SA_FLOOR]
    scale = run.samples[0, _k.SA_KIN] + chain.n * chain.mass.m * chain.g * chain.l
    drift = float(np.max(np.abs(ledger - ledger[0])))
    if drift > tolerance * scale:
        raise FloatingPointError(
            f"rods: the energy balance broke down (drift {drift:.3g} J, scale {scale:.3g} J) "
            f"with dt = {run.dt:.3g} s; reduce dt (raise steps_per_contact)"
        )


class RodStepper:
    """One run of the chain, integrated in resumable pieces.

    Push domino 0 with angular velocity ``push`` [rad/s] and run until the wave passed.
    The run stops ("wave passed") when the last domino's first contact with its
    predecessor has ended or the last domino lies flat (plus ``tail_time`` [s]), or when
    no new domino was reached for ``stall_time`` [s] (default ``20 sqrt(l/g)``; "wave
    passed" if the last domino was reached -- its contact never ended, dominoes lean on
    each other -- else "stalled"), or at ``t_max`` [s] (default ``5 N sqrt(l/g)``).

    ``dt`` defaults to :meth:`RodChain.time_step` with ``steps_per_contact`` (>= 50 is
    the standard; the result warns if a first collision of a pair lasted fewer than 20
    steps).
    ``theta0``/``omega0`` (shape ``(N,)``) replace the default start (all upright at rest,
    domino 0 turning at ``push``); dominoes from the first one at exact rest on are
    treated as untouched (see :mod:`dominowave.rods.kernel`).

    ``n_samples`` energy samples over ``t_max``; at most ``max_events`` contacts recorded
    (default ``200 N + 1000``); ``frame_every`` > 0 records all angles every that many
    steps (at most ``max_frames`` frames; for animations).

    The checkpoint protocol (:mod:`dominowave.sweep.longrun`): :meth:`advance` integrates
    a number of steps, :meth:`get_state` / :meth:`set_state` save and restore everything
    the rest of the run depends on, :meth:`result` is the :class:`RodRun` so far. The
    pieces do not change the arithmetic: ``advance(a); advance(b)`` equals
    ``advance(a + b)`` bit for bit, and so does a run restored from a saved state.

    Raises ``FloatingPointError`` on numerical blow-up (NaN/inf state, from
    :meth:`advance`; an energy ledger that drifted by more than 5 % of the energy scale,
    from :meth:`result`).
    """

    def __init__(
        self,
        chain: RodChain,
        push: float,
        *,
        t_max: float | None = None,
        steps_per_contact: float = 100.0,
        dt: float | None = None,
        theta0: np.ndarray | None = None,
        omega0: np.ndarray | None = None,
        stall_time: float | None = None,
        tail_time: float = 0.0,
        n_samples: int = 2000,
        max_events: int | None = None,
        frame_every: int = 0,
        max_frames: int = 10_000,
    ):
        check_finite("push", push)
        n = chain.n
        time_scale = (
            math.sqrt(chain.l / chain.g)
            if chain.g > 0
            else chain.l / max(abs(push) * chain.l, 1e-12)
        )
        if dt is None:
            dt = chain.time_step(steps_per_contact, speed_bound=None)
        check_positive("dt", dt)
        t_max = 5.0 * n * time_scale if t_max is None else t_max
        check_positive("t_max", t_max)
        stall_time = 20.0 * time_scale if stall_time is None else stall_time
        check_positive("stall_time", stall_time)
        check_in_range("frame_every", frame_every, 0, math.inf, lo_inclusive=True)
        theta = np.zeros(n) if theta0 is None else np.array(theta0, dtype=float)
        omega = np.zeros(n) if omega0 is None else np.array(omega0, dtype=float)
        if theta.shape != (n,) or omega.shape != (n,):
            raise ValueError(
                f"theta0/omega0 must have shape ({n},), got {theta.shape}, {omega.shape}"
            )
        if omega0 is None:
            omega[0] = push
        moving = np.nonzero((theta != 0.0) | (omega != 0.0))[0]
        n_awake = int(moving[-1]) + 1 if moving.size else 1
        n_steps_est = t_max / dt
        sample_every = max(1, int(n_steps_est // max(n_samples - 1, 1)))
        max_events = 200 * n + 1000 if max_events is None else max_events
        frames = int(max_frames) if frame_every > 0 else 0
        records = max_events * _k.EV_COLUMNS + n_samples * _k.SA_COLUMNS + frames * (2 * n + 1)
        check_memory(
            8.0 * (records + 20 * 3 * n),  # + per-contact-slot and per-domino state
            "its state and records",
            f"n = {n}" + (f", max_frames = {frames}" if frames else ""),
        )
        self.chain = chain
        self.push = float(push)
        mass = chain.mass
        self._params = _k.ChainParams.typed(
            chain.l, chain.s, chain.pitch, mass.m, mass.inertia, mass.cm_u, mass.cm_w, chain.g,
            _k.LAW_LINEAR if chain.law == "linear" else _k.LAW_HERTZ,
            chain.k, chain.damping_ratio, chain.mu, chain.friction_speed,
            _k.NORMAL_GEOMETRIC if chain.normal == "geometric" else _k.NORMAL_HEAD_ON,
            chain.floor_restitution, chain.gravity_in_contact,
            dt, t_max, stall_time, tail_time, sample_every, frame_every,
        )  # fmt: skip
        self._state = _k.new_state(
            self._params,
            theta,
            omega,
            n_awake,
            max_events,
            n_samples + 2,
            int(max_frames) if frame_every > 0 else 0,
        )

    @property
    def dt(self) -> float:
        """Time step [s]."""
        return self._params.dt

    @property
    def steps(self) -> int:
        """Time steps done."""
        return int(self._state.step[0])

    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return float(self._state.step[0] * self._params.dt)

    @property
    def end_time(self) -> float:
        """When the run will end as far as known now (``t_max`` until the wave passed) [s]."""
        return float(self._state.t_stop[0])

    @property
    def toppled(self) -> int:
        """Dominoes the wave has reached so far (the pushed one included)."""
        return int(np.count_nonzero(~np.isnan(self._state.arrival)))

    @property
    def done(self) -> bool:
        """True once the run has ended."""
        return int(self._state.status[0]) != _k.STATUS_RUNNING

    def advance(self, n_steps: int) -> bool:
        """Integrate up to ``n_steps`` time steps (fewer if the run ends); True when ended."""
        check_in_range("n_steps", n_steps, 0, math.inf, lo_inclusive=True)
        _k.advance(self._params, self._state, int(n_steps))
        self._check_finite_state()
        return self.done

    def get_state(self) -> dict[str, np.ndarray]:
        """Copies of every array of the run's state (records cut to their filled rows)."""
        state = {name: array.copy() for name, array in self._state._asdict().items()}
        for buffer, counter in _k.RECORDS.items():
            rows = min(int(state[counter][0]), state[buffer].shape[0])
            state[buffer] = state[buffer][:rows]
        return state

    def set_state(self, state: dict[str, np.ndarray]) -> None:
        """Restore a state from :meth:`get_state` (of a run of the same chain and options).

        Raises ``ValueError`` if an array is missing, unknown, or of another dtype or shape.
        """
        current = self._state._asdict()
        unknown = sorted(set(state) - set(current))
        missing = sorted(set(current) - set(state))
        if unknown or missing:
            raise ValueError(f"rods state: unknown arrays {unknown}, missing arrays {missing}")
        counters = _k.RECORDS
        restored = {}
        # record buffers last: they are saved up to the filled rows their counters give
        for name, now in sorted(current.items(), key=lambda item: item[0] in counters):
            array = np.asarray(state[name])
            shape = now.shape
            if name in counters:
                rows = min(int(restored[counters[name]][0]), now.shape[0])
                shape = (rows, *now.shape[1:])
            if array.dtype != now.dtype or array.shape != shape:
                raise ValueError(
                    f"rods state: {name} has dtype {array.dtype} and shape {array.shape},"
                    f" this run needs {now.dtype} and {shape}"
                )
            if name in counters:
                restored[name] = np.full_like(now, np.nan)
                restored[name][: shape[0]] = array
            else:
                restored[name] = array.copy()
        self._state = _k.ChainState(**restored)

    def result(self) -> RodRun:
        """The :class:`RodRun` so far (status ``"running"`` if the run has not ended)."""
        self._check_finite_state()
        st = self._state
        n_events = int(st.n_events[0])
        max_events = st.events.shape[0]
        n_frames = int(st.n_frames[0])
        run = RodRun(
            chain=self.chain,
            push=self.push,
            dt=self.dt,
            status=_STATUS[int(st.status[0])],
            t_end=self.time,
            n_steps=self.steps,
            events=st.events[: min(n_events, max_events)].copy(),
            samples=st.samples[: int(st.n_samples[0])].copy(),
            arrival=st.arrival.copy(),
            hv_max=st.hv_max.copy(),
            lift_steps=st.lift_steps.copy(),
            theta_min_after=st.theta_min_after.copy(),
            theta=st.theta.copy(),
            omega=st.omega.copy(),
            frame_times=st.frame_t[:n_frames].copy(),
            frame_theta=st.frame_theta[:n_frames].copy(),
            frame_omega=st.frame_omega[:n_frames].copy(),
        )
        _check_energy_ledger(run)
        if n_events > max_events:
            warnings.warn(
                f"rods: {n_events} contacts, only the first {max_events} recorded"
                " (raise max_events)",
                RuntimeWarning,
                stacklevel=2,
            )
        if run.min_steps_per_contact < 20:
            warnings.warn(
                f"rods: a contact lasted only {run.min_steps_per_contact:.0f} time steps "
                f"(dt = {run.dt:.3g} s); results may be under-resolved",
                RuntimeWarning,
                stacklevel=2,
            )
        return run

    def _check_finite_state(self) -> None:
        if int(self._state.status[0]) == _k.STATUS_BLOW_UP:
            raise FloatingPointError(
                f"rods: the state became NaN/inf at t = {self.time:.6g} s (dt = {self.dt:.3g} s);"
                " reduce dt (raise steps_per_contact) or check the parameters"
            )


def simulate(chain: RodChain, push: float, **options) -> RodRun:
    """Push domino 0 with angular velocity ``push`` [rad/s] and run until the wave passed.

    The whole run of :class:`RodStepper` (``options``, stop rules, errors: see there)
    in one piece.
    """
    stepper = RodStepper(chain, push, **options)
    stepper.advance(sys.maxsize)
    return stepper.result()
