"""Checkpoints: bit-exact files, corruption detected, killed runs resume bit-identically."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from workflow_helpers import SAMPLE_EVERY, PendulumStepper, ToyPendulums

from dominowave.io.checkpoint import history_dir, load_checkpoint, save_checkpoint
from dominowave.sweep.longrun import CheckpointPolicy, resume_stepper, run_stepper

HERE = Path(__file__).parent
CLI = [sys.executable, str(HERE / "cli_with_helpers.py")]


def test_checkpoint_round_trip_is_bit_exact(tmp_path):
    rng = np.random.default_rng(1)
    state = {"x": rng.normal(size=(5, 3)), "n": np.array(7), "ids": np.arange(4, dtype=np.int32)}
    save_checkpoint(tmp_path / "c.npz", state, {"key": "abc", "steps": 7})
    back, meta = load_checkpoint(tmp_path / "c.npz", key="abc")
    assert meta["steps"] == 7
    for name, array in state.items():
        assert back[name].dtype == array.dtype
        np.testing.assert_array_equal(back[name], array)


@pytest.mark.parametrize("damage", ["truncate", "flip", "garbage", "empty"])
def test_corrupt_checkpoint_is_refused(tmp_path, damage):
    path = tmp_path / "c.npz"
    save_checkpoint(path, {"x": np.linspace(0, 1, 1000)}, {"key": "k", "steps": 1})
    raw = bytearray(path.read_bytes())
    if damage == "truncate":
        raw = raw[: len(raw) // 2]
    elif damage == "flip":  # inside the stored array data (npz members are not compressed)
        raw[len(raw) // 3] ^= 0xFF
    elif damage == "garbage":
        raw = bytearray(b"not a checkpoint at all")
    else:
        raw = bytearray()
    path.write_bytes(bytes(raw))
    with pytest.raises(ValueError, match=r"checkpoint .* (corrupt|truncated)"):
        load_checkpoint(path)


def test_checkpoint_of_another_config_is_refused(tmp_path):
    save_checkpoint(tmp_path / "c.npz", {"x": np.zeros(2)}, {"key": "aaa", "steps": 0})
    with pytest.raises(ValueError, match="belongs to config 'aaa', not 'bbb'"):
        load_checkpoint(tmp_path / "c.npz", key="bbb")


def _growing_run(rng, saves: int):
    """States of a run whose "frames" history grows by a few rows per save."""
    frames = np.empty((0, 3))
    for step in range(saves):
        frames = np.concatenate([frames, rng.normal(size=(rng.integers(0, 4), 3))])
        yield step, {"frames": frames.copy(), "engine": rng.normal(size=5)}


def test_history_is_stored_once_and_restored_bit_exact(tmp_path):
    path = tmp_path / "state.npz"
    rng = np.random.default_rng(2)
    for step, state in _growing_run(rng, 6):
        save_checkpoint(path, state, {"key": "k", "steps": step}, history=["frames"])
        back, meta = load_checkpoint(path, key="k")
        assert meta["steps"] == step
        for name, array in state.items():
            np.testing.assert_array_equal(back[name], array)
            assert back[name].dtype == array.dtype
    stored = sum(np.load(f)["frames"].shape[0] for f in history_dir(path).iterdir())
    assert stored == len(state["frames"])  # every row once, over all the saves
    with np.load(path) as main:
        assert main["frames"].shape == (0, 3)  # the checkpoint itself holds no history


def test_a_history_chunk_left_by_a_killed_save_is_ignored(tmp_path):
    path = tmp_path / "state.npz"
    rng = np.random.default_rng(3)
    states = [state for _, state in _growing_run(rng, 4) if len(state["frames"])]
    save_checkpoint(path, states[0], {"key": "k", "steps": 0}, history=["frames"])
    listed = sorted(history_dir(path).iterdir())
    (history_dir(path) / f"{len(listed):06d}.npz").write_bytes(b"half a chunk")
    back, _ = load_checkpoint(path, key="k")
    np.testing.assert_array_equal(back["frames"], states[0]["frames"])
    save_checkpoint(path, states[-1], {"key": "k", "steps": 1}, history=["frames"])
    np.testing.assert_array_equal(load_checkpoint(path)[0]["frames"], states[-1]["frames"])


@pytest.mark.parametrize("damage", ["missing", "flip"])
def test_a_damaged_history_chunk_is_refused(tmp_path, damage):
    path = tmp_path / "state.npz"
    frames = np.linspace(0, 1, 3000).reshape(1000, 3)
    save_checkpoint(path, {"frames": frames}, {"key": "k", "steps": 1}, history=["frames"])
    chunk = next(history_dir(path).iterdir())
    if damage == "missing":
        chunk.unlink()
    else:
        raw = bytearray(chunk.read_bytes())
        raw[len(raw) // 2] ^= 0xFF
        chunk.write_bytes(bytes(raw))
    with pytest.raises(ValueError, match=r"history chunk .* (missing|corrupt)"):
        load_checkpoint(path)


def test_chunked_run_equals_one_long_run():
    """advance(a); advance(b) == advance(a + b): the premise of bit-identical resumes."""
    cfg = ToyPendulums(n_steps=900)
    one = PendulumStepper(cfg)
    one.advance(900)
    chunked = run_stepper(PendulumStepper(cfg), CheckpointPolicy(Path("unused"), "k", chunk=97))
    np.testing.assert_array_equal(chunked.theta, one.theta)
    np.testing.assert_array_equal(chunked.omega, one.omega)


def test_resume_from_checkpoint_in_process_is_bit_identical(tmp_path):
    cfg = ToyPendulums(n_steps=1000)
    reference = run_stepper(PendulumStepper(cfg))
    policy = CheckpointPolicy(tmp_path / "state.npz", "key", steps=300, chunk=100)

    class Killed(Exception):
        pass

    def kill_at_650(**progress):
        if progress["steps"] >= 650:
            raise Killed

    with pytest.raises(Killed):
        run_stepper(PendulumStepper(cfg), policy, progress=kill_at_650)
    resumed = resume_stepper(PendulumStepper(cfg), policy)
    assert resumed.steps == 600
    run_stepper(resumed, policy)
    np.testing.assert_array_equal(resumed.theta, reference.theta)
    np.testing.assert_array_equal(resumed.energy_trace, reference.energy_trace)


def _study(tmp_path: Path, delay: float) -> Path:
    path = tmp_path / "toy.toml"
    path.write_text(f'[scenario]\nkind = "toy_pendulums"\nn_steps = 3000\ndelay = {delay}\n')
    return path


def _timeseries(folder: Path):
    with xr.open_dataset(folder / "timeseries.nc") as ds:
        return ds.load()


def test_sigkilled_run_resumes_bit_identically(tmp_path):
    """`run --checkpoint`, SIGKILL mid-run, `resume`: same bits as an uninterrupted run."""
    study = _study(tmp_path, delay=0.15)
    ref = tmp_path / "ref"
    subprocess.run([*CLI, "run", str(study), "--out", str(ref), "--quiet"], check=True)
    out = tmp_path / "killed"
    proc = subprocess.Popen(
        [*CLI, "run", str(study), "--out", str(out), "--checkpoint", "steps=500", "--quiet"]
    )
    ckpt = out / "checkpoint" / "state.npz"
    end = time.monotonic() + 60
    while time.monotonic() < end:
        if ckpt.is_file() and load_checkpoint(ckpt)[1]["steps"] >= 1000:
            break
        time.sleep(0.02)
    os.kill(proc.pid, signal.SIGKILL)
    proc.wait(timeout=30)
    assert not (out / "summary.json").exists(), "the run must be killed before it ends"
    steps_at_kill = load_checkpoint(ckpt)[1]["steps"]
    assert 1000 <= steps_at_kill < 3000
    subprocess.run([*CLI, "resume", str(out), "--quiet"], check=True)
    a, b = _timeseries(ref), _timeseries(out)
    for name in ("theta", "omega", "energy"):
        np.testing.assert_array_equal(a[name].values, b[name].values)
    assert not (out / "checkpoint").exists()  # a finished run keeps no checkpoint


@pytest.mark.parametrize(("signum", "code"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_ctrl_c_or_sigterm_writes_a_checkpoint_and_partial_results(tmp_path, signum, code):
    study = _study(tmp_path, delay=1.0)  # three chunks of 1000 steps, each sleeping 1 s
    out = tmp_path / "run"
    proc = subprocess.Popen(
        [*CLI, "run", str(study), "--out", str(out), "--checkpoint", "minutes=60", "--quiet"],
        stderr=subprocess.PIPE,
        text=True,
    )
    end = time.monotonic() + 60
    while not (out / "checkpoint" / "policy.json").is_file() and time.monotonic() < end:
        time.sleep(0.02)
    time.sleep(1.5)  # inside the second chunk
    proc.send_signal(signum)
    _, stderr = proc.communicate(timeout=30)
    assert proc.returncode == code, stderr
    assert "interrupted" in stderr and "Traceback" not in stderr
    _, meta = load_checkpoint(out / "checkpoint" / "state.npz")
    partial = _timeseries(out / "partial")
    assert partial.sizes["sample"] * SAMPLE_EVERY == meta["steps"] > 0
    subprocess.run([*CLI, "resume", str(out), "--quiet"], check=True)
    assert _timeseries(out)["energy"].size == 3000 // SAMPLE_EVERY
