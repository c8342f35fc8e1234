"""Results are never destroyed, files are readable by any JSON/TOML reader, folders are shared.

Each test reproduces a failure a user met: a forced re-run that failed deleted the good
result it was to replace; summary.json held bare NaN (rejected by strict JSON readers);
result folders were created 0700 whatever the umask; a study file saved with a byte-order
mark was rejected as invalid TOML.
"""

from __future__ import annotations

import json
import math
import os
import stat

import pytest

from dominowave.io.atomic import atomic_dir, write_json
from dominowave.io.config import load_study
from dominowave.io.results import read_summary
from dominowave.sweep.runner import run_one

STUDY = '[scenario]\nkind = "slow_theory"\nn_dominoes = 8\nn_frames = 10\nd_over_l = {d_over_l}\n'


def _strict_load(text: str):
    """json.loads that rejects NaN and Infinity, as RFC 8259 readers do."""

    def refuse(name):
        raise ValueError(f"non-standard JSON constant {name}")

    return json.loads(text, parse_constant=refuse)


def test_forced_rerun_that_fails_keeps_the_previous_result(tmp_path):
    good = tmp_path / "good.toml"
    good.write_text(STUDY.format(d_over_l=0.2))
    out = tmp_path / "run"
    assert run_one(load_study(good), out) == "ok"
    before = {p.name: p.read_bytes() for p in out.iterdir()}

    failing = tmp_path / "failing.toml"
    failing.write_text(STUDY.format(d_over_l=0.6) + "fail_above = 0.02\n")
    with pytest.raises(ValueError, match=r"run failed: .*previous result .* is kept"):
        run_one(load_study(failing), out, force=True)
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before
    failure = json.loads((tmp_path / "run.failed" / "failure.json").read_text())
    assert failure["error"].startswith("RuntimeError: deliberate failure")

    # a forced re-run that succeeds replaces the result (and the failure stays beside it)
    other = tmp_path / "other.toml"
    other.write_text(STUDY.format(d_over_l=0.3))
    assert run_one(load_study(other), out, force=True) == "ok"
    assert (out / "summary.json").read_bytes() != before["summary.json"]


def test_json_files_are_strict_and_nan_reads_back_as_nan(tmp_path):
    folder = tmp_path / "point"
    folder.mkdir()
    write_json(folder / "summary.json", {"speed": 1.5, "steady_speed": math.nan, "t": math.inf})
    data = _strict_load((folder / "summary.json").read_text())
    assert data == {"speed": 1.5, "steady_speed": None, "t": None}
    summary = read_summary(folder)
    assert summary["speed"] == 1.5 and math.isnan(summary["steady_speed"])


def test_every_json_file_of_a_run_is_strict(tmp_path):
    study = tmp_path / "s.toml"
    study.write_text(STUDY.format(d_over_l=0.2))
    out = tmp_path / "run"
    run_one(load_study(study), out)
    for path in out.rglob("*.json"):
        _strict_load(path.read_text())


@pytest.mark.parametrize("umask", [0o022, 0o002])
def test_result_folders_follow_the_umask(tmp_path, umask):
    old = os.umask(umask)
    try:
        atomic_dir(tmp_path / "d", lambda folder: (folder / "f.txt").write_text("x"))
    finally:
        os.umask(old)
    assert stat.S_IMODE((tmp_path / "d").stat().st_mode) == 0o777 & ~umask


def test_study_file_with_byte_order_mark_and_crlf_is_read(tmp_path, cli):
    _, text, _ = cli("config", "--example", "theory")
    path = tmp_path / "windows.toml"
    path.write_bytes(b"\xef\xbb\xbf" + text.replace("\n", "\r\n").encode("utf-8"))
    code, stdout, err = cli("config", path)
    assert code == 0, err
    assert "ok, scenario theory, 1 point(s)" in stdout


SWEEP = (
    '[scenario]\nkind = "theory"\nn_dominoes = 6\nn_frames = 10\n[sweep.grid]\nd_over_l = {grid}\n'
)


def test_a_sweep_folder_refuses_another_study_unless_forced(dask_client, tmp_path, cli):
    first, second = tmp_path / "a.toml", tmp_path / "b.toml"
    first.write_text(SWEEP.format(grid="[0.2, 0.4]"))
    second.write_text(SWEEP.format(grid="[0.6]"))
    out = tmp_path / "sweep"
    addr = dask_client.scheduler.address
    assert cli("sweep", first, "--out", out, "--scheduler", addr, "--quiet")[0] == 0
    study_before = (out / "study.toml").read_bytes()
    code, _, err = cli("sweep", second, "--out", out, "--scheduler", addr, "--quiet")
    assert code == 2
    assert err.strip().count("\n") == 0
    assert "holds another study" in err and "--force" in err
    assert (out / "study.toml").read_bytes() == study_before
    assert len(list((out / "points").iterdir())) == 2
    # the same study again is a resume, not another study
    code, stdout, _ = cli("sweep", first, "--out", out, "--scheduler", addr, "--quiet")
    assert code == 0 and "2 already stored, 0 run now" in stdout
    code, stdout, _ = cli("sweep", second, "--out", out, "--scheduler", addr, "--force", "--quiet")
    assert code == 0 and len(list((out / "points").iterdir())) == 3


def test_a_second_sweep_on_a_folder_in_use_is_refused(tmp_path):
    from dominowave.sweep.runner import run_sweep
    from dominowave.sweep.store import SweepStore

    study = tmp_path / "s.toml"
    study.write_text(SWEEP.format(grid="[0.2]"))
    store = SweepStore(tmp_path / "sweep").open_for_writing()
    with store.lock(), pytest.raises(ValueError, match="being written by another sweep"):
        run_sweep(load_study(study), store.root, quiet=True)
    assert not (store.root / "study.toml").exists()
    # released: the folder can be swept again (no cluster needed for zero points to run)
    with store.lock():
        pass


def test_sweep_help_names_the_sweep_table(cli):
    code, stdout, _ = cli("sweep", "--help")
    assert code == 0 and "Study file with a [sweep] table." in stdout


@pytest.mark.parametrize(
    "args",
    [
        ["figures"],
        ["chain", "--n", "4"],
        ["compare-rods", "--quick"],
        ["paper-fig6", "--quick"],
    ],
    ids=lambda a: a[0],
)
def test_an_output_folder_that_is_a_file_is_one_line(tmp_path, cli, args):
    target = tmp_path / "afile"
    target.write_text("not a folder")
    code, _, err = cli(*args, "--out", target)
    assert code == 2
    assert err == f"dominowave: error: output folder {target} exists and is not a folder\n"
    assert target.read_text() == "not a folder"


def test_a_full_disk_is_said_in_one_line(tmp_path, cli, monkeypatch):
    """HDF5 reports a full disk as "NetCDF: HDF error"; the user reads "disk full"."""
    import shutil
    from collections import namedtuple

    from dominowave.io import results

    def hdf_error(path, ds):
        raise RuntimeError("NetCDF: HDF error")

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(results, "_write_netcdf", hdf_error)
    monkeypatch.setattr(shutil, "disk_usage", lambda path: usage(10**9, 10**9, 4096))
    study = tmp_path / "s.toml"
    study.write_text(STUDY.format(d_over_l=0.2))
    code, _, err = cli("run", study, "--out", tmp_path / "run")
    assert code == 1
    assert err.startswith("dominowave: error: disk full") and err.count("\n") == 1
    assert not (tmp_path / "run").exists()  # nothing half-written is left
