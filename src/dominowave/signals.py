"""Stopping on SIGINT and SIGTERM: one exception for both, with the exit code of each.

A long command (a chain run, a checkpointed run, a sweep) must stop within seconds
on Ctrl-C, on ``kill -INT`` and on ``kill`` (SIGTERM, what a batch system or
``timeout`` sends), keep what it finished, and exit with the shell's convention
128 + signal number: 130 for SIGINT, 143 for SIGTERM.

:func:`install` makes both signals raise :class:`Interrupted` (a
``KeyboardInterrupt``, so every ``except KeyboardInterrupt`` clean-up of the
package -- final checkpoint, cancelled sweep points -- runs for both). It also
re-arms SIGINT when the command was started with SIGINT ignored, as a shell does
for a background job (``cmd &``), where ``kill -INT`` would otherwise do nothing.

A signal can arrive while Python runs code whose exceptions it must drop: a
weakref callback (the import system's module locks use them), a finalizer. The
:class:`Interrupted` raised there would only be printed ("Exception ignored in
...") and the command would run on to its end and exit 0. :func:`install` therefore
also hooks :data:`sys.unraisablehook`: such an exception is not printed, and the
signal is sent again a moment later, once that code has returned.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Iterator

__all__ = ["Interrupted", "defer", "exit_code", "ignore_sigint", "install"]

STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)
RESEND_S = 0.01
"""Delay [s] before a signal that Python had to drop is sent again."""


class Interrupted(KeyboardInterrupt):
    """Raised by SIGINT or SIGTERM; ``exit_code`` is 128 + the signal number."""

    def __init__(self, signum: int = signal.SIGINT):
        super().__init__(signal.Signals(signum).name)
        self.signum = int(signum)

    @property
    def exit_code(self) -> int:
        return 128 + self.signum


def _raise(signum, frame):
    raise Interrupted(signum)


def _deliver_again(unraisable) -> None:
    """``sys.unraisablehook``: an :class:`Interrupted` that Python had to drop is sent
    again as its signal to the main thread; anything else, and anything at exit, goes
    to the previous hook.

    Sent from a timer thread a little later: a signal sent from here would be
    handled here, inside the same callback, and dropped again. Should it land in
    such code once more, it comes back here and is sent once more.
    """
    # (at exit the signal would cut the next exit handler instead: the process ends anyway)
    exiting = sys.is_finalizing() or not threading.main_thread().is_alive()
    if isinstance(unraisable.exc_value, Interrupted) and not exiting:
        resend = threading.Timer(
            RESEND_S,
            signal.pthread_kill,
            (threading.main_thread().ident, unraisable.exc_value.signum),
        )
        resend.daemon = True
        try:
            resend.start()
            return
        except RuntimeError:  # (no new thread: the interpreter is shutting down)
            pass
    _previous_unraisablehook(unraisable)


_previous_unraisablehook = sys.unraisablehook


def install() -> None:
    """Make SIGINT and SIGTERM raise :class:`Interrupted` (main thread only), also
    when the signal arrives inside a weakref callback or a finalizer."""
    global _previous_unraisablehook
    if threading.current_thread() is threading.main_thread():
        for signum in STOP_SIGNALS:
            signal.signal(signum, _raise)
        if sys.unraisablehook is not _deliver_again:
            _previous_unraisablehook = sys.unraisablehook
            sys.unraisablehook = _deliver_again


def exit_code(exc: KeyboardInterrupt) -> int:
    """The exit code for ``exc``: 143 after SIGTERM, else 130 (Ctrl-C)."""
    return exc.exit_code if isinstance(exc, Interrupted) else 128 + signal.SIGINT


@contextlib.contextmanager
def defer() -> Iterator[dict]:
    """Defer SIGINT and SIGTERM: inside, a first signal only sets ``flag["signum"]``.

    For loops whose step must not be cut in half (a checkpoint of a half-updated
    state would not resume bit-identically; a dask client interrupted inside its
    own machinery may never shut its cluster down): check the flag between steps
    and stop, e.g. by raising ``Interrupted(flag["signum"])``. A second signal
    raises at once, so a user is never left without a way out. Outside the main
    thread (a dask worker) signals are not ours to handle and nothing changes.
    """
    flag: dict = {"signum": None}
    if threading.current_thread() is not threading.main_thread():
        yield flag
        return

    def note(signum, frame):
        if flag["signum"] is not None:
            raise Interrupted(signum)
        flag["signum"] = signum

    previous = {signum: signal.signal(signum, note) for signum in STOP_SIGNALS}
    try:
        yield flag
    finally:
        for signum, handler in previous.items():
            signal.signal(signum, handler)


@contextlib.contextmanager
def ignore_sigint() -> Iterator[None]:
    """Ignore SIGINT while worker processes are started, so that they inherit it.

    A terminal's Ctrl-C goes to the whole process group: without this every dask
    worker would print its own KeyboardInterrupt traceback while the client, which
    alone handles the signal, cancels their work and shuts them down.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)
    try:
        yield
    finally:
        signal.signal(signal.SIGINT, previous)
