"""VTK output for ParaView: spheres, dominoes as oriented boxes, contact forces as lines.

A :class:`VtkSeries` writes one ``.vtu`` file per frame and per kind of object
(``spheres_00012.vtu``, ``dominoes_00012.vtu``, ``contacts_00012.vtu``) and a
``.pvd`` collection per kind that ParaView opens as a time series. The ``.pvd``
files are rewritten (atomically) after every frame, so a killed run leaves a
readable series. The input is generic (:class:`SceneFrame`): any engine fills it.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np

from dominowave.io.atomic import atomic_path, ensure_writable_dir, write_text
from dominowave.io.trajectory import ChainTrajectory, SphereTrajectory

__all__ = ["SceneFrame", "VtkSeries", "domino_boxes", "write_result_vtk", "write_trajectory_vtk"]


@dataclass
class SceneFrame:
    """What one VTK frame shows (every part optional). SI units.

    sphere_centres (P, 3) [m], sphere_radii (P,) [m], sphere_velocities (P, 3) [m/s],
    clump_ids (P,) int (-1: free sphere);
    box_corners (B, 8, 3) [m] -- hexahedra in VTK order (a face 0-3, the opposite
    face 4-7, corner 4 opposite 0), box_data: name -> (B,) per-box values;
    contact_segments (C, 2, 3) [m] -- the two centres of each contact,
    contact_forces (C, 3) [N] -- force on the first body.
    """

    time: float
    sphere_centres: np.ndarray | None = None
    sphere_radii: np.ndarray | None = None
    sphere_velocities: np.ndarray | None = None
    clump_ids: np.ndarray | None = None
    box_corners: np.ndarray | None = None
    box_data: dict[str, np.ndarray] | None = None
    contact_segments: np.ndarray | None = None
    contact_forces: np.ndarray | None = None


def domino_boxes(traj: ChainTrajectory, frame: int, width: float) -> np.ndarray:
    """(N, 8, 3) box corners of the dominoes of ``traj`` at ``frame``.

    The side view lies in the x-z plane; boxes are extruded ``width`` [m] along y.
    """
    xz = traj.corners(frame)  # (N, 4, 2)
    n = xz.shape[0]
    out = np.empty((n, 8, 3))
    for side, y in enumerate((-width / 2, width / 2)):
        out[:, 4 * side : 4 * side + 4, 0] = xz[:, :, 0]
        out[:, 4 * side : 4 * side + 4, 1] = y
        out[:, 4 * side : 4 * side + 4, 2] = xz[:, :, 1]
    return out


class VtkSeries:
    """Write :class:`SceneFrame` s to ``folder`` as numbered .vtu files plus .pvd series."""

    KINDS = ("spheres", "dominoes", "contacts")

    def __init__(self, folder: str | Path):
        self.folder = ensure_writable_dir(Path(folder))
        self.entries: dict[str, list[tuple[float, str]]] = {k: [] for k in self.KINDS}
        self.count = 0

    def write(self, frame: SceneFrame) -> None:
        """Write one frame (each present part to its own .vtu) and update the .pvd files."""
        import meshio

        index = self.count
        parts = {}
        if frame.sphere_centres is not None:
            centres = np.asarray(frame.sphere_centres, dtype=float)
            p = centres.shape[0]
            point_data = {"radius": np.asarray(frame.sphere_radii, dtype=float)}
            if frame.sphere_velocities is not None:
                point_data["velocity"] = np.asarray(frame.sphere_velocities, dtype=float)
            ids = frame.clump_ids if frame.clump_ids is not None else np.full(p, -1)
            point_data["clump_id"] = np.asarray(ids, dtype=np.int32)
            cells = [("vertex", np.arange(p).reshape(-1, 1))]
            parts["spheres"] = meshio.Mesh(centres, cells, point_data=point_data)
        if frame.box_corners is not None:
            corners = np.asarray(frame.box_corners, dtype=float)
            b = corners.shape[0]
            cells = [("hexahedron", np.arange(8 * b).reshape(b, 8))]
            cell_data = {"domino": [np.arange(1, b + 1, dtype=np.int32)]}
            for name, values in (frame.box_data or {}).items():
                cell_data[name] = [np.asarray(values, dtype=float)]
            parts["dominoes"] = meshio.Mesh(corners.reshape(-1, 3), cells, cell_data=cell_data)
        if frame.contact_segments is not None:
            seg = np.asarray(frame.contact_segments, dtype=float)
            c = seg.shape[0]
            force = np.asarray(frame.contact_forces, dtype=float).reshape(c, 3)
            cells = [("line", np.arange(2 * c).reshape(c, 2))]
            cell_data = {"force": [force], "force_magnitude": [np.linalg.norm(force, axis=1)]}
            parts["contacts"] = meshio.Mesh(seg.reshape(-1, 3), cells, cell_data=cell_data)
        for kind, mesh in parts.items():
            name = f"{kind}_{index:05d}.vtu"
            with atomic_path(self.folder / name) as tmp:
                meshio.write(tmp, mesh, file_format="vtu")
            self.entries[kind].append((float(frame.time), name))
            self._write_pvd(kind)
        self.count += 1

    def _write_pvd(self, kind: str) -> None:
        rows = "\n".join(
            f'    <DataSet timestep="{t!r}" group="" part="0" file={quoteattr(f)}/>'
            for t, f in self.entries[kind]
        )
        write_text(
            self.folder / f"{kind}.pvd",
            '<?xml version="1.0"?>\n<VTKFile type="Collection" version="0.1">\n'
            f"  <Collection>\n{rows}\n  </Collection>\n</VTKFile>\n",
        )


def write_trajectory_vtk(
    folder: str | Path,
    traj: ChainTrajectory | None,
    every: int = 1,
    width: float | None = None,
    spheres: SphereTrajectory | None = None,
) -> int:
    """Write every ``every``-th frame as domino boxes (and spheres); return the frame count.

    ``width`` [m] is the out-of-plane size of the boxes (default: half the height).
    Each box carries its angle [rad] and angular velocity [rad/s]. ``spheres``, if
    given, must share the frames of ``traj`` (or stand alone when ``traj`` is None).
    """
    if every < 1:
        raise ValueError(f"every = {every} is outside the valid range [1, inf)")
    if traj is None and spheres is None:
        raise ValueError("nothing to write to VTK: the run recorded no frames")
    series = VtkSeries(folder)
    times = traj.time if traj is not None else spheres.time
    omega = traj.angular_velocity() if traj is not None else None
    width = (traj.height / 2 if width is None else width) if traj is not None else None
    for f in range(0, times.size, every):
        frame = SceneFrame(time=float(times[f]))
        if traj is not None:
            frame.box_corners = domino_boxes(traj, f, width)
            frame.box_data = {"angle": traj.angle[f], "omega": omega[f]}
        if spheres is not None:
            frame.sphere_centres = spheres.centres[f]
            frame.sphere_radii = spheres.radii
            frame.clump_ids = spheres.clump_ids
            if spheres.velocities is not None:
                frame.sphere_velocities = spheres.velocities[f]
            # meshio cannot write a mesh of zero line cells: frames without contacts
            # (always frame 0) get no contacts file entry.
            if spheres.contact_segments and len(spheres.contact_segments[f]):
                frame.contact_segments = spheres.contact_segments[f]
                frame.contact_forces = spheres.contact_forces[f]
        series.write(frame)
    return series.count


def write_result_vtk(folder: str | Path, result, every: int) -> int:
    """VTK frames of a :class:`~dominowave.io.results.RunResult` (trajectory and spheres)."""
    return write_trajectory_vtk(folder, result.trajectory, every, spheres=result.spheres)
