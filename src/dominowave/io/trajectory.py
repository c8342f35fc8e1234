"""The generic domino-chain trajectory that animations and plots draw.

Any scenario (theory kinematics, rod model, DEM chain) hands over the same
arrays, so the drawing code knows nothing about how they were computed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from dominowave.checks import check_finite, check_positive

__all__ = ["ChainTrajectory", "SphereTrajectory"]


@dataclass(frozen=True)
class ChainTrajectory:
    """Side view of a toppling chain, frame by frame.

    Attributes
    ----------
    time : (F,) frame times [s], increasing.
    base_x : (F, N) horizontal position of each domino's pivot -- its front bottom
        edge, about which it topples towards +x [m]. Varies in time if bases slide.
    angle : (F, N) inclination from the vertical [rad], positive towards +x.
    height, thickness : domino height l and thickness s [m].
    omega : (F, N) angular velocity [rad/s]; if None it is computed from
        ``angle`` by finite differences (:meth:`angular_velocity`).
    base_z : (F, N) height of the pivot above the floor [m] (None: on the floor), for
        dominoes that lift off or land on others.
    """

    time: np.ndarray
    base_x: np.ndarray
    angle: np.ndarray
    height: float
    thickness: float
    omega: np.ndarray | None = None
    base_z: np.ndarray | None = None

    def __post_init__(self):
        time = np.asarray(self.time, dtype=float)
        angle = np.asarray(self.angle, dtype=float)
        base_x = np.broadcast_to(np.asarray(self.base_x, dtype=float), angle.shape)
        if time.ndim != 1 or angle.ndim != 2 or angle.shape[0] != time.size:
            raise ValueError(
                f"trajectory shapes: time {time.shape}, angle {angle.shape};"
                " expected time (F,) and angle (F, N)"
            )
        if time.size and np.any(np.diff(time) <= 0):
            raise ValueError("trajectory time must be strictly increasing")
        check_finite("trajectory angle", angle)
        check_finite("trajectory base_x", base_x)
        check_positive("height", self.height)
        object.__setattr__(self, "time", time)
        object.__setattr__(self, "angle", angle)
        object.__setattr__(self, "base_x", base_x)
        if self.base_z is not None:
            base_z = np.broadcast_to(np.asarray(self.base_z, dtype=float), angle.shape)
            check_finite("trajectory base_z", base_z)
            object.__setattr__(self, "base_z", base_z)

    @property
    def n_frames(self) -> int:
        return self.time.size

    @property
    def n_dominoes(self) -> int:
        return self.angle.shape[1]

    def angular_velocity(self) -> np.ndarray:
        """(F, N) angular velocity [rad/s]: ``omega`` if given, else d(angle)/dt."""
        if self.omega is not None:
            return np.asarray(self.omega, dtype=float)
        if self.n_frames < 2:
            return np.zeros_like(self.angle)
        return np.gradient(self.angle, self.time, axis=0)

    def corners(self, frame: int) -> np.ndarray:
        """(N, 4, 2) corners (x, z) [m] of each domino's side-view rectangle.

        At rest a domino occupies ``[pivot - s, pivot] x [0, l]``; it is rotated
        about its pivot by ``angle`` (clockwise seen with +x right, +z up).
        """
        s, l = self.thickness, self.height
        local = np.array([[-s, 0.0], [0.0, 0.0], [0.0, l], [-s, l]])
        th = self.angle[frame][:, None]
        c, sn = np.cos(th), np.sin(th)
        x = local[None, :, 0] * c + local[None, :, 1] * sn
        z = -local[None, :, 0] * sn + local[None, :, 1] * c
        lift = 0.0 if self.base_z is None else self.base_z[frame][:, None]
        return np.stack([x + self.base_x[frame][:, None], z + lift], axis=-1)

    def to_dataset(self):
        """As an ``xarray.Dataset`` (dims ``time``, ``domino``)."""
        import xarray as xr

        data = {
            "base_x": (("time", "domino"), self.base_x, {"units": "m"}),
            "angle": (("time", "domino"), self.angle, {"units": "rad"}),
        }
        if self.omega is not None:
            data["omega"] = (("time", "domino"), np.asarray(self.omega), {"units": "rad/s"})
        if self.base_z is not None:
            data["base_z"] = (("time", "domino"), self.base_z, {"units": "m"})
        return xr.Dataset(
            data,
            coords={
                "time": ("time", self.time, {"units": "s"}),
                "domino": np.arange(1, self.n_dominoes + 1),
            },
            attrs={"height": self.height, "thickness": self.thickness},
        )

    @classmethod
    def from_dataset(cls, ds) -> ChainTrajectory:
        """Inverse of :meth:`to_dataset`."""
        return cls(
            time=ds["time"].values,
            base_x=ds["base_x"].values,
            angle=ds["angle"].values,
            height=float(ds.attrs["height"]),
            thickness=float(ds.attrs["thickness"]),
            omega=ds["omega"].values if "omega" in ds else None,
            base_z=ds["base_z"].values if "base_z" in ds else None,
        )


@dataclass(frozen=True)
class SphereTrajectory:
    """The spheres of a DEM run, frame by frame (for VTK).

    time (F,) [s]; centres (F, S, 3) [m]; velocities (F, S, 3) [m/s] or None;
    radii (S,) [m]; clump_ids (S,) int (the body each sphere belongs to).
    Optionally the contact forces as lines, per frame (empty tuples: not recorded):
    contact_segments, a (C, 2, 3) array [m] per frame (sphere centre to sphere centre,
    or sphere centre to the contact point on a wall), and contact_forces, a (C, 3)
    array [N] per frame, the total force on the sphere at the segment's first end.
    """

    time: np.ndarray
    centres: np.ndarray
    radii: np.ndarray
    clump_ids: np.ndarray
    velocities: np.ndarray | None = None
    contact_segments: tuple = ()
    contact_forces: tuple = ()
