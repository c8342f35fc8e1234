"""The ``chain`` scenario: a DEM chain of sphere clumps (dominowave.chain on dominowave.dem).

:class:`dominowave.chain.scenario.DominoChain` builds, pushes, runs and analyses the
chain; this adapter turns its :class:`ChainRun` into result files: the summary
(measured steady speed with its error, the theory beside it), one event row per
domino (``DominoEvents``), the tilt and angular velocity of every domino per frame,
the side-view trajectory for ``animate`` and, when VTK is wanted, every sphere and the
contact forces (:class:`~dominowave.io.trajectory.SphereTrajectory`).

The run is checkpointable: :class:`ChainScenarioStepper` advances
:class:`dominowave.chain.stepper.ChainStepper` in pieces, and :func:`run_chain` drives it
through :func:`dominowave.sweep.longrun.run_stepping` (checkpoints, resume, Ctrl-C, progress).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from dominowave.chain.events import forward_tilt, rotate_vectors
from dominowave.chain.scenario import ChainRun, DominoChain, Push
from dominowave.chain.wave import unsettled_reason
from dominowave.io.models import ChainScenario
from dominowave.io.results import RunResult
from dominowave.io.trajectory import ChainTrajectory, SphereTrajectory
from dominowave.sweep.context import RunContext
from dominowave.sweep.longrun import ScenarioStepper, run_stepping

__all__ = [
    "ChainScenarioStepper",
    "chain_result",
    "chain_trajectory",
    "run_chain",
    "sphere_trajectory",
]


def chain_trajectory(record, radius: float, height: float, thickness: float) -> ChainTrajectory:
    """Side view of a DEM chain record: pivot edge and forward tilt of each domino.

    The pivot (a clump's front bottom sphere, a box's rounded front bottom edge) of
    radius ``radius`` [m] carries the front bottom edge at ``(+R, -R)`` from its centre
    in the domino's frame; its height is kept (bases lift off).
    The tilt is ``chain.events.forward_tilt``, the angular velocity the world y
    component (positive = toppling forward).
    """
    keep = _distinct_frames(record.times)
    tilt = forward_tilt(record)[keep]
    pivot = (record.com + rotate_vectors(record.quat, record.base_offset))[keep]
    base_x = pivot[..., 0] + radius * (np.cos(tilt) - np.sin(tilt))
    base_z = pivot[..., 2] - radius * (np.sin(tilt) + np.cos(tilt))
    return ChainTrajectory(
        time=record.times[keep],
        base_x=base_x,
        angle=tilt,
        height=height,
        thickness=thickness,
        omega=record.angular_velocity[keep, :, 1],
        base_z=base_z,
    )


def _distinct_frames(times: np.ndarray) -> np.ndarray:
    """Mask of frames with a later time than the previous one (the record repeats the
    frame where one engine run ends and the next begins)."""
    return np.concatenate([[True], np.diff(times) > 0])


def contact_lines(contacts, centres: np.ndarray, f: int) -> tuple[np.ndarray, np.ndarray]:
    """Frame ``f`` of ``contacts`` (``dem.ContactFrames``) as force lines.

    ``centres`` (S, 3) [m] the sphere centres of that frame.  Returns segments
    (C, 2, 3) [m] and forces (C, 3) [N] on the first end: for a sphere pair the first
    sphere (``-force``: the recorded force acts on the second), for a wall contact the
    sphere (the recorded force).
    """
    rows = contacts.frame(f)
    first, second = contacts.first[rows], contacts.second[rows]
    force = contacts.force[rows].copy()
    wall = first < 0
    segments = np.empty((first.size, 2, 3))
    segments[:, 0] = np.where(wall[:, None], centres[second], centres[np.maximum(first, 0)])
    segments[:, 1] = np.where(wall[:, None], contacts.point[rows], centres[second])
    force[~wall] *= -1.0
    return segments, force


def sphere_trajectory(chain: DominoChain, record, push: Push, contacts=None) -> SphereTrajectory:
    """Every sphere of the chain at every recorded frame (rigid clumps: from COM and rotation);
    with ``contacts`` (``dem.ContactFrames`` of the same frames) also the force lines."""
    sim, _ = chain.build(push)
    start = np.asarray(sim.sphere_positions(), dtype=float)  # (S, 3) at t = 0
    body = np.asarray(sim.sphere_body)
    offsets = start - record.com[0, body]  # from each clump's centre of mass, frame 0
    arms = rotate_vectors(record.quat[:, body], offsets)  # (F, S, 3)
    centres = record.com[:, body] + arms
    velocities = record.velocity[:, body] + np.cross(record.angular_velocity[:, body], arms)
    radii = np.tile(chain.shape.radii, chain.params.n_dominoes)
    keep = _distinct_frames(record.times)
    if contacts is None:
        return SphereTrajectory(record.times[keep], centres[keep], radii, body, velocities[keep])
    lines = [contact_lines(contacts, centres[f], f) for f in np.flatnonzero(keep)]
    return SphereTrajectory(
        record.times[keep],
        centres[keep],
        radii,
        body,
        velocities[keep],
        contact_segments=tuple(seg for seg, _ in lines),
        contact_forces=tuple(force for _, force in lines),
    )


def run_chain(cfg: ChainScenario, ctx: RunContext | None = None) -> RunResult:
    """Run the DEM chain ``cfg`` and measure its wave (SI units); checkpointable."""
    ctx = ctx or RunContext()
    factory = functools.partial(ChainScenarioStepper, spheres=bool(ctx.vtk_every))
    return run_stepping(cfg, ctx, factory=factory)


class ChainScenarioStepper(ScenarioStepper):
    """The chain run of ``cfg`` in resumable pieces (protocol: :mod:`dominowave.sweep.longrun`).

    Everything but :meth:`result` is that of :class:`dominowave.chain.stepper.ChainStepper`;
    :meth:`result` measures the run so far into a :class:`RunResult` (with every sphere
    per frame if ``spheres``, for VTK).
    """

    def __init__(self, cfg: ChainScenario, spheres: bool = False):
        self.cfg = cfg
        self.spheres = spheres
        if spheres and cfg.shape == "box":
            raise ValueError(
                "vtk_every: VTK output draws the spheres of clump dominoes; shape = 'box'"
                " has none (run box chains without VTK output)"
            )
        self.chain = DominoChain(cfg.params(), **cfg.run_options())
        push = Push(omega=cfg.push_omega) if cfg.push_omega is not None else None
        self.stepper = self.chain.stepper(push, contact_forces=spheres)

    def result(self) -> RunResult:
        run = self.stepper.result(keep_record=True)
        return chain_result(
            self.chain,
            run,
            spheres=self.spheres,
            contacts=self.stepper.contact_frames(),
            fit_from=self.cfg.fit_from,
        )


def chain_result(
    chain: DominoChain,
    run: ChainRun,
    spheres: bool = False,
    contacts=None,
    fit_from: int | None = None,
) -> RunResult:
    """Summary, per-domino events, tilt/omega time series and trajectory of ``run``
    (with ``contacts``, ``dem.ContactFrames`` of its frames, the VTK force lines too).
    ``fit_from = K``: the summary's ``speed_fit_from`` is the front speed fitted from
    domino ``K`` on (``chain.wave.speed_from``; NaN when not asked for)."""
    import xarray as xr

    params = chain.params
    record = run.record
    traj = chain_trajectory(record, params.contact_radius, params.height, params.thickness)
    secondary = run.secondary
    summary = {
        "kind": "chain",
        "d_over_l": params.d_over_l,
        # the paper's per-particle k (eq 24): k_n = k / 2 per contact, a box's two points k / 4
        "stiffness": 2.0 * params.points_per_spring * params.contact_stiffness,
        "stiffness_over_kstar": params.stiffness_over_kstar,
        # contact_kn, material_kn, stiffness_error: of a chain of given materials, the spring it
        # ran with against the material's and the estimated speed error of the softening
        # (chain.fidelity; NaN and 0 without one)
        **run.contact_columns,
        "mass": params.mass,
        "speed": run.wave.speed,
        "speed_err": run.wave.speed_err,
        "speed_settled": bool(run.wave.settled),
        "speed_note": _speed_note(run, chain.max_time),
        "fit_from": -1 if fit_from is None else int(fit_from),
        "speed_fit_from": math.nan if fit_from is None else chain.speed_from(run, fit_from).speed,
        "speed_fit_from_err": (
            math.nan if fit_from is None else chain.speed_from(run, fit_from).speed_err
        ),
        "dominoes_toppled": int(run.wave.reached),
        "speed_theory": run.theory_speed,
        "speed_theory_window": run.theory_window_speed,
        "omega_1": run.omega_1,
        "dt": run.dt,
        "n_steps": run.n_steps,
        "engine_wall_time": run.wall_time,
        "stop_reason": run.stop_reason,
        "secondary_wave": secondary is not None,
        "secondary_overtakes": bool(getattr(secondary, "overtakes", False)),
    }
    events = {"domino": np.arange(1, params.n_dominoes + 1), "position": run.positions}
    table = {k: np.asarray(v, dtype=float) for k, v in run.events.table().items()}
    events["arrival_time"] = table.pop("arrival")  # the column name every scenario uses
    events.update(table)
    timeseries = xr.Dataset(
        {
            "tilt": (("time", "domino"), traj.angle, {"units": "rad"}),
            "omega_y": (("time", "domino"), traj.omega, {"units": "rad/s"}),
            "base_x": (("time", "domino"), traj.base_x, {"units": "m"}),
        },
        coords={"time": ("time", traj.time, {"units": "s"}), "domino": events["domino"]},
    )
    return RunResult(
        summary=summary,
        events=events,
        timeseries=timeseries,
        trajectory=traj,
        may_be_nan=(
            "speed",
            "speed_err",
            "speed_theory_window",
            "speed_fit_from",
            "speed_fit_from_err",
            "material_kn",
        ),
        spheres=sphere_trajectory(chain, record, run.push, contacts) if spheres else None,
    )


def _speed_note(run, max_time: float) -> str:
    """Why the summary's speed is not the whole chain's ('' if nothing to say): the run
    ended at ``max_time`` with the wave on its way (``ChainRun.cut_short``), the wave
    did not settle (``chain.wave.unsettled_reason``), or both."""
    note = unsettled_reason(run.arrival, run.positions)
    if run.cut_short:
        cut = f"the run {run.cut_short_text(max_time)}"
        note = f"{cut}; {note}" if note else cut
    return note
