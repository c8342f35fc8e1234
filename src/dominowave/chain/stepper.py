"""A domino-chain run in resumable pieces: the one loop behind ``DominoChain.run``.

``ChainStepper(chain, push)`` owns the ``dem`` simulation of one run and advances it
in two phases, as the paper's runs do: (1) until the wave touches the last domino, dies
out (no new contact for ``chain.quiet_time``) or ``chain.max_time`` is reached; (2) if
it touched the last domino, a tail of ``chain.tail_time`` for the aftermath, which ends
sooner once every domino is at rest (held: asleep, or never touched), where nothing
moves again (``dem.StopCondition.at_rest``).  The record of such a run ends where the
whole tail would have ended (a contact still open then ends there, as in the longer
run), with the frames and events of the longer run: it would only repeat the last frame.

It satisfies the stepper protocol of :mod:`dominowave.sweep.longrun`:
``advance(n_steps) -> done``, ``time``, ``end_time``, ``steps``, ``toppled``,
``get_state()`` / ``set_state()`` (the engine state plus the phase, the trajectory
frames and contact events recorded so far, the counters) and ``result()`` (the
``ChainRun`` so far). With ``contact_forces=True`` the engine also records the force of
every active contact at each frame (``dem.ContactFrames``), kept in the saved state and
returned by :meth:`contact_frames`. ``advance(a); advance(b)`` gives the same bits as
``advance(a + b)``, so a run resumed from a checkpoint ends exactly as an
uninterrupted one.

Why the quiet-time stop is not simply the engine's: the engine counts
``StopCondition.no_onset_for`` from the last contact onset *or from the start of the
current* ``Simulation.run`` *call*, whichever is later, so split into calls it would
stop later than in one call. The stepper therefore asks the engine for the steps to the
quiet stop counted from the phase's start (:func:`dominowave.dem.engine.steps_until_quiet`,
the engine's own test on the engine's clock) and caps each engine call there; an engine
call that reaches the cap with no new onset is the quiet stop.
"""

from __future__ import annotations

import math
import time

import numpy as np

from dominowave import dem
from dominowave.chain.events import ChainRecord
from dominowave.chain.frames import FIELDS, SparseFrames
from dominowave.checks import check_format
from dominowave.dem.engine import steps_until_quiet

__all__ = ["ChainStepper", "steps_until_quiet"]

_FRAMES = ("times", *FIELDS)
"""The dense trajectory frames of a checkpoint, one row per frame
(:meth:`~dominowave.chain.frames.SparseFrames.dense`)."""
_EVENTS = ("time", "body_i", "body_j", "kind")
"""Contact event arrays of a ``dem`` run result, one row per event."""
_EVENT_DTYPES = (np.float64, np.int64, np.int64, np.int8)
"""Their dtypes in the engine's recorder (``dem.engine.Recorder``)."""
_CONTACTS = ("count", "first", "second", "point", "force")
"""Recorded contact forces: rows per frame (``count``), then the ``dem.ContactFrames`` rows."""
_CONTACT_SHAPES = (((), np.int64), ((), np.int64), ((), np.int64), ((3,), float), ((3,), float))
"""Row shape and dtype of each of them (empty pieces)."""
_REASONS = ("", "touched", "no_onset", "until")
"""Why phase 1 ended ('' while it runs), coded by index in the checkpoint."""
STATE_FORMAT = 2
"""Version of the layout of :meth:`ChainStepper.get_state` (key ``stepper_format``; the
simulation's own state has its version, ``dem.simulation.STATE_FORMAT``).  1 (states
without the key): ``record_end`` may be missing, from a run that did not stop at rest,
whose record ends at the run's time."""


class ChainStepper:
    """The run of ``chain`` (a ``DominoChain``) pushed by ``push``, advanced on demand.

    ``time`` [s] simulated so far; ``end_time`` [s] the latest it can end (``max_time``
    in phase 1, the end of the tail in phase 2); ``steps`` time steps done;
    ``toppled`` dominoes the wave has reached (domino 0 counts once it hits domino 1).
    """

    def __init__(self, chain, push, contact_forces: bool = False):
        self.chain = chain
        self.contact_forces = contact_forces
        self.push = push
        self.sim, self.omega_1 = chain.build(push)
        self.every = max(1, round(chain.frame_interval / self.sim.dt))
        self.steps = 0
        self.phase = 1
        self.done = False
        self.stop_reason = ""
        self.tail_end = math.nan
        self.record_end = math.nan  # [s] where the record ends if not now (stopped at rest)
        self.wall_time = 0.0
        self.reached = 0
        self.frames = SparseFrames(chain.initial_frame(self.sim, push))
        self.events = {
            k: [np.zeros(0, dtype)] for k, dtype in zip(_EVENTS, _EVENT_DTYPES, strict=True)
        }
        # the initial frame (before the first step) has no recorded contacts
        self.contacts = _empty_contacts(n_frames=1) if contact_forces else {}

    # --- where the run is ---------------------------------------------------------------
    @property
    def time(self) -> float:
        return float(self.sim.time)

    @property
    def end_time(self) -> float:
        return self.chain.max_time if self.phase == 1 else self.tail_end

    @property
    def toppled(self) -> int:
        return self.reached

    # --- running ------------------------------------------------------------------------
    def advance(self, n_steps: int) -> bool:
        """Integrate up to ``n_steps`` time steps; True once the run is over."""
        start = time.perf_counter()
        left = int(n_steps)
        while left > 0 and not self.done:
            left -= self._engine_call(left)
        self.wall_time += time.perf_counter() - start
        return self.done

    def _engine_call(self, limit: int) -> int:
        """One ``Simulation.run`` of at most ``limit`` steps; returns the steps done."""
        sim, chain = self.sim, self.chain
        if self.phase == 2:
            res = sim.run(
                n_steps=limit,
                until=self.tail_end,
                stop=dem.StopCondition(at_rest=True),
                trajectory_every=self.every,
                record_contact_forces=self.contact_forces,
            )
            self._keep(res)
            self.done = res.stop_reason in ("until", "at_rest")
            if res.stop_reason == "at_rest":
                self.record_end = _clock_at(sim.time, sim.dt, self.tail_end)
            return res.n_steps
        onset = float(sim.rec.last_onset[0])  # last body-body contact onset [s], -inf: none
        since = max(onset, 0.0)  # phase 1 starts at t = 0
        cap = steps_until_quiet(sim.time, sim.dt, since, chain.quiet_time, limit)
        stop = dem.StopCondition(
            no_onset_for=chain.quiet_time, touched_body=chain.params.n_dominoes - 1
        )
        res = sim.run(
            n_steps=limit if cap is None else cap,
            until=chain.max_time,
            stop=stop,
            trajectory_every=self.every,
            record_contact_forces=self.contact_forces,
        )
        self._keep(res)
        reason = res.stop_reason
        if reason == "n_steps" and res.n_steps == cap and sim.rec.last_onset[0] == onset:
            reason = "no_onset"
        if reason in _REASONS[1:]:  # phase 1 is over
            self.stop_reason = reason
            if reason == "touched":
                # phase 2: the aftermath (re-contacts, rebounds, the last domino's fall)
                self.phase, self.tail_end = 2, sim.time + chain.tail_time
            else:
                self.done = True
        return res.n_steps

    def _keep(self, res) -> None:
        """Append the frames and events of one engine call, count its steps."""
        self.steps += int(res.n_steps)
        self.frames.append_rows(res.frames)
        for k in _EVENTS:
            self.events[k].append(np.asarray(getattr(res.events, k)))
        self.reached = max(self.reached, _highest_hit(res.events.body_j, res.events.kind))
        if self.contact_forces:
            cf = res.contact_frames
            self.contacts["count"].append(np.diff(cf.start))
            for k in _CONTACTS[1:]:
                self.contacts[k].append(getattr(cf, k))

    # --- checkpoints --------------------------------------------------------------------
    def get_state(self) -> dict[str, np.ndarray]:
        """Everything the rest of the run depends on, as NumPy arrays (copies)."""
        self._compact()
        state = {f"sim.{k}": v for k, v in self.sim.get_state().items()}
        state.update({f"frames.{k}": v for k, v in self.frames.dense().items()})
        state.update({f"events.{k}": v[0].copy() for k, v in self.events.items()})
        state.update({f"contacts.{k}": v[0].copy() for k, v in self.contacts.items()})
        state["steps"] = np.array(self.steps, np.int64)
        state["phase"] = np.array(self.phase, np.int64)
        state["done"] = np.array(self.done)
        state["stop_reason"] = np.array(_REASONS.index(self.stop_reason), np.int64)
        state["tail_end"] = np.array(self.tail_end)
        state["record_end"] = np.array(self.record_end)
        state["wall_time"] = np.array(self.wall_time)
        state["stepper_format"] = np.array(STATE_FORMAT)
        return state

    @property
    def history_keys(self) -> tuple[str, ...]:
        """Arrays of :meth:`get_state` that only grow along their first axis (frames,
        events, contact records): a checkpoint stores their rows once
        (:func:`dominowave.io.checkpoint.save_checkpoint`)."""
        groups = {"frames": _FRAMES, "events": _EVENTS, "contacts": _CONTACTS}
        return tuple(f"{group}.{k}" for group, keys in groups.items() for k in keys)

    def set_state(self, state: dict[str, np.ndarray]) -> None:
        """Restore a state of :meth:`get_state` (from a stepper of the same chain and push),
        of any :data:`STATE_FORMAT` up to this one."""
        version = check_format("stepper_format", int(state.get("stepper_format", 1)), STATE_FORMAT)
        self.sim.set_state({k[4:]: v for k, v in state.items() if k.startswith("sim.")})
        self.frames = SparseFrames.from_dense({k: state[f"frames.{k}"] for k in _FRAMES})
        self.events = {k: [np.array(state[f"events.{k}"])] for k in _EVENTS}
        if not self.contact_forces:
            self.contacts = {}
        elif "contacts.count" in state:
            self.contacts = {k: [np.array(state[f"contacts.{k}"])] for k in _CONTACTS}
        else:  # a state saved without the recorder: its frames have no contacts
            self.contacts = _empty_contacts(n_frames=self.frames.n_frames)
        self.steps = int(state["steps"])
        self.phase = int(state["phase"])
        self.done = bool(state["done"])
        self.stop_reason = _REASONS[int(state["stop_reason"])]
        self.tail_end = float(state["tail_end"])
        # (format 1: saved before runs stopped at rest, or just after, without the key)
        self.record_end = float(
            state["record_end"] if version >= 2 else state.get("record_end", math.nan)
        )
        self.wall_time = float(state["wall_time"])
        self.reached = _highest_hit(self.events["body_j"][0], self.events["kind"][0])

    def _compact(self) -> None:
        """Join the per-call pieces of events and contact records into one array each."""
        for pieces in (*self.events.values(), *self.contacts.values()):
            pieces[:] = [np.concatenate(pieces)]

    # --- results ------------------------------------------------------------------------
    def record(self, dense: bool = True) -> ChainRecord:
        """The trajectory and contact events so far as a ``ChainRecord``; ``dense=False``:
        with each domino's stored frames (``ChainRecord.tracks``) instead of the arrays of
        every frame, which the event analysis needs and a long chain's frames would not
        fit (:mod:`dominowave.chain.frames`)."""
        self._compact()
        events = {k: v[0] for k, v in self.events.items()}
        end = self.time if math.isnan(self.record_end) else self.record_end
        if dense:
            return self.chain.record(self.frames.dense(), events, end_time=end)
        frames = {"times": self.frames.times}
        return self.chain.record(frames, events, end, tracks=self.frames.tracks())

    def contact_frames(self) -> dem.ContactFrames | None:
        """The recorded contact forces of every frame of :meth:`record` (None if not
        recorded); frame 0, the state before the first step, has none."""
        if not self.contact_forces:
            return None
        self._compact()
        c = {k: v[0] for k, v in self.contacts.items()}
        start = np.concatenate([[0], np.cumsum(c["count"])])
        return dem.ContactFrames(start, c["first"], c["second"], c["point"], c["force"])

    def result(self, keep_record: bool = False):
        """The ``ChainRun`` of the run so far (analysed as a finished one would be;
        ``stop_reason`` is ``"running"`` until phase 1 has ended)."""
        return self.chain.analyse(
            self.push,
            self.omega_1,
            self.record(dense=keep_record),
            dt=self.sim.dt,
            n_steps=self.steps,
            wall_time=self.wall_time,
            stop_reason=self.stop_reason or "running",
            keep_record=keep_record,
        )


def _clock_at(t: float, dt: float, t_end: float) -> float:
    """The time [s] at which the engine's clock, now at ``t``, stops a run ``until=t_end``:
    the time loop's own arithmetic (one ``+ dt`` per step until ``t >= t_end - dt/2``)."""
    while t < t_end - 0.5 * dt:
        t = t + dt
    return t


def _empty_contacts(n_frames: int) -> dict[str, list[np.ndarray]]:
    """Contact pieces for ``n_frames`` frames without contacts."""
    out = {
        k: [np.zeros((0, *shape), dtype)]
        for k, (shape, dtype) in zip(_CONTACTS, _CONTACT_SHAPES, strict=True)
    }
    out["count"] = [np.zeros(n_frames, np.int64)]
    return out


def _highest_hit(body_j: np.ndarray, kind: np.ndarray) -> int:
    """Highest body index with a body-body contact onset among events (0 if none)."""
    hit = np.asarray(body_j)[(np.asarray(kind) == dem.ONSET) & (np.asarray(body_j) >= 0)]
    return int(hit.max()) if hit.size else 0
