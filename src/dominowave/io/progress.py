"""Progress bars for long runs and sweeps (rich), only on a terminal.

They are off with ``--quiet`` and whenever stderr is not a terminal (CI, pipes,
log files), so logs never fill with control characters.
"""

from __future__ import annotations

import sys
import time

__all__ = ["RunProgress", "SweepProgress", "progress_enabled"]


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


class RunProgress(_Bar):
    """Simulated time / end time, steps/s, ETA and dominoes toppled of one run.

    Pass the instance as ``RunContext.progress``; the scenario calls it with
    ``sim_time``, ``end_time`` [s], ``steps`` and ``toppled``. Redraws at most
    ten times a second.
    """

    def __init__(self, quiet: bool = False):
        self.enabled = progress_enabled(quiet)
        self._bar = None
        self._last = 0.0
        self._t0 = time.perf_counter()
        if self.enabled:
            from rich.progress import BarColumn, TextColumn, TimeRemainingColumn

            self._bar = _progress(
                TextColumn("t = {task.completed:.4g} / {task.total:.4g} s"),
                BarColumn(),
                TextColumn("{task.fields[rate]:.3g} steps/s"),
                TextColumn("{task.fields[toppled]} toppled"),
                TextColumn("ETA"),
                TimeRemainingColumn(),
            )
            self._task = self._bar.add_task("run", total=1.0, rate=0.0, toppled=0)

    def __call__(self, *, sim_time: float, end_time: float, steps: int, toppled: int) -> None:
        if self._bar is None:
            return
        now = time.perf_counter()
        if now - self._last < 0.1 and sim_time < end_time:
            return
        self._last = now
        rate = steps / max(now - self._t0, 1e-9)
        self._bar.update(self._task, completed=sim_time, total=end_time, rate=rate, toppled=toppled)
