"""Trajectories, animations, VTK and figures."""

from __future__ import annotations

import numpy as np
import pytest

from dominowave import theory
from dominowave.io.animation import animate, frame_times, render_frames
from dominowave.io.models import TheoryScenario
from dominowave.io.trajectory import ChainTrajectory
from dominowave.io.vtk import SceneFrame, VtkSeries, domino_boxes, write_trajectory_vtk
from dominowave.sweep.run_theory import lean_angle, run_theory

L, S = 0.048, 0.0075


@pytest.fixture(scope="module")
def theory_run():
    """A 48 x 7.5 mm, 8 g domino at d = 24 mm."""
    domino = {"height": L, "thickness": S, "mass": 0.008, "d_over_l": 0.024 / L}
    return run_theory(TheoryScenario(n_dominoes=8, n_frames=400, stiffness_ratio=1e4, **domino))


def test_corners_of_an_upright_and_a_flat_domino():
    traj = ChainTrajectory(
        np.array([0.0, 1.0]), np.array([0.1]), np.array([[0.0], [np.pi / 2]]), L, S
    )
    np.testing.assert_allclose(traj.corners(0)[0], [[0.1 - S, 0], [0.1, 0], [0.1, L], [0.1 - S, L]])
    # toppled forward about the pivot: the top lies at x = pivot + l, the back face at z = s
    np.testing.assert_allclose(
        traj.corners(1)[0], [[0.1, S], [0.1, 0], [0.1 + L, 0], [0.1 + L, S]], atol=1e-15
    )


def test_validate_lean_angle_touches_the_next_back_face():
    """The leaning domino's top front corner lies on the next domino's back face."""
    d = 0.02
    for theta_next in np.linspace(0.0, 1.2, 7):
        theta = lean_angle(theta_next, d + S, S, L)
        traj = ChainTrajectory(
            np.array([0.0]), np.array([[0.0, d + S]]), np.array([[theta, theta_next]]), L, S
        )
        c = traj.corners(0)
        top_front = c[0, 2]
        back_bottom, back_top = c[1, 0], c[1, 3]
        edge = back_top - back_bottom
        cross = edge[0] * (top_front - back_bottom)[1] - edge[1] * (top_front - back_bottom)[0]
        assert abs(cross) / np.linalg.norm(edge) < 1e-15
    assert lean_angle(0.0, d + S, S, L) == pytest.approx(np.arcsin(d / L), rel=1e-14)


def test_validate_theory_trajectory_obeys_energy_balance_in_free_fall(theory_run):
    """Between start and strike, omega^2 = Omega_n^2 + 2 g/l (1 - cos theta) (eq 10)."""
    traj, ev = theory_run.trajectory, theory_run.events
    beta = np.arcsin(0.024 / L)
    omega_fd = np.gradient(traj.angle, traj.time, axis=0)
    for n in (2, 4):
        t0, omega_n = ev["start_time"][n], ev["omega"][n]
        t_hit = t0 + theory.fall_time(omega_n, beta, L, 9.81)
        inside = (traj.time > t0 + 0.2 * (t_hit - t0)) & (traj.time < t_hit - 0.2 * (t_hit - t0))
        assert inside.sum() >= 5
        theta = traj.angle[inside, n]
        expected = np.sqrt(omega_n**2 + 2 * 9.81 / L * (1 - np.cos(theta)))
        np.testing.assert_allclose(omega_fd[inside, n], expected, rtol=2e-3)


def test_theory_trajectory_ends_with_the_chain_down(theory_run):
    traj = theory_run.trajectory
    assert traj.angle[0].max() == 0.0
    final = traj.angle[-1]
    # resting dominoes lean at cos(theta) = s / (d + s); the last one lies flat
    assert final[-1] == pytest.approx(np.pi / 2, abs=1e-6)
    assert final[0] == pytest.approx(np.arccos(S / (0.024 + S)), abs=2e-3)


def test_frame_times_follow_fps_and_slowdown(theory_run):
    traj = theory_run.trajectory
    times = frame_times(traj, fps=20, slowdown=10.0)
    np.testing.assert_allclose(np.diff(times), 1 / 200)
    assert times[-1] <= traj.time[-1] < times[-1] + 1 / 200
    with pytest.raises(ValueError, match="more than"):
        frame_times(traj, fps=25, slowdown=1e6)


def test_rendered_frames_show_the_wave_moving(theory_run):
    traj = theory_run.trajectory
    times = np.linspace(traj.time[0], traj.time[-1], 3)
    first, middle, last = list(render_frames(traj, times, width_px=480))
    assert first.shape == middle.shape == last.shape and first.shape[1] == 480
    assert first.shape[0] % 16 == 0
    assert (first != middle).any(axis=-1).mean() > 0.01
    assert (middle != last).any(axis=-1).mean() > 0.01


@pytest.mark.parametrize("suffix", [".gif", ".mp4"])
def test_animation_file_has_the_frames(theory_run, tmp_path, suffix):
    import imageio.v2 as imageio

    out = tmp_path / f"chain{suffix}"
    n = animate(theory_run.trajectory, out, fps=10, slowdown=2.0)
    frames = [frame for frame in imageio.get_reader(out)]
    assert len(frames) == n == frame_times(theory_run.trajectory, 10, 2.0).size
    assert [p.name for p in tmp_path.iterdir()] == [out.name]


def test_vtk_files_read_back(tmp_path):
    import meshio

    rng = np.random.default_rng(0)
    frame = SceneFrame(
        time=0.5,
        sphere_centres=rng.normal(size=(6, 3)),
        sphere_radii=np.full(6, 0.01),
        sphere_velocities=rng.normal(size=(6, 3)),
        clump_ids=np.array([0, 0, 0, 1, 1, -1]),
        contact_segments=rng.normal(size=(2, 2, 3)),
        contact_forces=np.array([[1.0, 0, 0], [0, 3.0, 4.0]]),
    )
    series = VtkSeries(tmp_path)
    series.write(frame)
    spheres = meshio.read(tmp_path / "spheres_00000.vtu")
    np.testing.assert_array_equal(spheres.points, frame.sphere_centres)
    np.testing.assert_array_equal(spheres.point_data["clump_id"], frame.clump_ids)
    np.testing.assert_array_equal(spheres.point_data["velocity"], frame.sphere_velocities)
    contacts = meshio.read(tmp_path / "contacts_00000.vtu")
    np.testing.assert_array_equal(contacts.cell_data["force_magnitude"][0], [1.0, 5.0])
    assert 'timestep="0.5"' in (tmp_path / "spheres.pvd").read_text()


def test_validate_domino_boxes_have_the_domino_volume(theory_run, tmp_path):
    """Each hexahedron's volume (divergence theorem, via meshio's cell volumes) is l s w."""
    import meshio

    traj = theory_run.trajectory
    n = write_trajectory_vtk(tmp_path, traj, every=100, width=0.024)
    assert n == len(range(0, traj.n_frames, 100))
    mesh = meshio.read(tmp_path / "dominoes_00002.vtu")
    boxes = mesh.points.reshape(-1, 8, 3)
    np.testing.assert_array_equal(boxes, domino_boxes(traj, 200, 0.024))
    for box in boxes:  # volume of a parallelepiped from three edges at corner 0
        e = box[[1, 3, 4]] - box[0]
        assert abs(np.linalg.det(e)) == pytest.approx(L * S * 0.024, rel=1e-12)
    np.testing.assert_array_equal(mesh.cell_data["angle"][0], traj.angle[200])
