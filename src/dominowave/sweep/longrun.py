"""Long runs with checkpoints: advance in chunks, save the state, resume bit-identically.

A scenario that supports checkpoints (a steppable kind of
:data:`dominowave.io.kinds.KINDS`, see :func:`dominowave.sweep.registry.register_stepper`)
provides a *stepper*: an object with

* ``advance(n_steps) -> bool`` -- integrate up to ``n_steps`` time steps; True when done;
* ``time`` [s], ``end_time`` [s], ``steps``, ``toppled`` -- where the run is;
  ``dominoes`` (optional) -- the chain's length, for the progress bar's estimate;
* ``get_state() -> dict[str, ndarray]`` -- everything the future depends on;
* ``set_state(state)`` -- restore it exactly;
* ``result() -> RunResult`` -- the results so far (also of an unfinished run).

Because the state is saved bit-exactly and ``advance`` is deterministic, a run
resumed from a checkpoint retraces the uninterrupted one to the last bit, as long
as chunk boundaries do not change the arithmetic (``advance(a); advance(b)`` must
equal ``advance(a + b)``) -- each stepper's tests check that.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from operator import attrgetter
from pathlib import Path

from dominowave import signals
from dominowave.io.checkpoint import load_checkpoint, save_checkpoint
from dominowave.io.results import write_result_folder
from dominowave.sweep.context import RunContext
from dominowave.sweep.hashing import config_dict, point_key

__all__ = [
    "CheckpointPolicy",
    "ScenarioStepper",
    "resume_stepper",
    "run_stepper",
    "run_stepping",
]


def _of_stepper(name: str, doc: str) -> property:
    """A read-only property that reads ``name`` of the wrapped stepper ``self.stepper``."""
    return property(attrgetter(f"stepper.{name}"), doc=doc)


class ScenarioStepper:
    """A scenario's stepper that wraps a simulation's own stepper (``self.stepper``).

    Everything of the protocol but :meth:`result` is delegated to the wrapped
    stepper; a subclass builds ``self.stepper`` in ``__init__`` and turns the run so
    far into a ``RunResult`` in :meth:`result`.
    """

    stepper = None  # the simulation's stepper, set by the subclass

    time = _of_stepper("time", "Simulated time so far [s].")
    end_time = _of_stepper("end_time", "Simulated time at which the run ends [s].")
    steps = _of_stepper("steps", "Time steps taken so far.")
    toppled = _of_stepper("toppled", "Dominoes toppled so far.")

    @property
    def dominoes(self) -> int:
        """Dominoes in the chain (a subclass keeps its scenario config as ``self.cfg``)."""
        return int(self.cfg.n_dominoes)

    def advance(self, n_steps: int) -> bool:
        return self.stepper.advance(n_steps)

    def get_state(self) -> dict:
        return self.stepper.get_state()

    def set_state(self, state: dict) -> None:
        self.stepper.set_state(state)

    @property
    def history_keys(self) -> tuple[str, ...]:
        return getattr(self.stepper, "history_keys", ())

    def result(self):
        raise NotImplementedError("a scenario stepper turns its run into a RunResult")


@dataclass(frozen=True)
class CheckpointPolicy:
    """When to checkpoint: every ``steps`` time steps and/or ``seconds`` of wall time.

    ``chunk`` is the number of steps per ``advance`` call (progress updates too).
    """

    path: Path
    key: str
    steps: int = 0
    seconds: float = 0.0
    chunk: int = 1000

    def __post_init__(self):
        if self.steps < 0 or self.seconds < 0 or self.chunk < 1:
            raise ValueError(f"checkpoint policy {self} has a negative or zero interval")


def _save(stepper, policy: CheckpointPolicy) -> None:
    meta = {"key": policy.key, "steps": int(stepper.steps), "time": float(stepper.time)}
    history = getattr(stepper, "history_keys", ())  # arrays that only grow: saved once
    save_checkpoint(policy.path, stepper.get_state(), meta, history=history)


def run_stepper(stepper, policy: CheckpointPolicy | None = None, progress=None):
    """Advance ``stepper`` to the end, checkpointing per ``policy``; return it.

    On Ctrl-C or SIGTERM the current chunk finishes, a final checkpoint is written
    and :class:`~dominowave.signals.Interrupted` is raised, so ``resume`` continues
    from exactly there.
    """
    chunk = policy.chunk if policy is not None else 1000
    if policy is not None and policy.steps:
        chunk = min(chunk, policy.steps)
    last_wall = time.monotonic()
    last_steps = stepper.steps
    with signals.defer() as flag:
        _loop(stepper, policy, progress, chunk, flag, last_wall, last_steps)
    return stepper


def _loop(stepper, policy, progress, chunk, flag, last_wall, last_steps) -> None:
    try:
        while True:
            if flag["signum"] is not None:
                raise signals.Interrupted(flag["signum"])
            done = stepper.advance(chunk)
            if progress is not None:
                progress(
                    sim_time=stepper.time,
                    end_time=stepper.end_time,
                    steps=stepper.steps,
                    toppled=stepper.toppled,
                    dominoes=getattr(stepper, "dominoes", 0),
                )
            if done:
                break
            if policy is None:
                continue
            due_steps = policy.steps and stepper.steps - last_steps >= policy.steps
            due_time = policy.seconds and time.monotonic() - last_wall >= policy.seconds
            if due_steps or due_time:
                _save(stepper, policy)
                last_wall, last_steps = time.monotonic(), stepper.steps
    except KeyboardInterrupt:
        if policy is not None:
            _save(stepper, policy)
        raise


def resume_stepper(stepper, policy: CheckpointPolicy):
    """Restore ``stepper`` (freshly built from the same config) from ``policy.path``."""
    state, meta = load_checkpoint(policy.path, key=policy.key)
    stepper.set_state(state)
    if stepper.steps != meta["steps"]:
        raise ValueError(
            f"checkpoint {policy.path}: restored state is at step {stepper.steps},"
            f" header says {meta['steps']}"
        )
    return stepper


def run_stepping(config, ctx: RunContext | None = None, *, factory):
    """Run function of a steppable scenario: ``factory(config)`` builds its stepper.

    With ``ctx.checkpoint_dir`` set, checkpoints go to ``<dir>/state.npz`` and an
    existing checkpoint of the same config is resumed from. On Ctrl-C the final
    checkpoint and the partial results (``<dir>/../partial``) are written.
    """
    ctx = ctx or RunContext()
    stepper = factory(config)
    policy = None
    if ctx.checkpoint_dir is not None:
        policy = CheckpointPolicy(
            Path(ctx.checkpoint_dir) / "state.npz",
            point_key(config),
            steps=ctx.checkpoint_every_steps,
            seconds=ctx.checkpoint_every_seconds,
        )
        if policy.path.exists():
            resume_stepper(stepper, policy)
    try:
        run_stepper(stepper, policy, ctx.progress)
    except KeyboardInterrupt:
        if policy is not None:
            _write_partial(policy.path.parent.parent / "partial", config, stepper)
        raise
    return stepper.result()


def _write_partial(folder: Path, config, stepper) -> None:
    import shutil

    prov = {"key": point_key(config), "partial": True, "steps": int(stepper.steps)}
    new = folder.with_name(folder.name + ".new")
    shutil.rmtree(new, ignore_errors=True)
    write_result_folder(new, config_dict(config), prov, stepper.result())
    shutil.rmtree(folder, ignore_errors=True)
    new.rename(folder)
