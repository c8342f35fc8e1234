"""Progress bars for long runs and sweeps (rich), only on a terminal.

They are off with ``--quiet`` and whenever stderr is not a terminal (CI, pipes,
log files), so logs never fill with control characters.
"""

from __future__ import annotations

import sys
import time

__all__ = ["RunProgress", "SweepProgress", "eta_seconds", "expected_end", "progress_enabled"]


def progress_enabled(quiet: bool) -> bool:
    """True if progress should be drawn: not ``quiet`` and stderr is a terminal."""
    return not quiet and sys.stderr.isatty()


def _progress(*columns):
    from rich.console import Console
    from rich.progress import Progress

    return Progress(*columns, console=Console(stderr=True), transient=False)


class _Bar:
    """A rich progress bar (``self._bar``, None when off) used as a context manager."""

    _bar = None

    def __enter__(self):
        if self._bar is not None:
            self._bar.start()
        return self

    def __exit__(self, *exc):
        if self._bar is not None:
            self._bar.stop()


class SweepProgress(_Bar):
    """Points finished / total, failures, elapsed time and ETA of a sweep."""

    def __init__(self, total: int, done: int = 0, quiet: bool = False):
        self.enabled = progress_enabled(quiet)
        self.failed = 0
        self._bar = None
        if self.enabled:
            from rich.progress import (
                BarColumn,
                MofNCompleteColumn,
                TextColumn,
                TimeElapsedColumn,
                TimeRemainingColumn,
            )

            self._bar = _progress(
                TextColumn("sweep"),
                BarColumn(),
                MofNCompleteColumn(),
                TextColumn("{task.fields[failed]} failed"),
                TimeElapsedColumn(),
                TextColumn("ETA"),
                TimeRemainingColumn(),
            )
            self._task = self._bar.add_task("sweep", total=total, completed=done, failed=0)

    def advance(self, status: str) -> None:
        self.failed += status == "failed"
        if self._bar is not None:
            self._bar.update(self._task, advance=1, failed=self.failed)


def expected_end(sim_time: float, end_time: float, toppled: int, dominoes: int) -> float:
    """Simulated time [s] at which the run is expected to end.

    ``end_time`` [s] is only the latest it can end (a cap, several times the wave's
    travel time); the wave runs at a nearly steady speed, so once ``toppled`` of the
    ``dominoes`` have been reached at ``sim_time`` [s] it reaches the last one near
    ``sim_time * dominoes / toppled``. Once all are reached (or the length is
    unknown, ``dominoes = 0``) the run's own ``end_time`` is the estimate.
    """
    if dominoes <= 0 or toppled < 2 or toppled >= dominoes:
        return end_time
    return min(end_time, sim_time * dominoes / toppled)


def eta_seconds(wall: float, sim_time: float, end: float) -> float:
    """Wall time [s] left to simulate from ``sim_time`` to ``end`` [s] at the rate
    measured so far (``sim_time`` simulated in ``wall`` seconds); NaN before any."""
    if wall <= 0 or sim_time <= 0:
        return float("nan")
    return max(end - sim_time, 0.0) * wall / sim_time


def _clock(seconds: float) -> str:
    if not seconds == seconds:  # NaN: no rate measured yet
        return "-:--:--"
    s = round(seconds)
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


class RunProgress(_Bar):
    """Simulated time / expected end, steps/s, dominoes reached and ETA of one run.

    Pass the instance as ``RunContext.progress``; the scenario calls it with
    ``sim_time``, ``end_time`` [s], ``steps``, ``toppled`` and ``dominoes``. The end
    is estimated from the wave's progress (:func:`expected_end`), the ETA from the
    measured rate (:func:`eta_seconds`) from the first call on, so that neither the
    kernels' compilation nor a resumed run's earlier part enters the rate. Redraws at
    most ten times a second.
    """

    def __init__(self, quiet: bool = False):
        self.enabled = progress_enabled(quiet)
        self._bar = None
        self._last = 0.0
        self._origin: tuple[float, float, int] | None = None  # wall, sim time, steps
        if self.enabled:
            from rich.progress import BarColumn, TextColumn

            self._bar = _progress(
                TextColumn("t = {task.completed:.3g} / ~{task.total:.3g} s"),
                BarColumn(),
                TextColumn("{task.fields[rate]:.3g} steps/s"),
                TextColumn("{task.fields[toppled]} toppled"),
                TextColumn("ETA {task.fields[eta]}"),
            )
            self._task = self._bar.add_task("run", total=1.0, rate=0.0, toppled="0", eta="")

    def __call__(
        self, *, sim_time: float, end_time: float, steps: int, toppled: int, dominoes: int = 0
    ) -> None:
        if self._bar is None:
            return
        now = time.perf_counter()
        if self._origin is None:
            self._origin = (now, sim_time, steps)
        if now - self._last < 0.1 and sim_time < end_time:
            return
        self._last = now
        wall0, sim0, steps0 = self._origin
        wall = now - wall0
        end = expected_end(sim_time, end_time, toppled, dominoes)
        self._bar.update(
            self._task,
            completed=sim_time,
            total=max(end, sim_time),
            rate=(steps - steps0) / wall if wall > 0 else 0.0,
            toppled=f"{toppled}/{dominoes}" if dominoes else str(toppled),
            eta=_clock(eta_seconds(wall, sim_time - sim0, end - sim0)),
        )
