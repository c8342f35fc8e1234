"""SIGINT and SIGTERM stop a sweep within seconds, keep its points, leave no workers.

The three ways a user stops a sweep: Ctrl-C on a terminal (SIGINT to the whole
process group, workers included), ``kill -INT`` of the client (also when it was
started as a background job, whose SIGINT the shell ignores), and ``kill`` (SIGTERM,
as sent by a batch system). Each must end the command with exit code 130 (143), no
traceback, every finished point stored, and no dask worker process left behind.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import psutil
import pytest

HERE = Path(__file__).parent
CLI = [sys.executable, str(HERE / "cli_with_helpers.py")]

STUDY = (
    '[scenario]\nkind = "slow_theory"\nn_dominoes = 6\nn_frames = 10\ndelay = 1.0\n'
    "[sweep.grid]\nd_over_l = [0.20, 0.22, 0.24, 0.26, 0.28, 0.30, 0.32, 0.34,"
    " 0.36, 0.38, 0.40, 0.42]\n"
)


def _ignore_sigint():
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # what `cmd &` gets from a shell


@pytest.mark.parametrize(
    ("signum", "to_group", "background", "code"),
    [
        (signal.SIGINT, True, False, 130),  # Ctrl-C on a terminal
        (signal.SIGINT, False, True, 130),  # kill -INT of a background job
        (signal.SIGTERM, False, False, 143),  # kill
    ],
    ids=["ctrl-c", "kill-int-background", "sigterm"],
)
def test_a_signal_stops_a_sweep_cleanly(tmp_path, signum, to_group, background, code):
    study = tmp_path / "s.toml"
    study.write_text(STUDY)
    out = tmp_path / "sweep"
    proc = subprocess.Popen(
        [*CLI, "sweep", str(study), "--out", str(out), "--workers", "2", "--quiet"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
        preexec_fn=_ignore_sigint if background else None,
    )
    points = out / "points"
    end = time.monotonic() + 120
    while time.monotonic() < end:
        if points.is_dir() and any(not p.name.startswith(".") for p in points.iterdir()):
            break
        time.sleep(0.05)
    workers = psutil.Process(proc.pid).children(recursive=True)
    assert workers, "the sweep must have started its workers"
    sent = time.monotonic()
    if to_group:
        os.killpg(proc.pid, signum)
    else:
        proc.send_signal(signum)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == code, stderr
    assert time.monotonic() - sent < 20
    assert "Traceback" not in stderr
    assert "sweep interrupted: 12 points" in stdout
    stored = [p for p in points.iterdir() if not p.name.startswith(".")]
    assert 1 <= len(stored) < 12
    _, alive = psutil.wait_procs(workers, timeout=10)
    assert not alive, f"worker processes left behind: {alive}"
    # and the sweep resumes where it stopped
    again = subprocess.run(
        [*CLI, "sweep", str(study), "--out", str(out), "--workers", "2", "--quiet"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert again.returncode == 0, again.stderr
    assert f"{len(stored)} already stored, {12 - len(stored)} run now" in again.stdout


def test_an_interrupted_fig6_writes_no_summary_and_resumes(tmp_path):
    """A summary of some of the points would read as the figure: after a signal the
    command writes none, says so, and keeps the points for the re-run."""
    out = tmp_path / "fig6"
    proc = subprocess.Popen(
        [*CLI, "paper-fig6", "--quick", "--out", str(out), "--workers", "1"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        start_new_session=True,
    )
    points = out / "points"
    end = time.monotonic() + 300
    while time.monotonic() < end and proc.poll() is None:
        if points.is_dir() and any(not p.name.startswith(".") for p in points.iterdir()):
            break
        time.sleep(0.05)
    assert proc.poll() is None, "the quick Fig 6 ended before a point was stored"
    os.killpg(proc.pid, signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert "interrupted: no summary or figure written" in " ".join(stdout.split())
    assert not (out / "summary.csv").exists()
    assert any(not p.name.startswith(".") for p in points.iterdir())


DROPPED_SIGNAL = """
import signal, time, weakref
from dominowave import signals

signals.install()


class Thing:
    pass


def callback(ref):  # Python must drop what a weakref callback raises
    signal.raise_signal(signal.SIGINT)
    for _ in range(1000):  # the handler runs in here, and its Interrupted is dropped
        pass


thing = Thing()
ref = weakref.ref(thing, callback)
try:
    del thing
    time.sleep(30)
    print("ran on")
except signals.Interrupted as exc:
    print("stopped by", exc)
"""


def test_a_signal_that_lands_in_a_weakref_callback_still_stops_the_command():
    """A signal handled where Python drops exceptions (a weakref callback, as in the
    import system's module locks, or a finalizer) must not be lost: the command
    would run on to its end and exit 0."""
    started = time.monotonic()
    run = subprocess.run(
        [sys.executable, "-c", DROPPED_SIGNAL], capture_output=True, text=True, timeout=60
    )
    assert run.returncode == 0, run.stderr
    assert run.stdout.strip() == "stopped by SIGINT"
    assert "Exception ignored" not in run.stderr
    assert time.monotonic() - started < 20


AT_EXIT = """
import atexit, time
from dominowave import signals


def last():
    time.sleep(0.5)  # (longer than signals.RESEND_S)
    print("the last exit handler ran", flush=True)


signals.install()
atexit.register(last)
atexit.register(signals._raise, 2, None)  # dropped, at exit
"""


def test_a_signal_dropped_at_exit_is_not_sent_again_into_the_other_exit_handlers():
    run = subprocess.run(
        [sys.executable, "-c", AT_EXIT], capture_output=True, text=True, timeout=60
    )
    assert "the last exit handler ran" in run.stdout, run.stderr
