"""Run a study: one point in-process, or a sweep on dask.distributed.

A sweep submits every point not yet stored to a Dask cluster -- a LocalCluster
with one single-threaded worker process per core by default, or an existing
cluster given by its scheduler address -- and writes each point's folder the
moment its result arrives (see :mod:`dominowave.sweep.store`). The client, not
the workers, writes: the output folder need not be shared with the cluster.
"""

from __future__ import annotations

import contextlib
import json
import logging
import os
import shutil
import time
import traceback
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

from dominowave import signals
from dominowave.io.atomic import TMP_PREFIX, ensure_writable_dir, write_json, write_text
from dominowave.io.checkpoint import load_checkpoint
from dominowave.io.config import Study
from dominowave.io.progress import SweepProgress
from dominowave.io.provenance import provenance
from dominowave.io.results import result_status, write_failure_folder, write_result_folder
from dominowave.io.toml_text import dumps
from dominowave.io.vtk import write_result_vtk
from dominowave.sweep.execute import PointOutcome, execute_point
from dominowave.sweep.hashing import config_dict, point_key
from dominowave.sweep.registry import RunContext, get_runner, is_steppable, steppable_kinds
from dominowave.sweep.store import SweepStore

__all__ = ["SweepReport", "run_one", "run_sweep", "store_outcome", "study_toml"]

_UNFINISHED_RUN_ENTRIES = {"checkpoint", "partial"}
"""What a result folder holds while its run is unfinished (besides temporary files)."""

POLL_S = 0.05
"""How often the sweep client looks for finished points and for a stop signal [s]."""

INDEX_INTERVAL_S = 1.0
"""Minimum time between rewrites of index.json during a sweep [s] (it is also
rebuilt from the point folders at the start and end, so nothing depends on it)."""


@dataclass
class SweepReport:
    """Counts of a sweep run: points in the study, already stored, run now, failed."""

    folder: Path
    total: int
    skipped: int
    ran: int = 0
    failed: int = 0
    interrupted: int = 0
    """0, or the exit code of the signal that stopped the sweep (130 SIGINT, 143 SIGTERM)."""
    set_aside: list[str] = field(default_factory=list)
    """One line per stored point whose files did not parse (moved to unreadable/, run again)."""

    def line(self) -> str:
        state = "interrupted" if self.interrupted else "done"
        return "\n".join(
            [
                *self.set_aside,
                f"sweep {state}: {self.total} points, {self.skipped} already stored, "
                f"{self.ran} run now ({self.failed} failed) -> {self.folder}",
            ]
        )


def study_toml(study: Study) -> str:
    """The study as TOML, scenario fully resolved (what is stored beside the results)."""
    data: dict = {"scenario": config_dict(study.scenario)}
    if study.sweep is not None:
        data["sweep"] = study.sweep.model_dump(exclude_none=True)
    data["output"] = study.output.model_dump()
    return dumps(data)


def store_outcome(folder: Path, config, outcome: PointOutcome, keep_trajectory: bool) -> bool:
    """Write ``outcome`` as the result folder ``folder``; False if it already existed."""
    cfg = config_dict(config)
    if outcome.status == "ok":
        return write_result_folder(folder, cfg, outcome.provenance, outcome.result, keep_trajectory)
    return write_failure_folder(folder, cfg, outcome.provenance, outcome.error, outcome.traceback)


# --------------------------------------------------------------------------- one run


def run_one(study: Study, out: Path, ctx: RunContext | None = None, force: bool = False) -> str:
    """Run the study's scenario in this process and write its folder ``out``.

    Returns "ok" or "up to date" (``out`` already holds this config's result);
    raises ``ValueError`` if the run failed (the failure is recorded in ``out``).
    An existing result of another config is replaced only with ``force``, and then
    atomically and only by a successful run: old files stay until the new ones are
    complete, and a failed forced run leaves them as they are and writes its failure
    beside them in ``<out>.failed``. A failed result of
    the same config is run again. With ``ctx.checkpoint_dir`` (inside ``out``) an
    existing checkpoint is checked first and then resumed from.
    """
    out = Path(out)
    config = study.scenario
    key = point_key(config)
    ctx = ctx or RunContext()
    if ctx.checkpoint_dir is not None:
        _check_checkpointing(config, Path(ctx.checkpoint_dir), key)
    if out.exists():
        if not out.is_dir():
            raise ValueError(f"output folder {out} exists and is not a folder")
        status = result_status(out)
        if status is not None:
            old_key = _stored_key(out)
            if old_key == key and status == "ok" and not force:
                return "up to date"
            if old_key != key and not force:
                raise ValueError(
                    f"output folder {out} holds the result of another config (key {old_key});"
                    " choose another --out or pass --force to replace it"
                )
        elif any(p for p in out.iterdir() if p.name not in _UNFINISHED_RUN_ENTRIES):
            raise ValueError(f"output folder {out} is not empty and holds no result")
    ensure_writable_dir(out.parent if str(out.parent) else Path("."))
    if ctx.checkpoint_dir is not None:
        ensure_writable_dir(ctx.checkpoint_dir)
        write_text(Path(ctx.checkpoint_dir) / "study.toml", study_toml(study))
        write_json(
            Path(ctx.checkpoint_dir) / "policy.json",
            {"steps": ctx.checkpoint_every_steps, "seconds": ctx.checkpoint_every_seconds},
        )
    outcome = execute_point(config, ctx=ctx)
    new = out.parent / f"{TMP_PREFIX}{out.name}.new"
    shutil.rmtree(new, ignore_errors=True)
    store_outcome(new, config, outcome, study.output.trajectory)
    if ctx.vtk_every and outcome.status == "ok":
        write_result_vtk(new / "vtk", outcome.result, ctx.vtk_every)
    if outcome.status == "failed" and result_status(out) == "ok":
        # A forced re-run that failed never destroys the good result it was to replace:
        # the failure goes beside it (a checkpoint stays in ``out``, where a re-run looks).
        failed = out.parent / f"{out.name}.failed"
        shutil.rmtree(failed, ignore_errors=True)
        os.rename(new, failed)
        raise ValueError(
            f"run failed: {outcome.error} (the previous result in {out} is kept;"
            f" traceback in {failed / 'failure.json'})"
        )
    if outcome.status == "failed" and (out / "checkpoint").is_dir():
        os.rename(out / "checkpoint", new / "checkpoint")  # keep it: a re-run resumes from it
    if out.exists():
        trash = out.parent / f"{TMP_PREFIX}{out.name}.old"
        shutil.rmtree(trash, ignore_errors=True)
        os.rename(out, trash)
        os.rename(new, out)
        shutil.rmtree(trash, ignore_errors=True)
    else:
        os.rename(new, out)
    if outcome.status == "failed":
        raise ValueError(f"run failed: {outcome.error} (traceback in {out / 'failure.json'})")
    return "ok"


def _check_checkpointing(config, checkpoint_dir: Path, key: str) -> None:
    """Refuse checkpoints for kinds without a time loop, and corrupt or foreign checkpoints."""
    if not is_steppable(config.kind):
        raise ValueError(
            f"--checkpoint: scenario {config.kind!r} has no time loop to checkpoint"
            f" (steppable: {', '.join(steppable_kinds()) or 'none yet'})"
        )
    state = checkpoint_dir / "state.npz"
    if state.exists():
        load_checkpoint(state, key=key)


def _stored_key(folder: Path) -> str | None:
    try:
        return json.loads((folder / "provenance.json").read_text())["key"]
    except (OSError, ValueError, KeyError):
        return None


# --------------------------------------------------------------------------- sweeps


@contextlib.contextmanager
def dask_client(scheduler: str | None = None, n_workers: int | None = None):
    """A dask.distributed Client: on ``scheduler`` if given, else on a new LocalCluster.

    The LocalCluster has ``n_workers`` (default: all cores) single-threaded
    worker processes -- the simulations hold the GIL or are numba kernels, so
    processes, not threads, give parallelism.
    """
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            client = Client(scheduler, timeout="10s")
        except (OSError, TimeoutError) as exc:
            raise ValueError(f"--scheduler {scheduler}: cannot connect ({exc})") from None
        with client:
            yield client
        return
    workers = n_workers or os.cpu_count() or 1
    with signals.ignore_sigint():  # the workers inherit it: Ctrl-C is the client's alone
        cluster = LocalCluster(
            n_workers=workers,
            threads_per_worker=1,
            processes=True,
            dashboard_address=":0",
            silence_logs=logging.CRITICAL,  # a worker that loses the scheduler at shutdown
            # logs a heartbeat traceback; failures of points are stored, not logged
        )
    with cluster, Client(cluster) as client:
        yield client


def run_sweep(
    study: Study,
    out: Path,
    *,
    client=None,
    scheduler: str | None = None,
    n_workers: int | None = None,
    quiet: bool = False,
    retry_failed: bool = False,
    force: bool = False,
    on_point: Callable[[object, PointOutcome], None] | None = None,
) -> SweepReport:
    """Run every point of ``study`` not yet stored in ``out``; return the counts.

    Points are keyed by :func:`~dominowave.sweep.hashing.point_key`; a stored point
    (ok or failed) is skipped, a failed one is run again with ``retry_failed``.
    A sweep folder belongs to one study: a folder that holds another study is
    refused (``ValueError``) unless ``force``, which adds this study's points to it.
    One sweep at a time writes a folder: a second one started on it is refused.
    Give ``client`` to reuse a connected dask Client (tests, notebooks).
    ``on_point(config, outcome)`` is called after each point run now is stored.
    Ctrl-C cancels the running points and returns with ``interrupted`` set:
    everything finished so far is on disk, and re-running resumes.
    """
    store = SweepStore(out).open_for_writing()
    text = study_toml(study)
    with store.lock():
        _check_same_study(store.root / "study.toml", text, force)
        write_text(store.root / "study.toml", text)
        return _run_points(
            study, store, client, scheduler, n_workers, quiet, retry_failed, on_point
        )


def _check_same_study(path: Path, text: str, force: bool) -> None:
    """Refuse to mix two studies in one folder (``collect`` could not tell them apart)."""
    if force or not path.is_file() or path.read_text(encoding="utf-8") == text:
        return
    raise ValueError(
        f"sweep folder {path.parent} holds another study ({path.name} differs);"
        " choose another --out or pass --force to add this study's points to it"
    )


def _run_points(
    study, store, client, scheduler, n_workers, quiet, retry_failed, on_point
) -> SweepReport:
    """The body of :func:`run_sweep`, run while the folder's lock is held."""
    configs = {}
    swept = {}
    for config, override in zip(study.points, study.overrides, strict=True):
        key = point_key(config)
        configs.setdefault(key, config)
        swept.setdefault(key, override)
    set_aside = store.set_aside_unreadable()  # a file that does not parse is no result
    stored = store.status()
    if retry_failed:
        for key in [k for k in configs if stored.get(k) == "failed"]:
            shutil.rmtree(store.folder(key))
            del stored[key]
    todo = [k for k in configs if k not in stored]
    report = SweepReport(
        store.root, total=len(configs), skipped=len(configs) - len(todo), set_aside=set_aside
    )
    store.write_index(swept)
    if not todo:
        return report
    keep = study.output.trajectory
    # Signals are only noted while dask runs: a KeyboardInterrupt raised inside the
    # client's machinery can leave it unable to shut its cluster down (a hang).
    with signals.defer() as flag, contextlib.ExitStack() as stack:
        if client is None:
            client = stack.enter_context(dask_client(scheduler, n_workers))
        progress = stack.enter_context(SweepProgress(len(configs), report.skipped, quiet))
        report = _gather(
            client, store, configs, todo, swept, keep, progress, report, flag, on_point
        )
    store.write_index(swept)
    return report


def _gather(
    client, store, configs, todo, swept, keep, progress, report, flag, on_point
) -> SweepReport:
    """Submit the points ``todo``, store each outcome as it arrives; stop on a signal
    noted in ``flag`` (see :func:`dominowave.signals.defer`) within ``POLL_S``."""
    from distributed import as_completed

    futures = {}
    for key in todo:
        config = configs[key]
        future = client.submit(
            execute_point,
            config,
            get_runner(config.kind),
            key=f"dominowave-point-{key}",
            pure=False,
        )
        futures[future] = key
    last_index = time.monotonic()
    arrivals = as_completed(futures)
    while not arrivals.is_empty():
        if flag["signum"] is not None:
            client.cancel(list(futures))
            report.interrupted = signals.Interrupted(flag["signum"]).exit_code
            break
        if not arrivals.has_ready():
            time.sleep(POLL_S)
            continue
        for future in arrivals.next_batch(block=False):
            key = futures.pop(future)
            outcome = _outcome(future, key)
            store_outcome(store.folder(key), configs[key], outcome, keep)
            report.ran += 1
            report.failed += outcome.status == "failed"
            progress.advance(outcome.status)
            if on_point is not None:
                on_point(configs[key], outcome)
            future.release()
        if time.monotonic() - last_index > INDEX_INTERVAL_S:
            store.write_index(swept)
            last_index = time.monotonic()
    if flag["signum"] is not None and not report.interrupted:
        # the signal came while the last points were being stored: all is kept, and
        # the exit code still says that the user stopped the command
        report.interrupted = signals.Interrupted(flag["signum"]).exit_code
    return report


def _outcome(future, key: str) -> PointOutcome:
    """The outcome of a finished future; a task dask itself gave up on counts as failed."""
    try:
        return future.result()
    except Exception as exc:  # e.g. KilledWorker: the point crashed its worker repeatedly
        prov = provenance(key=key, seed=None, wall_time=float("nan"), started=time.time())
        return PointOutcome(
            key,
            "failed",
            prov,
            error=f"{type(exc).__name__}: {exc}",
            traceback="".join(traceback.format_exception(exc)),
        )
