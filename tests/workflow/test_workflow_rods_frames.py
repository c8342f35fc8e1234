"""A rods run records the chain frame by frame: trajectory.nc, `animate`, `--vtk`, resume.

The geometric checks use only the stored trajectory (pivot ``x_n``, angle, height,
thickness) and the contact times and overlaps the simulation reported: wherever the
rods model says the top front edge of domino n touches the back face of domino n+1,
the rectangles drawn from the trajectory must touch there too.
"""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr
from typer.testing import CliRunner

from dominowave.cli import app
from dominowave.io.animation import frame_times
from dominowave.io.checkpoint import load_checkpoint
from dominowave.io.models import RodsScenario
from dominowave.io.results import read_summary, read_trajectory
from dominowave.io.trajectory import ChainTrajectory
from dominowave.rods import kernel
from dominowave.sweep.registry import RunContext
from dominowave.sweep.run_rods import FRAME_VALUES, TIME_LIMIT, frame_schedule, run_rods

STUDY = """\
[scenario]
kind = "rods"
n_dominoes = 8
height = 0.048
thickness = 0.0075
d_over_l = 0.5
"""
VTK_EVERY = 20


def _dominowave(*args) -> str:
    result = CliRunner().invoke(app, [str(a) for a in args], catch_exceptions=False)
    assert result.exit_code == 0, result.output
    return result.output


@pytest.fixture(scope="module")
def rods_folder(tmp_path_factory):
    """A rods run through the CLI, with VTK every VTK_EVERY frames."""
    tmp = tmp_path_factory.mktemp("rods_frames")
    study = tmp / "study.toml"
    study.write_text(STUDY)
    out = tmp / "run"
    _dominowave("run", study, "--out", out, "--vtk", f"every={VTK_EVERY}", "--quiet")
    return out


def _back_face_contact(traj: ChainTrajectory, angle: np.ndarray, n: int) -> tuple[float, float]:
    """Overlap [m] of domino n's top front corner behind domino n+1's back face (> 0:
    inside), and the corner's height along that face [m], for the angles ``angle`` (N,)."""
    corners = ChainTrajectory(
        np.zeros(1), traj.base_x[:1], angle[None, :], traj.height, traj.thickness
    ).corners(0)
    corner = corners[n, 2]  # top front
    back_bottom, back_top = corners[n + 1, 0], corners[n + 1, 3]
    along = (back_top - back_bottom) / traj.height  # works for s = 0 too
    inward = np.array([along[1], -along[0]])  # towards the front face
    return float((corner - back_bottom) @ inward), float((corner - back_bottom) @ along)


def test_rods_run_writes_its_trajectory(rods_folder):
    traj = read_trajectory(rods_folder)
    summary = read_summary(rods_folder)
    l, pitch = 0.048, 0.024 + 0.0075
    assert traj.n_dominoes == 8 and traj.height == l and traj.thickness == 0.0075
    np.testing.assert_allclose(traj.base_x - np.arange(8) * pitch, 0.0, atol=1e-15)
    # frame 0: all upright, domino 0 pushed; last frame (the run stops when the last
    # domino's first contact ended): all have struck their successor, the last is falling
    assert np.all(traj.angle[0] == 0.0) and traj.omega[0, 0] == 5.0
    assert np.all(traj.angle[-1, :-1] > np.arcsin(0.024 / l)) and traj.omega[-1, -1] > 0
    assert traj.time[-1] == summary["end_time"]  # the final state is the last frame
    assert 100 < traj.n_frames < 1000  # a few hundred frames for the run


@pytest.mark.parametrize("thickness", [0.0075, 0.0])
def test_validate_rods_trajectory_touches_where_the_model_reports_contact(thickness):
    """From the trajectory alone: at each domino's first-contact time (events) the
    striking domino's top front corner lies on the next domino's back face (within the
    peak overlap of that contact), at height ``sqrt(l^2 - d^2)`` (``sin(beta) = d/l``)
    on it; in every frame during a reported contact the corner is behind the face by
    ``0 < delta <= delta_max``; before it, in front of the face (``delta < 0``)."""
    cfg = RodsScenario(n_dominoes=10, thickness=thickness)
    result = run_rods(cfg)
    traj, arrival = result.trajectory, result.events["arrival_time"]
    table = result.timeseries["contacts"].values
    l, d = cfg.height, cfg.spacing
    lower, upper, kind = (table[:, c] for c in (kernel.EV_LOWER, kernel.EV_UPPER, kernel.EV_KIND))
    wave = table[(kind == 0) & (upper == lower + 1)]  # top edge of n on back face of n+1
    assert np.all(np.isfinite(arrival))  # the wave ran through
    frames_in_contact = 0
    for n in range(cfg.n_dominoes - 1):
        first = wave[wave[:, kernel.EV_LOWER] == n][0]
        assert first[kernel.EV_T_ON] == arrival[n + 1]
        angle = np.array([np.interp(arrival[n + 1], traj.time, a) for a in traj.angle.T])
        delta, height = _back_face_contact(traj, angle, n)
        delta_max = first[kernel.EV_DELTA_MAX]
        assert abs(delta) <= delta_max, (n, delta, delta_max)
        assert abs(height - np.sqrt(l * l - d * d)) <= delta_max, (n, height)
        for f in np.nonzero(traj.time < arrival[n + 1])[0]:
            assert _back_face_contact(traj, traj.angle[f], n)[0] < 0.0, (n, f)
    for row in wave:
        n, t_on, t_off = int(row[kernel.EV_LOWER]), row[kernel.EV_T_ON], row[kernel.EV_T_OFF]
        t_off = np.inf if np.isnan(t_off) else t_off
        for f in np.nonzero((traj.time > t_on) & (traj.time < t_off))[0]:
            delta, height = _back_face_contact(traj, traj.angle[f], n)
            assert 0.0 < delta <= row[kernel.EV_DELTA_MAX] * (1 + 1e-9), (n, f, delta)
            assert 0.0 <= height <= l
            frames_in_contact += 1
    assert frames_in_contact > 20  # the frame interval resolves the contacts


def test_animate_draws_the_rods_run(rods_folder, tmp_path):
    import imageio.v2 as imageio

    movie = tmp_path / "rods.gif"
    n = frame_times(read_trajectory(rods_folder), fps=5, slowdown=10.0).size
    assert f"wrote {n} frames" in _dominowave(
        "animate", rods_folder, "--out", movie, "--fps", "5", "--slowdown", "10"
    )
    frames = np.array(imageio.mimread(movie))
    assert frames.shape[0] == n > 10
    # the picture changes: upright chain first, fallen chain last
    assert np.mean(frames[0] != frames[-1]) > 0.01


def test_vtk_boxes_of_a_rods_run_follow_the_trajectory(rods_folder):
    """Box corners of the VTK files, from the stored pivot and angle: the top front edge
    of domino n is at ``x_n + l sin(theta)``, height ``l cos(theta)``."""
    import meshio

    traj = read_trajectory(rods_folder)
    files = sorted((rods_folder / "vtk").glob("dominoes_*.vtu"))
    assert len(files) == -(-traj.n_frames // VTK_EVERY)
    for k in (1, len(files) - 1):
        mesh = meshio.read(files[k])
        f = k * VTK_EVERY
        theta, x = traj.angle[f], traj.base_x[f]
        boxes = mesh.points.reshape(traj.n_dominoes, 8, 3)
        top_front = boxes[:, 2]
        np.testing.assert_allclose(top_front[:, 0], x + traj.height * np.sin(theta), atol=1e-12)
        np.testing.assert_allclose(top_front[:, 2], traj.height * np.cos(theta), atol=1e-12)
        np.testing.assert_array_equal(mesh.cell_data["angle"][0], theta)
        np.testing.assert_array_equal(mesh.cell_data["omega"][0], traj.omega[f])


def test_frames_survive_an_interrupted_and_resumed_run(tmp_path):
    """The frames are in the checkpoint: a resumed run has the trajectory of an
    uninterrupted one, bit for bit."""
    cfg = RodsScenario(n_dominoes=12, mass_model="block", friction_dominoes=0.2)
    reference = run_rods(cfg).trajectory

    def interrupt(**progress):
        if progress["steps"] >= 3000:
            raise KeyboardInterrupt

    checkpoint = tmp_path / "checkpoint"
    checkpoint.mkdir()
    ctx = RunContext(progress=interrupt, checkpoint_dir=checkpoint, checkpoint_every_seconds=3600)
    with pytest.raises(KeyboardInterrupt):
        run_rods(cfg, ctx)
    state, _ = load_checkpoint(checkpoint / "state.npz")
    saved = int(state["n_frames"][0])
    assert state["frame_theta"].shape[0] == saved > 1
    assert np.array_equal(state["frame_theta"], reference.angle[:saved])
    resumed = run_rods(cfg, RunContext(checkpoint_dir=checkpoint)).trajectory
    assert xr.Dataset.identical(resumed.to_dataset(), reference.to_dataset())


@pytest.mark.parametrize("n", [2, 30, 110, 1000, 100_000])
def test_frame_buffer_covers_the_whole_run_within_its_memory_bound(n):
    time_scale, dt = 0.07, 4.4e-5
    t_max = TIME_LIMIT * n * time_scale
    every, max_frames = frame_schedule(t_max, dt, n, time_scale)
    last_step = int(np.ceil(t_max / dt)) + 1
    assert last_step // every + 1 <= max_frames  # frames at steps 0, every, ... fit
    assert every * dt >= 0.02 * time_scale - dt / 2  # never finer than FRAME_INTERVAL
    assert max_frames * n <= 1.01 * FRAME_VALUES + 3 * n  # memory bound
