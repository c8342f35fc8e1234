"""Malformed studies and arguments: one clear line, exit code 2, no result file damaged.

Every case runs the real command line (``dominowave.cli.main``) in this process
next to a finished result folder and a finished sweep folder, and checks that the
error is a single line naming the problem, that the exit code is 2 and that not
one byte of the existing results changed. A few cases also run in a separate
process to check that no traceback reaches the terminal.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parent / "workflow"))
import workflow_helpers  # noqa: F401  (registers the steppable toy scenario)

from dominowave.chain import ChainParams, DominoChain
from dominowave.io.checkpoint import save_checkpoint

HERTZ_CHAIN = ["chain", "--n", "4", "--shape", "box", "--normal-law", "hertz"]

GOOD = '[scenario]\nkind = "theory"\nn_dominoes = 6\nn_frames = 10\n'

# (case id, study text or None, extra args, fragments the error line must contain)
STUDY_CASES = [
    ("unknown-table", '[scenaro]\nkind = "theory"\n', [], ["unknown key scenaro"]),
    (
        "chain-too-soft",
        '[scenario]\nkind = "chain"\nstiffness_ratio = 1e-6\n',
        [],
        ["k/k* = 1e-06) is too soft"],
    ),
    (
        "chain-too-stiff",
        '[scenario]\nkind = "chain"\nstiffness_ratio = 1e308\n',
        [],
        ["1e+10 allowed"],
    ),
    (
        "unknown-key",
        GOOD + "spacng = 0.02\n",
        [],
        ["study.toml:5", "unknown key scenario.spacng", "valid keys"],
    ),
    (
        "chain-box-with-base",
        '[scenario]\nkind = "chain"\nshape = "box"\nbase = "two"\n',
        [],
        ["base = 'two'", "shape = 'clump' only"],
    ),
    (
        "chain-clump-with-rounding",
        '[scenario]\nkind = "chain"\nrounding = 1e-4\n',
        [],
        ["rounding = 0.0001", "shape = 'box' only"],
    ),
    (
        "chain-hertz-clump",
        '[scenario]\nkind = "chain"\nnormal_law = "hertz"\nyoung = 2.5e9\n',
        [],
        ["normal_law = 'hertz' needs shape = 'box'"],
    ),
    (
        "chain-hertz-poisson",
        '[scenario]\nkind = "chain"\nshape = "box"\nnormal_law = "hertz"\nyoung = 2.5e9\n'
        "poisson = 0.5\n",
        [],
        ["poisson", "0.5"],
    ),
    ("no-scenario", '[output]\ndir = "x"\n', [], ["scenario is required"]),
    ("empty-file", "", [], ["scenario is required"]),
    ("no-kind", "[scenario]\nd_over_l = 0.4\n", [], ["scenario.kind = missing", "theory"]),
    (
        "unknown-kind",
        '[scenario]\nkind = "thoery"\n',
        [],
        ["study.toml:2", "'thoery'", "not one of"],
    ),
    (
        "unit-string",
        GOOD + 'height = "5 cm"\n',
        [],
        ["study.toml:5", "scenario.height = '5 cm'", "SI units (m)"],
    ),
    ("bool-for-number", GOOD + "mass = true\n", [], ["scenario.mass = True", "not a number"]),
    ("list-for-number", GOOD + "mass = [0.01]\n", [], ["scenario.mass = [0.01]", "not a number"]),
    (
        "float-for-int",
        '[scenario]\nkind = "theory"\nn_dominoes = 30.5\n',
        [],
        ["scenario.n_dominoes = 30.5", "not an integer"],
    ),
    (
        "negative-height",
        GOOD + "height = -0.05\n",
        [],
        ["scenario.height = -0.05", "valid range (0, inf) m"],
    ),
    ("zero-mass", GOOD + "mass = 0\n", [], ["scenario.mass = 0", "(0, inf) kg"]),
    (
        "spacing-above-height",
        GOOD + "d_over_l = 1.2\n",
        [],
        ["study.toml:5", "scenario.d_over_l = 1.2", "valid range (0, 1)"],
    ),
    (
        "thickness-above-height",
        GOOD + "thickness = 0.05\n",
        [],
        ["scenario.thickness", "less than height"],
    ),
    ("nan", GOOD + "d_over_l = nan\n", [], ["scenario.d_over_l = nan", "not a finite number"]),
    ("inf-mass", GOOD + "mass = inf\n", [], ["scenario.mass = inf", "not a finite number"]),
    (
        "one-domino",
        '[scenario]\nkind = "theory"\nn_dominoes = 1\n',
        [],
        ["scenario.n_dominoes = 1", "[2, 100000]"],
    ),
    (
        "two-stiffnesses",
        GOOD + "stiffness = 100.0\nstiffness_ratio = 10.0\n",
        [],
        ["stiffness = 100.0 and stiffness_ratio = 10.0", "exactly one"],
    ),
    (
        "bad-convention",
        GOOD + 'stiffness_convention = "yade"\n',
        [],
        ["scenario.stiffness_convention = 'yade'"],
    ),
    (
        "negative-friction",
        GOOD + "friction_floor = -0.1\n",
        [],
        ["scenario.friction_floor = -0.1", "[0, inf)"],
    ),
    (
        "renamed-key",
        GOOD + "spacing = 0.024\n",
        [],
        ["study.toml:5", "scenario.spacing was renamed: write d_over_l"],
    ),
    (
        "renamed-swept-key",
        GOOD + "[sweep.grid]\ngravity = [9.81]\n",
        [],
        ["study.toml:6", "sweep.grid.gravity was renamed: write g"],
    ),
    ("toml-syntax", GOOD + "height = = 1\n", [], ["not valid TOML", "line 5"]),
    ("sweep-empty-grid", GOOD + "[sweep.grid]\n", [], ["sweep.grid is empty"]),
    (
        "sweep-empty-list",
        GOOD + "[sweep.grid]\nd_over_l = []\n",
        [],
        ["sweep.grid.d_over_l", "no points"],
    ),
    ("sweep-empty-points", GOOD + "[sweep]\npoints = []\n", [], ["sweep.points", "no points"]),
    (
        "sweep-grid-and-points",
        GOOD + "[sweep]\ngrid = {d_over_l = [0.2]}\npoints = [{d_over_l = 0.4}]\n",
        [],
        ["exactly one of sweep.grid or sweep.points"],
    ),
    (
        "sweep-unknown-field",
        GOOD + "[sweep.grid]\nspaceing = [0.01]\n",
        [],
        ["study.toml:6", "sweep.grid.spaceing is not a scenario field"],
    ),
    (
        "sweep-bad-value",
        GOOD + "[sweep]\npoints = [{d_over_l = 0.2}, {d_over_l = 0.4}, "
        "{d_over_l = 0.6}, {d_over_l = -1.0}]\n",
        [],
        ["study.toml:6", "sweep point 3 (d_over_l=-1.0)", "(0, 1)"],
    ),
    (
        "sweep-string-value",
        GOOD + '[sweep.grid]\nmass = ["1 g"]\n',
        [],
        ["sweep point 0", "scenario.mass = '1 g'"],
    ),
    ("sweep-kind", GOOD + '[sweep.grid]\nkind = ["rods"]\n', [], ["cannot change scenario.kind"]),
    ("output-unknown-key", GOOD + "[output]\nfolder = 'x'\n", [], ["unknown key output.folder"]),
    ("output-dir-type", GOOD + "[output]\ndir = 3\n", [], ["output.dir = 3", "not a string"]),
    ("sweep-without-table", GOOD, ["sweep"], ["no [sweep] table"]),
    ("vtk-syntax", GOOD, ["run", "--vtk", "each=3"], ["--vtk 'each=3'", "every=N"]),
    ("vtk-not-int", GOOD, ["run", "--vtk", "every=abc"], ["--vtk every = 'abc'", "not an integer"]),
    ("vtk-zero", GOOD, ["run", "--vtk", "every=0"], ["--vtk every = 0", "(0, inf)"]),
    ("checkpoint-negative", GOOD, ["run", "--checkpoint", "steps=-5"], ["--checkpoint steps"]),
    ("checkpoint-unknown", GOOD, ["run", "--checkpoint", "hours=2"], ["steps=N, minutes=N"]),
    (
        "checkpoint-not-steppable",
        GOOD,
        ["run", "--checkpoint", "steps=10"],
        ["scenario 'theory' has no time loop"],
    ),
    (
        "scheduler-address",
        GOOD + "[sweep.grid]\nd_over_l = [0.2]\n",
        ["sweep", "--scheduler", "not an address"],
        ["is not a scheduler address"],
    ),
    (
        "workers-zero",
        GOOD + "[sweep.grid]\nd_over_l = [0.2]\n",
        ["sweep", "--workers", "0"],
        ["--workers = 0", "[1, inf)"],
    ),
]


def tree_digest(root: Path) -> dict[str, str]:
    return {
        str(p.relative_to(root)): hashlib.sha256(p.read_bytes()).hexdigest()
        for p in sorted(root.rglob("*"))
        if p.is_file()
    }


@pytest.fixture(scope="module")
def results(tmp_path_factory):
    """A finished run folder and sweep folder that no bad input may touch."""
    from dominowave.io.config import parse_study
    from dominowave.io.models import TheoryScenario
    from dominowave.sweep.execute import execute_point
    from dominowave.sweep.runner import store_outcome
    from dominowave.sweep.store import SweepStore

    root = tmp_path_factory.mktemp("results")
    cfg = TheoryScenario(n_dominoes=6, n_frames=10)
    store_outcome(root / "run", cfg, execute_point(cfg), keep_trajectory=True)
    store = SweepStore(root / "sweep").open_for_writing()
    study = parse_study(
        {
            "scenario": {"kind": "theory", "n_dominoes": 6, "n_frames": 10},
            "sweep": {"grid": {"d_over_l": [0.2, 0.4]}},
        }
    )
    from dominowave.sweep.hashing import point_key

    for point in study.points:
        store_outcome(store.folder(point_key(point)), point, execute_point(point), True)
    store.write_index({})
    (root / "sweep" / "study.toml").write_text(GOOD)
    (root / "other.toml").write_text(GOOD.replace("n_dominoes = 6", "n_dominoes = 7"))
    return root


def check_one_line(code: int, err: str, fragments) -> None:
    assert code == 2, err
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0].startswith("dominowave: error: ")
    assert "Traceback" not in err
    for fragment in fragments:
        assert fragment in lines[0], (fragment, lines[0])


@pytest.mark.parametrize(
    ("text", "args", "fragments"), [c[1:] for c in STUDY_CASES], ids=[c[0] for c in STUDY_CASES]
)
def test_bad_study_or_option(text, args, fragments, results, tmp_path, cli):
    before = tree_digest(results)
    study = tmp_path / "study.toml"
    study.write_text(text)
    command = args[0] if args else "run"
    for target in ("run", "sweep"):  # write into the existing results: must be refused or
        out = results / target  # fail before anything is written
        code, _, err = cli(command, study, "--out", out, *args[1:])
        check_one_line(code, err, fragments)
    assert tree_digest(results) == before


def test_unwritable_output_folder(results, tmp_path, cli):
    blocker = tmp_path / "a_file"
    blocker.write_text("x")
    study = tmp_path / "s.toml"
    study.write_text(GOOD + "[sweep.grid]\nd_over_l = [0.2]\n")
    for command in ("run", "sweep"):
        code, _, err = cli(command, study, "--out", blocker / "out")
        check_one_line(code, err, [str(blocker)])
        assert "is not a folder" in err or "is not writable (Not a directory)" in err


@pytest.mark.skipif(os.geteuid() == 0, reason="root ignores folder permissions")
def test_read_only_output_folder(tmp_path, cli):
    ro = tmp_path / "ro"
    ro.mkdir(mode=0o555)
    study = tmp_path / "s.toml"
    study.write_text(GOOD)
    code, _, err = cli("run", study, "--out", ro / "out")
    check_one_line(code, err, ["not writable"])


@pytest.mark.parametrize(
    ("args", "fragments"),
    [
        (["run", "{tmp}/missing.toml"], ["missing.toml: study file not found"]),
        (["run", "{tmp}"], ["is a directory"]),
        (["config", "--example", "chainz"], ["example = 'chainz' is not one of"]),
        (["collect", "{results}/run"], ["not a sweep folder (no index.json)"]),
        (["collect", "{tmp}"], ["not a sweep folder"]),
        (["plot", "{tmp}/nowhere"], ["no such folder"]),
        (["plot", "{tmp}"], ["neither a sweep folder"]),
        (["animate", "{results}/run", "--out", "{tmp}/a.avi"], [".mp4 or .gif"]),
        (["animate", "{results}/run", "--out", "{tmp}/no/such/dir/a.gif"], ["does not exist"]),
        (
            ["animate", "{results}/run", "--out", "{tmp}/a.gif", "--fps", "0"],
            ["--fps = 0", "[1, 120]"],
        ),
        (
            ["animate", "{results}/run", "--out", "{tmp}/a.gif", "--slowdown", "-2"],
            ["--slowdown = -2"],
        ),
        (
            ["animate", "{results}/sweep", "--point", "0123456789abcdef", "--out", "{tmp}/a.gif"],
            ["--point 0123456789abcdef: no such point"],
        ),
        (["animate", "{tmp}", "--out", "{tmp}/a.gif"], ["trajectory.nc: not found"]),
        (["resume", "{tmp}"], ["nothing to resume"]),
        (["chain", "--n", "4", "--seed", "-1"], ["--seed = -1", "[0, inf)"]),
        (["chain", "--n", "4", "--members", "-3"], ["--members = -3", "[1, inf)"]),
        (
            ["chain", "--n", "4", "--shear-kinematics", "exact"],
            ["--shear-kinematics = 'exact' is not one of 'contact_point', 'yade'"],
        ),
        (["chain", "--n", "4", "--stiffness-ratio", "1e-6"], ["k/k* = 1e-06) is too soft"]),
        (["chain", "--n", "4", "--fit-from", "3"], ["--fit-from = 3 is outside [1, 2]"]),
        (  # the user's stiffness is named, not the time step it would give
            ["chain", "--n", "4", "--shape", "box", "--stiffness-ratio", "inf"],
            ["--stiffness-ratio = inf is outside the valid range (0, inf)"],
        ),
        (["chain", "--n", "4", "--young", "inf"], ["--young = inf is outside"]),
        (  # the chain's length is named, not the fit that it leaves no room for
            ["predict", "--gap", "0.00938", "--floor", "felt", "--n", "1"],
            ["n_dominoes = 1 is outside the valid range [3, inf)"],
        ),
        (["chain", "--n", "4", "--fit-from", "0"], ["--fit-from = 0 is outside [1, 2]"]),
        (["chain", "--n", "4", "--placement-along", "-1e-3"], ["--placement-along = -0.001"]),
        (["chain", "--n", "4", "--placement-across", "1e-3"], ["needs --model = '3d'"]),
        (["chain", "--n", "4", "--push-error", "-1"], ["--push-error = -1", "[0, inf)"]),
        (["chain", "--n", "4", "--stiffness-ratio", "1e308"], ["steps", "1e+10 allowed"]),
        (["chain", "--n", "4", "--shape", "cube"], ["shape = 'cube'", "'clump', 'box'"]),
        (
            ["chain", "--n", "4", "--shape", "box", "--base", "two"],
            ["base = 'two'", "shape = 'clump' only"],
        ),
        (
            ["chain", "--n", "4", "--shape", "box", "--spheres-per-column", "20"],
            ["--spheres-per-column = 20", "--shape = 'clump' only"],
        ),
        (["chain", "--n", "4", "--rounding", "1e-4"], ["rounding = 0.0001", "shape = 'box' only"]),
        (
            ["chain", "--n", "4", "--shape", "box", "--rounding", "0.01"],
            ["rounding = 0.01", "(0, 0.0025)"],
        ),
        (
            ["chain", "--n", "4", "--shape", "box", "--restitution-floor", "2"],
            ["--restitution-floor = 2", "(0, 1]"],
        ),
        (
            ["chain", "--n", "4", "--shape", "box", "--normal-law", "hooke", "--young", "1e9"],
            ["--normal-law = 'hooke' is not one of 'linear', 'hertz'"],
        ),
        (
            ["chain", "--n", "4", "--normal-law", "hertz", "--young", "1e9"],
            ["--normal-law = 'hertz' needs --shape = 'box'"],
        ),
        (
            HERTZ_CHAIN,
            ["--normal-law = 'hertz' needs young", "(0, inf) Pa"],
        ),
        (
            [*HERTZ_CHAIN, "--young", "1e9", "--poisson", "0.5"],
            ["poisson = 0.5 is outside the valid range [0, 0.5)"],
        ),
        (
            [*HERTZ_CHAIN, "--young", "100", "--poisson", "0.3"],
            ["young = 100 Pa (Hertz law) is too soft", "young >= "],
        ),
        (
            ["chain", "--n", "4", "--shape", "box", "--poisson", "0.3"],
            ["--poisson = 0.3 is an option of --normal-law = 'hertz' only"],
        ),
        (["rods", "--push", "1e9"], ["push = 1e+09", "(0, 100]"]),
        (["rods", "--d-over-l", "1e-300"], ["d_over_l = 1e-300", "[0.001, 1)"]),
        (
            ["run", "{results}/other.toml", "--out", "{results}/run"],
            ["holds the result of another config", "--force"],
        ),
        (
            ["run", "{results}/other.toml", "--out", "{results}/sweep"],
            ["not empty and holds no result"],
        ),
    ],
    ids=lambda v: "-".join(v) if isinstance(v, list) and v and v[0].isalpha() else None,
)
def test_bad_arguments(args, fragments, results, tmp_path, cli):
    before = tree_digest(results)
    args = [a.format(tmp=tmp_path, results=results) for a in args]
    code, _, err = cli(*args)
    check_one_line(code, err, [f.format(tmp=tmp_path, results=results) for f in fragments])
    assert tree_digest(results) == before
    assert not list(tmp_path.glob("*.gif")) and not list(tmp_path.glob("*.avi"))


@pytest.mark.parametrize("damage", ["truncated", "tampered", "foreign"])
def test_corrupt_checkpoint_is_refused_on_resume(damage, tmp_path, cli):
    study = tmp_path / "toy.toml"
    study.write_text('[scenario]\nkind = "toy_pendulums"\nn_steps = 200\n')
    out = tmp_path / "run"
    ck = out / "checkpoint"
    ck.mkdir(parents=True)
    (ck / "study.toml").write_text(study.read_text())
    (ck / "policy.json").write_text('{"steps": 100, "seconds": 0}')
    from dominowave.io.config import load_study
    from dominowave.sweep.hashing import point_key

    key = point_key(load_study(study).scenario) if damage != "foreign" else "someotherkey"
    state = {
        "theta": np.zeros(16),
        "omega": np.zeros(16),
        "steps": np.array(100),
        "energy_trace": np.zeros(1),
    }
    save_checkpoint(ck / "state.npz", state, {"key": key, "steps": 100})
    raw = (ck / "state.npz").read_bytes()
    if damage == "truncated":
        (ck / "state.npz").write_bytes(raw[: len(raw) // 2])
    elif damage == "tampered":
        i = raw.index(b"\x00" * 8)  # inside the zero-filled theta array
        (ck / "state.npz").write_bytes(raw[:i] + b"\x01" + raw[i + 1 :])
    before = tree_digest(out)
    code, _, err = cli("resume", out)
    check_one_line(code, err, ["checkpoint", str(ck / "state.npz")])
    assert tree_digest(out) == before
    assert not (out / "summary.json").exists()


def test_errors_reach_a_real_terminal_as_one_line(tmp_path):
    """In a separate process too: one line on stderr, exit 2, nothing on stdout."""
    study = tmp_path / "s.toml"
    study.write_text(GOOD + "mass = -1.0\n")
    proc = subprocess.run(
        [sys.executable, "-m", "dominowave", "run", str(study), "--out", str(tmp_path / "o")],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert proc.returncode == 2
    assert proc.stdout == ""
    assert proc.stderr.count("\n") == 1 and "scenario.mass = -1.0" in proc.stderr
    assert not (tmp_path / "o").exists()


def test_chain_step_from_the_estimate_refuses_before_building():
    """``DominoChain(safety=...)`` builds a scene for the engine's estimate: the memory
    and softness checks come first (a 1e5-domino chain would otherwise be built, minutes
    of work, before it is refused)."""
    p = ChainParams(shape="box", model="3d", n_dominoes=100_000, young=2.5e9, normal_law="hertz")
    with pytest.raises(ValueError, match="more than this machine can hold"):
        DominoChain(p, safety=0.5)
    soft = ChainParams(shape="box", n_dominoes=4, young=100.0, normal_law="hertz")
    with pytest.raises(ValueError, match=r"young = 100 Pa \(Hertz law\) is too soft"):
        DominoChain(soft, safety=0.5)


@pytest.mark.parametrize(
    "args",
    [
        ["predict", "--gap", "0.00938", "--floor", "carpet"],
        ["chain", "--n", "4", "--fit-from", "9"],
    ],
    ids=lambda a: a[0],
)
def test_a_refused_command_leaves_no_empty_output_folder(tmp_path, args):
    out = tmp_path / "new" / "out"
    proc = subprocess.run(
        [sys.executable, "-m", "dominowave", *args, "--out", str(out)],
        capture_output=True,
        text=True,
    )
    assert proc.returncode == 2, proc.stderr
    assert not (tmp_path / "new").exists()


def test_a_folder_with_files_is_never_removed(tmp_path):
    from dominowave.io.atomic import ensure_writable_dir, remove_empty_created

    kept, emptied = tmp_path / "a" / "kept", tmp_path / "b"
    ensure_writable_dir(kept)
    ensure_writable_dir(emptied)
    (kept / "result.csv").write_text("1\n")
    assert set(remove_empty_created()) == {emptied}
    assert (kept / "result.csv").exists() and not emptied.exists()


def test_an_interrupted_chain_leaves_no_empty_output_folder(tmp_path):
    import signal
    import time

    out = tmp_path / "new" / "out"
    proc = subprocess.Popen(
        [sys.executable, "-m", "dominowave", "chain", "--n", "200", "--out", str(out)],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    end = time.monotonic() + 60
    while not out.exists() and time.monotonic() < end:  # the folder is made before the run
        time.sleep(0.05)
    assert out.is_dir()
    proc.send_signal(signal.SIGINT)
    _, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130, stderr
    assert not (tmp_path / "new").exists()
