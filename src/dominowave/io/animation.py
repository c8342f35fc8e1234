"""Movies of a toppling chain: 2D side view, coloured by angular velocity.

``animate(trajectory, "chain.mp4")`` draws every domino of a
:class:`~dominowave.io.trajectory.ChainTrajectory` as its side-view rectangle,
filled with a colour for ``|d angle / dt|``, with a time stamp. The movie runs
``slowdown`` times slower than the simulation (a wave down 30 dominoes takes
about a second). mp4 is written by imageio-ffmpeg, gif by Pillow.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from dominowave.io.atomic import atomic_path
from dominowave.io.trajectory import ChainTrajectory

__all__ = ["animate", "frame_times", "render_frames"]

DEFAULT_MOVIE_SECONDS = 6.0
"""Length of the movie when no slowdown is given [s]."""

MAX_FRAMES = 5000
"""Refuse to draw longer movies (a typo in --slowdown should not run for hours)."""


def frame_times(traj: ChainTrajectory, fps: int, slowdown: float | None) -> np.ndarray:
    """Simulated times [s] of the movie frames: ``fps`` per movie second."""
    duration = traj.time[-1] - traj.time[0]
    if slowdown is None:
        slowdown = DEFAULT_MOVIE_SECONDS / duration if duration > 0 else 1.0
    if not slowdown > 0 or not np.isfinite(slowdown):
        raise ValueError(f"slowdown = {slowdown} is outside the valid range (0, inf)")
    n = int(np.floor(duration * slowdown * fps)) + 1
    if n > MAX_FRAMES:
        raise ValueError(
            f"slowdown = {slowdown:.6g} gives {n} frames, more than {MAX_FRAMES}; lower it"
        )
    return traj.time[0] + np.arange(max(n, 2)) / (slowdown * fps)


def _interp(traj: ChainTrajectory, t: float, field: np.ndarray) -> np.ndarray:
    """(N,) values of ``field`` (F, N) at time ``t``, linear between stored frames."""
    i = int(np.clip(np.searchsorted(traj.time, t) - 1, 0, traj.n_frames - 2))
    w = np.clip((t - traj.time[i]) / (traj.time[i + 1] - traj.time[i]), 0.0, 1.0)
    return (1 - w) * field[i] + w * field[i + 1]


def render_frames(traj: ChainTrajectory, times: np.ndarray, width_px: int = 960):
    """Yield (H, W, 3) uint8 images of the chain at ``times`` [s]."""
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.cm import ScalarMappable
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    if traj.n_frames < 2:
        raise ValueError("a trajectory needs at least 2 frames to animate")
    omega = np.abs(traj.angular_velocity())
    vmax = float(np.max(omega)) or 1.0
    norm, cmap = Normalize(0.0, vmax), colormaps["viridis"]
    l = traj.height
    x_lo = float(np.min(traj.base_x)) - 0.1 * l - traj.thickness
    x_hi = float(np.max(traj.base_x)) + 1.1 * l
    # axes of the data's aspect ratio plus strips for the axis labels (bottom) and the
    # time stamp and colour bar (top); sizes divisible by 16 so mp4 needs no rescaling
    width_px = 16 * max(20, round(width_px / 16))
    axes_h = max(80.0, 0.94 * width_px * 1.3 * l / (x_hi - x_lo))
    y_span = axes_h * (x_hi - x_lo) / (0.94 * width_px)  # equal scales on both axes
    height_px = 16 * round((axes_h + 90.0) / 16)
    fig = Figure(figsize=(width_px / 100, height_px / 100), dpi=100)
    canvas = FigureCanvasAgg(fig)
    ax = fig.add_axes((0.03, 50 / height_px, 0.94, axes_h / height_px))
    cax = fig.add_axes((0.62, (height_px - 26) / height_px, 0.3, 10 / height_px))
    bar = fig.colorbar(ScalarMappable(norm, cmap), cax=cax, orientation="horizontal")
    fig.text(0.61, (height_px - 26) / height_px, "|ω| [rad/s]", ha="right", fontsize=9)
    cax.tick_params(labelsize=7)
    bar.outline.set_linewidth(0.5)
    ax.set_xlim(x_lo, x_hi)
    ax.set_ylim(-0.1 * l, y_span - 0.1 * l)
    ax.axhline(0.0, color="0.3", lw=1)
    ax.set_xlabel("x [m]")
    ax.set_yticks([])
    # Thin rods (s = 0) are zero-area polygons: draw their outline in the |omega|
    # colour, thicker, so the colour stays visible.
    thin = traj.thickness == 0.0
    polys = PolyCollection([], edgecolors="k", linewidths=2.0 if thin else 0.5)
    ax.add_collection(polys)
    stamp = fig.text(0.03, (height_px - 24) / height_px, "", family="monospace")
    for t in times:
        angle = _interp(traj, t, traj.angle)
        base = _interp(traj, t, traj.base_x)
        lift = None if traj.base_z is None else _interp(traj, t, traj.base_z)[None, :]
        snapshot = ChainTrajectory(
            np.array([t]),
            base[None, :],
            angle[None, :],
            traj.height,
            traj.thickness,
            base_z=lift,
        )
        polys.set_verts(list(snapshot.corners(0)))
        colours = cmap(norm(_interp(traj, t, omega)))
        polys.set_facecolors(colours)
        if thin:
            polys.set_edgecolors(colours)
        stamp.set_text(f"t = {t * 1e3:8.2f} ms")
        canvas.draw()
        yield np.asarray(canvas.buffer_rgba())[..., :3].copy()


def animate(
    traj: ChainTrajectory, out: str | Path, fps: int = 25, slowdown: float | None = None
) -> int:
    """Write the movie ``out`` (.mp4 or .gif); return the number of frames.

    The file appears atomically: an interrupted write leaves no broken movie.
    """
    import imageio.v2 as imageio

    out = Path(out)
    suffix = out.suffix.lower()
    if suffix not in {".mp4", ".gif"}:
        raise ValueError(f"--out {out}: the movie must end in .mp4 or .gif")
    if not out.parent.is_dir():
        raise ValueError(f"--out {out}: folder {out.parent} does not exist")
    times = frame_times(traj, fps, slowdown)
    with atomic_path(out) as tmp:
        if suffix == ".mp4":
            writer = imageio.get_writer(
                tmp, format="FFMPEG", fps=fps, codec="libx264", quality=7, macro_block_size=16
            )
        else:
            writer = imageio.get_writer(tmp, format="GIF", duration=1000.0 / fps, loop=0)
        with writer:
            for image in render_frames(traj, times):
                writer.append_data(image)
    return times.size
