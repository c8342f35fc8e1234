"""The :class:`Simulation` object: owns the state arrays, runs the compiled loop, grows
its buffers, returns recorded data, saves and restores checkpoints."""

from __future__ import annotations

import copy
import functools
import math
from dataclasses import dataclass, field

import numpy as np

from dominowave import compile_ahead
from dominowave.checks import check_finite, check_format, check_in_range, check_positive
from dominowave.dem import engine
from dominowave.dem.boxes import (
    box_energies,
    box_state,
    boxes_from_state,
    empty_boxes,
)
from dominowave.dem.contact import build_verlet_list, compute_forces, compute_forces_planar
from dominowave.dem.energy import E_TOTAL, ENERGY_NAMES, N_ENERGIES, N_MECHANICAL, energies
from dominowave.dem.engine import Recorder, SceneKind, Settings, time_loop
from dominowave.dem.laws.tangential import SHEAR_CONTACT_POINT
from dominowave.dem.material_pairs import RULE_GIVEN
from dominowave.dem.planar import planar_violation
from dominowave.dem.state import (
    Bodies,
    Material,
    MaterialTable,
    Spheres,
    Walls,
    empty_contacts,
)

__all__ = [
    "ContactEvents",
    "ContactFrames",
    "FrameRows",
    "PairStats",
    "RunResult",
    "Simulation",
    "StopCondition",
]

STOP_REASONS = {
    engine.DONE_STEPS: "n_steps",
    engine.DONE_TIME: "until",
    engine.STOP_NO_ONSET: "no_onset",
    engine.STOP_TOUCHED: "touched",
    engine.STOP_KINETIC: "kinetic",
    engine.STOP_AT_REST: "at_rest",
}

_FRAME_ROWS = {
    "positions": "traj_pos",
    "quaternions": "traj_quat",
    "velocities": "traj_vel",
    "angular_velocities": "traj_omega",
}
"""The fields of :class:`FrameRows` and the recorder's rows they come from
(engine._record_frame)."""

STATE_FORMAT = 7
"""Version of the layout of :meth:`Simulation.get_state` (key ``state_format``).
1 (files without the key): no ``settings.planar``, ``planar_kernels``,
``mats.shear_kinematics``, material-pair tables or Hertz tables, and the stiffness rule
of materials giving k_n as the flag ``mats.given_kn``, and possibly no record of which
boxes were held at the last list build or of the box-sphere list; 2: no sleeping boxes
(``settings.sleep_speed``, ``settings.sleep_time``, ``bodies.calm_since``, the rows of
resting pairs ``boxes.dormant.*``); 1 to 3: one column ``mats.stiffness`` for E or k_n
(by the rule) instead of ``mats.young`` and ``mats.kn``; 1 to 4: sphere contacts
without their rows' ``contacts.point``, ``contacts.normal`` and ``contacts.mult``, and an
idle pair may hold a stale positive overlap; 1 to 5: sphere contacts with a flag
``contacts.active`` (1 while the overlap is positive) and without the record's feature
key ``contacts.key`` (0 for spheres); 1 to 6: the box-sphere rows in a table of their own
(``boxes.sphere_rows.*``, the partner ``j`` the sphere's index); :func:`_upgraded` reads
them all."""


def _upgraded(state: dict, n_materials: int) -> dict:
    """``state`` in the layout of :data:`STATE_FORMAT`: an older state with the values its
    scene had implicitly (format 1: planar kernels allowed, the contact-point shear
    kinematics, the min rule of the pair tables, linear contacts, every box held at the
    last list build -- a run in which one is free builds the list again at its start --
    and no box-sphere list -- every pair a candidate until the next build, the same
    forces; formats 1 and 2: no sleeping, no resting rows put aside; formats 1 to 3: the
    one stiffness column split into E and k_n by the rule; formats 1 to 4: the sphere
    contacts' points and normals, which each step writes before they are read, zero, and
    an idle pair's overlap, which nothing read, not positive; formats 1 to 5: the sphere
    contacts' feature keys zero, their flag ``active`` dropped: a pair touches while its
    overlap is positive; formats 1 to 6: the box-sphere rows appended to the box rows,
    their partner the sphere after the boxes, ``j = n_boxes + sphere``); a state of a
    newer format is refused."""
    version = int(np.asarray(state.get("state_format", 1)))
    if check_format("state_format", version, STATE_FORMAT) == STATE_FORMAT:
        return state
    nm = n_materials
    nb = np.asarray(state["bodies.mass"]).shape[0]
    state = {
        "settings.sleep_speed": np.array(0.0),
        "settings.sleep_time": np.array(0.0),
        "bodies.calm_since": np.full(nb, np.nan),
        "settings.planar": np.array(False),  # (decided at each run)
        "planar_kernels": np.array(True),
        "mats.shear_kinematics": np.array([SHEAR_CONTACT_POINT], np.int64),
        "mats.pair_friction": np.full((nm, nm), np.nan),
        "mats.pair_restitution": np.full((nm, nm), np.nan),
        "mats.poisson": np.full(nm, Material.poisson),
        "mats.hertz_damping": np.zeros((nm, nm)),
        **state,
        "state_format": np.array(STATE_FORMAT),
    }
    if "boxes.body" in state:  # (what a freshly built scene of its boxes has; the row
        # capacity for its spheres is set by boxes_from_state, only the defaults count)
        law = int(np.asarray(state["boxes.normal_law"]).reshape(-1)[0])
        shape = (state[f"boxes.{k}"] for k in ("body", "half", "radius", "material"))
        built = empty_boxes(*shape, law)
        state = {**{f"boxes.{k}": v for k, v in box_state(built).items()}, **state}
    given = np.asarray(state.pop("mats.given_kn", [0])).reshape(-1)
    if given.size and given[0] == 1:
        state["mats.rule"] = np.array([RULE_GIVEN], np.int64)
    if "mats.stiffness" in state:  # (E or k_n, by the rule)
        stiffness = np.asarray(state.pop("mats.stiffness"), float)
        unset = np.full_like(stiffness, np.nan)
        given = int(np.asarray(state["mats.rule"]).reshape(-1)[0]) == RULE_GIVEN
        state["mats.young"], state["mats.kn"] = (unset, stiffness) if given else (stiffness, unset)
    if "contacts.point" not in state:
        overlap = np.asarray(state["contacts.overlap"], float)
        idle = np.asarray(state["contacts.active"]) == 0
        state["contacts.overlap"] = np.where(idle, np.minimum(overlap, 0.0), overlap)
        state["contacts.point"] = np.zeros((overlap.size, 3))
        state["contacts.normal"] = np.zeros((overlap.size, 3))
        state["contacts.mult"] = np.ones(overlap.size)
    if "contacts.key" not in state:
        state.pop("contacts.active", None)
        state["contacts.key"] = np.zeros(np.shape(state["contacts.overlap"])[0], np.int64)
    if "boxes.sphere_rows.n" in state:
        state = _joined_sphere_rows(state)
    return state


def _joined_sphere_rows(state: dict) -> dict:
    """``state`` (formats 1 to 6) with its box-sphere rows ``boxes.sphere_rows.*`` after
    the box rows ``boxes.rows.*``, in one table, as box_forces writes them (the partner
    sphere ``s`` is ``j = n_boxes + s``)."""
    prefix = "boxes.sphere_rows."
    spheres = {k[len(prefix) :]: state[k] for k in state if k.startswith(prefix)}
    state = {k: v for k, v in state.items() if not k.startswith(prefix)}
    n_boxes = np.asarray(state["boxes.body"]).size
    for name, value in spheres.items():
        if name != "n":
            value = np.asarray(value) + n_boxes if name == "j" else np.asarray(value)
            state[f"boxes.rows.{name}"] = np.concatenate((state[f"boxes.rows.{name}"], value))
    state["boxes.rows.n"] = np.asarray(state["boxes.rows.n"]) + np.asarray(spheres["n"])
    return state


@dataclass(frozen=True)
class StopCondition:
    """Stop conditions evaluated inside the compiled loop (any that is not None).

    no_onset_for : stop when no body-body contact has started for this long [s] (counted
        from the last onset, or from the start of the run if none yet).
    touched_body : stop at the first body-body contact onset involving this body.
    kinetic_below : stop when the total kinetic energy is below this [J] (tested every
        ``check_every`` steps).
    at_rest : stop when every body is held (boxes not yet touched, or asleep:
        ``Scene.build``'s ``sleep_speed``), at a trajectory frame if frames are recorded.
        Exact: nothing moves again, so a longer run would only repeat that frame.
    """

    no_onset_for: float | None = None
    touched_body: int | None = None
    kinetic_below: float | None = None
    at_rest: bool = False


@dataclass(frozen=True)
class ContactEvents:
    """Every onset/end of a body-body or body-wall contact, in time order.

    time (E,) [s]; body_i (E,); body_j (E,) (body_i < body_j, or ``-(wall + 1)`` for a
    wall); kind (E,) ``ONSET`` = 1 or ``END`` = 0.
    """

    time: np.ndarray
    body_i: np.ndarray
    body_j: np.ndarray
    kind: np.ndarray


@dataclass(frozen=True)
class ContactFrames:
    """Contact forces at the trajectory frames of one run (``record_contact_forces=True``).

    Flat rows, frame ``f`` owning rows ``start[f]:start[f + 1]`` (start (F + 1,) int64).
    Per row (K,): ``first`` shape id, or ``-(wall + 1)``; ``second`` shape id;
    ``point`` (K, 3) contact point [m] (midway through the overlap); ``force`` (K, 3) [N]
    total contact force (normal elastic + dashpot + tangential) acting on shape
    ``second`` as applied at that step, or, for the rows of resting (held or sleeping)
    boxes put aside, as when they were put aside (``-force`` acts on ``first``).  Shapes are
    numbered spheres first (sphere id), then boxes (box x: ``n_spheres + x``).  Every
    active sphere-sphere and sphere-wall contact, then every box contact point (a planar
    row: the sum of the points it stands for, boxes.box_contact_forces; those of resting
    boxes put aside with the force that holds them); the one-kick end
    impulse of a contact that opened in the last drift (laws.linear.end_impulse) is not a row.
    """

    start: np.ndarray
    first: np.ndarray
    second: np.ndarray
    point: np.ndarray
    force: np.ndarray

    def frame(self, f: int) -> slice:
        """The rows of trajectory frame ``f``."""
        return slice(int(self.start[f]), int(self.start[f + 1]))


@dataclass(frozen=True)
class PairStats:
    """Per body pair (n_bodies, n_bodies), symmetric, cumulative over all runs.

    first_contact, last_separation [s] (nan: never); n_contacts: number of distinct
    contacts; peak_normal_force [N]: largest normal force of one sphere contact or one box
    contact point of the pair (only if ``record_peak_force``).
    """

    first_contact: np.ndarray
    last_separation: np.ndarray
    n_contacts: np.ndarray
    peak_normal_force: np.ndarray


@dataclass(frozen=True)
class FrameRows:
    """The trajectory frames of one run as the engine records them: frame ``f`` has a
    row for each body of ``range(first[f], first[f] + start[f + 1] - start[f])``, its
    rows ``start[f]:start[f + 1]``; the first frame has every body.  A body a frame
    leaves out was held since the frame before it (untouched or asleep: engine.py), so
    it has, to the bit, its state of that frame.  In a chain held until touched a frame
    holds the moving dominoes, not all of them.

    n_bodies: the bodies of a frame; times (F,) [s]; first (F,) int64; start (F + 1,)
    int64; per row (R,): positions (R, 3) [m], quaternions (R, 4) (w, x, y, z),
    velocities (R, 3) [m/s] and angular_velocities (R, 3) [rad/s] (full-step values,
    t_n)."""

    n_bodies: int
    times: np.ndarray
    first: np.ndarray
    start: np.ndarray
    positions: np.ndarray
    quaternions: np.ndarray
    velocities: np.ndarray
    angular_velocities: np.ndarray

    def __post_init__(self):
        if not self.times.size:
            return
        count = self.start[1] - self.start[0]
        if self.first[0] != 0 or count != self.n_bodies:
            raise ValueError(
                f"the first frame has the rows of {count} bodies from body {self.first[0]} "
                f"on; it needs every body, 0 to {self.n_bodies - 1}"
            )

    def frame_and_body(self) -> tuple[np.ndarray, np.ndarray]:
        """``(frame, body)`` (R,) int64 each: the frame and the body of every row."""
        frame = np.repeat(np.arange(self.times.size), np.diff(self.start))
        return frame, self.first[frame] + np.arange(frame.size) - self.start[frame]

    def dense(self, name: str) -> np.ndarray:
        """(F, n_bodies, d) field ``name`` at every frame, of every body: its row of the
        last frame up to it that has one."""
        return np.take(getattr(self, name), self._source, 0)  # (faster than a[source])

    @functools.cached_property
    def _source(self) -> np.ndarray:
        """(F, n_bodies) the row of each body's state at each frame (:func:`carried_rows`),
        found once for every field."""
        return carried_rows(*self.frame_and_body(), self.times.size, self.n_bodies)


def carried_rows(frame, body, n_frames: int, n_bodies: int) -> np.ndarray:
    """(n_frames, n_bodies) int64: the row that holds each body's state at each frame,
    its last row up to that frame, of the rows ``frame`` (R,) (ascending) and ``body``
    (R,); the first frame has a row of every body."""
    source = np.zeros((n_frames, n_bodies), np.int64)
    source[frame, body] = np.arange(frame.size)
    np.maximum.accumulate(source, axis=0, out=source)  # (rows ascend by frame)
    return source


class _DenseFrames:
    """A field of :class:`FrameRows` as dense (F, nb, d) frames of a :class:`RunResult`,
    built from ``result.frames`` on first use and kept."""

    def __set_name__(self, owner, name):
        self.name = name

    def __get__(self, result, owner=None):
        if result is None:
            return self
        value = result.frames.dense(self.name)
        result.__dict__[self.name] = value  # (kept: an attribute of the instance now)
        return value


@dataclass(frozen=True)
class RunResult:
    """What one :meth:`Simulation.run` recorded (frames at full steps t_n).

    ``frames`` holds the trajectory frames as recorded (:class:`FrameRows`); ``times``
    (F,) and the dense ``positions`` (F, nb, 3), ``quaternions`` (F, nb, 4),
    ``velocities`` (F, nb, 3) and ``angular_velocities`` (F, nb, 3) are built from it
    on first use."""

    stop_reason: str
    n_steps: int
    time: float
    frames: FrameRows
    energy_times: np.ndarray  # (G,)
    energy: dict = field(default_factory=dict)  # name -> (G,)
    events: ContactEvents | None = None
    contact_frames: ContactFrames | None = None  # with record_contact_forces=True

    @property
    def times(self) -> np.ndarray:
        """(F,) [s] the time of every frame."""
        return self.frames.times

    positions = _DenseFrames()  # (F, nb, 3) [m] centres of mass
    quaternions = _DenseFrames()  # (F, nb, 4) orientations (w, x, y, z)
    velocities = _DenseFrames()  # (F, nb, 3) [m/s]
    angular_velocities = _DenseFrames()  # (F, nb, 3) [rad/s]


def _symmetric(a, fill):
    out = a.copy()
    lower = np.tril_indices(a.shape[0], -1)
    out[lower] = a.T[lower]
    np.fill_diagonal(out, fill)
    return out


class Simulation:
    """A built scene.  Create with :meth:`dominowave.dem.Scene.build`."""

    def __init__(
        self,
        bodies: Bodies,
        spheres: Spheres,
        walls: Walls,
        mats: MaterialTable,
        *,
        gravity,
        dt,
        critical_dt,
        damping,
        damp_gravity,
        skin,
        record_pairs,
        record_peak_force,
        check_every,
        track_energy=True,
        boxes=None,
        sleep_speed=0.0,
        sleep_time=0.0,
    ):
        self.bodies = bodies
        #: rounded-cuboid bodies and their contact rows (dem/boxes.py)
        self.boxes = empty_boxes() if boxes is None else boxes
        partners = self.boxes.body.size + spheres.body.size
        if self.boxes.body.size and self.boxes.partner_body.size != partners:
            raise ValueError(
                f"boxes.partner_body has {self.boxes.partner_body.size} entries, the scene's"
                f" {self.boxes.body.size} boxes and {spheres.body.size} spheres need"
                f" {partners} (dem.boxes.empty_boxes(sphere_body=...))"
            )
        self.spheres = spheres
        self.walls = walls
        self.mats = mats
        self.critical_dt = float(critical_dt)
        self.settings = Settings(
            gravity=np.asarray(gravity, float),
            dt=dt,
            damping=damping,
            damp_gravity=damp_gravity,
            skin=skin,
            record_pairs=record_pairs,
            record_peak_force=record_peak_force,
            check_every=check_every,
            track_energy=bool(track_energy),
            planar=False,  # decided at each run (_start_run)
            sleep_speed=float(sleep_speed),
            sleep_time=float(sleep_time),
        )
        #: Use the planar kernels when the scene is planar (dem/planar.py).  False forces
        #: the general ones (the same trajectories in every scene compared; planar.py).
        self.planar_kernels = True
        capacity = 8 * spheres.body.shape[0] + 64
        self.contacts = empty_contacts(capacity, n=-1)  # (-1: the list never built)
        self.rec = _empty_recorder(
            bodies.mass.shape[0], walls.point.shape[0], capacity, record_pairs
        )
        if not track_energy:  # not tracked: the dissipated energies and the total are nan
            self.rec.ledger[:] = np.nan
        # on a first run a second process compiles the time loop while the set-up's
        # kernels compile here (compile_ahead); a scene of boxes runs the loop in its
        # set-up (_first_step) and would only wait for it
        self._compiling = None
        if not self.boxes.body.size:
            kind = self.kind._replace(planar=self._next_run_planar())
            self._compiling = compile_ahead.start_compiling(
                engine.__name__, "time_loop", (tuple(kind),), self._loop_args(0, 0.0, np.empty(5))
            )
        self._refresh_energy()

    # ------------------------------------------------------------------ properties
    @property
    def dt(self) -> float:
        """Time step [s]."""
        return self.settings.dt

    @property
    def time(self) -> float:
        """Current time [s]."""
        return float(self.rec.clock[engine.CLOCK_TIME])

    @property
    def n_bodies(self) -> int:
        return int(self.bodies.mass.shape[0])

    @property
    def sphere_body(self) -> np.ndarray:
        """(n_spheres,) owner body of each sphere, in the order added."""
        return self.spheres.body

    @property
    def release_time(self) -> np.ndarray:
        """(n_bodies,) time a held (or sleeping) body was first released [s]; nan: never
        released."""
        return self.bodies.release_time.copy()

    @property
    def pairs(self) -> PairStats:
        """Body-pair statistics (see :class:`PairStats`)."""
        if not self.settings.record_pairs:
            raise ValueError("record_pairs = False: build with record_pairs=True")
        r = self.rec
        return PairStats(
            first_contact=_symmetric(r.first_contact, np.nan),
            last_separation=_symmetric(r.last_separation, np.nan),
            n_contacts=_symmetric(r.n_contacts, 0),
            peak_normal_force=_symmetric(r.peak_force, 0.0),
        )

    def sphere_positions(self) -> np.ndarray:
        """(n_spheres, 3) world centres of the spheres [m]."""
        return self.spheres.pos.copy()

    def positions(self) -> np.ndarray:
        """(n_bodies, 3) centres of mass [m]."""
        return self.bodies.pos.copy()

    def energy(self) -> dict:
        """Energies [J] at the last step done (or the initial state), keyed by ENERGY_NAMES."""
        return dict(zip(ENERGY_NAMES, self.rec.energy_now.tolist(), strict=True))

    def set_velocity(self, body: int, velocity=None, angular_velocity=None):
        """Set a body's linear [m/s] and/or angular [rad/s] velocity (world frame).

        Blocked components are kept (a blocked DOF keeps its velocity, YADE semantics);
        an aspherical clump given a spin about a blocked axis is a ValueError
        (integrate.check_blocked_spin).  Between runs only: the next step's tangential
        increment of the body's existing contacts uses the new velocity instead of the
        one of the last drift, i.e. the shear springs jump by ``(v_new - v_old) dt``
        (negligible unless set on a body in frictional contact).
        """
        from dominowave.dem.integrate import ROT_AXIS, ROT_FREE, ROT_NONE, check_blocked_spin

        check_in_range("body", body, 0, self.n_bodies - 1, lo_inclusive=True, hi_inclusive=True)
        b = self.bodies
        if b.held[body]:
            raise ValueError(f"body {body} is held until touched; it cannot be given a velocity")
        if velocity is not None:
            v = np.asarray(velocity, float)
            check_finite("velocity", v)
            free = b.blocked[body, :3] == 0
            b.vel[body, free] = v[free]
            b.vel_full[body] = b.vel[body]
            b.fresh[body] = 1
        if angular_velocity is not None:
            w = np.asarray(angular_velocity, float)
            check_finite("angular_velocity", w)
            mode = b.rot_mode[body]
            check_blocked_spin(body, w, mode, b.axis[body])
            if mode == ROT_NONE:
                self._refresh_energy()
                return
            if mode == ROT_AXIS:
                w = b.axis[body] * (w @ b.axis[body])
                L = b.axis_inertia[body] * w
            elif mode == ROT_FREE:
                R = b.rot[body]
                L = R @ (b.inertia[body] * (R.T @ w))
            else:
                w = np.where(b.blocked[body, 3:] == 1, b.omega[body], w)
                L = b.inertia[body, 0] * w
            b.omega[body] = w
            b.omega_full[body] = w
            b.angmom[body] = L
            b.angmom_full[body] = L
            b.fresh[body] = 1
        self._refresh_energy()

    def _refresh_energy(self):
        """Energies of the current state into ``rec.energy_now``.

        Before the first step the contacts of initially overlapping bodies are evaluated
        on a copy, so that their elastic energy counts from t = 0 and no state changes:
        a scene with boxes takes them from the time loop's first step
        (:meth:`_first_step`: box_forces is inlined into the loop and has no entry from
        Python; a call of its own from Python would compile it a second time), a scene of
        spheres from the sphere kernel its first step will use (compiled on its own
        before the loop that calls it, which compiles faster than within the loop:
        benchmarks/README.md, "First run"); afterwards the contact state of the last step
        is used.
        """
        contacts, boxes = self.contacts, self.boxes
        spheres = self.kind.spheres
        if self.rec.step[0] == 0:
            if spheres:
                while (
                    build_verlet_list(
                        self.spheres,
                        self.walls,
                        self.bodies,
                        self.mats,
                        contacts,
                        self.settings.skin,
                    )
                    < 0
                ):
                    contacts = _grown_contacts(contacts)
            else:  # (what the list builds do without spheres; the loop of boxes alone
                # compiles neither, engine.SceneKind)
                contacts.n[0] = boxes.n_sphere_cand[0] = 0
                self.bodies.pos_at_build[:] = self.bodies.pos
                self.bodies.quat_at_build[:] = self.bodies.quat
            self.contacts = contacts
            self.rec = self.rec._replace(**_change_list(contacts.i.shape[0]))
            if boxes.body.size:
                first = self._first_step()
                contacts, boxes = first.contacts, first.boxes
            else:
                contacts = copy.deepcopy(contacts)
                (compute_forces_planar if self._next_run_planar() else compute_forces)(
                    copy.deepcopy(self.bodies), self.spheres, self.walls, contacts, self.dt,
                    np.zeros(3), self.rec.changes.copy(), self.rec.change_lag.copy(), True,
                    self.mats.shear_kinematics[0],
                )  # fmt: skip
        energies(self.bodies, contacts, self.settings.gravity, self.rec.ledger, self.rec.energy_now)
        if boxes.body.size:
            box_energies(boxes, self.rec.energy_now)

    def _first_step(self) -> Simulation:
        """A copy of this simulation, at its first step, after that step: its sphere
        contacts and box rows are those the step found in the initial configuration.  The
        step is the time loop's own (no other kernel is compiled for it); the copy
        records nothing (its recorder is a new one, without the pair tables)."""
        first = copy.copy(self)
        for name in ("bodies", "spheres", "contacts", "boxes"):  # (what a step writes)
            setattr(first, name, copy.deepcopy(getattr(self, name)))
        capacity = self.contacts.i.shape[0]
        first.rec = _empty_recorder(self.n_bodies, self.walls.point.shape[0], capacity, False)
        first.rec.clock[engine.CLOCK_TIME] = self.time
        first.settings = self.settings._replace(record_pairs=False, record_peak_force=False)
        first._start_run(0, 0, False)
        first._advance(1, np.inf, first._stop_array(StopCondition()))
        return first

    # ------------------------------------------------------------------ running
    def run(
        self,
        n_steps: int | None = None,
        until: float | None = None,
        stop: StopCondition | None = None,
        *,
        trajectory_every: int = 0,
        energy_every: int = 0,
        record_contact_forces: bool = False,
    ) -> RunResult:
        """Advance the simulation in compiled code; see the module docstring of engine.py.

        Parameters
        ----------
        n_steps : at most this many steps.
        until : stop when the time reaches this value [s].
        stop : compiled stop conditions (:class:`StopCondition`).
        trajectory_every, energy_every : record a frame every this many steps (0 = never).
        record_contact_forces : also record every active contact's force at each
            trajectory frame (``RunResult.contact_frames``, :class:`ContactFrames`).
        """
        stop = stop or StopCondition()
        if n_steps is None and until is None and stop == StopCondition():
            raise ValueError("run needs n_steps, until or a stop condition")
        if n_steps is None and until is None and stop == StopCondition(at_rest=True):
            raise ValueError(
                "run with only stop=StopCondition(at_rest=True) needs n_steps or until: a"
                " scene need never come to rest"
            )
        if n_steps is not None:
            check_in_range("n_steps", n_steps, 0, math.inf, lo_inclusive=True)
        if until is not None:
            check_finite("until", until)
        check_in_range("trajectory_every", trajectory_every, 0, math.inf, lo_inclusive=True)
        check_in_range("energy_every", energy_every, 0, math.inf, lo_inclusive=True)
        needs_pairs = stop.no_onset_for is not None or stop.touched_body is not None
        if needs_pairs and not self.settings.record_pairs:
            raise ValueError("stop conditions on contacts need record_pairs=True at build")
        if stop.no_onset_for is not None:
            check_positive("no_onset_for", stop.no_onset_for)
        if stop.touched_body is not None:
            check_in_range(
                "touched_body",
                stop.touched_body,
                0,
                self.n_bodies - 1,
                lo_inclusive=True,
                hi_inclusive=True,
            )
        if stop.kinetic_below is not None:
            check_positive("kinetic_below", stop.kinetic_below)
        stop_array = self._stop_array(stop)
        remaining = np.iinfo(np.int64).max if n_steps is None else int(n_steps)
        t_end = np.inf if until is None else float(until)
        self._start_run(trajectory_every, energy_every, record_contact_forces)
        code, done = self._advance(remaining, t_end, stop_array)
        if code >= engine.ABORT_NAN:
            self._abort(code)
        return self._result(STOP_REASONS[code], done)

    def _stop_array(self, stop: StopCondition) -> np.ndarray:
        """``stop`` as the time loop reads it (entries engine.STOP_ARG_*), the run starting
        now."""
        stop_array = np.empty(5)
        stop_array[engine.STOP_ARG_QUIET] = (
            np.inf if stop.no_onset_for is None else stop.no_onset_for
        )
        stop_array[engine.STOP_ARG_TOUCHED_BODY] = (
            -1 if stop.touched_body is None else stop.touched_body
        )
        stop_array[engine.STOP_ARG_KINETIC_BELOW] = (
            -1.0 if stop.kinetic_below is None else stop.kinetic_below
        )
        stop_array[engine.STOP_ARG_RUN_START] = self.time
        stop_array[engine.STOP_ARG_AT_REST] = float(stop.at_rest)
        return stop_array

    def _advance(self, n_steps, t_end, stop_array):
        """Run the time loop of the scene's kind (engine.time_loop) for up to ``n_steps``
        steps, to ``t_end`` [s] or a stop condition (``stop_array``, engine.STOP_ARG_*),
        growing a full buffer and going on; returns ``(code, steps done)`` with a code
        of engine.DONE_*, STOP_* or ABORT_*."""
        if self._compiling is not None:  # the loop compiled by a second process
            if self._compiling.factory_args == (tuple(self.kind),):
                compile_ahead.wait(self._compiling)
            else:  # (planar_kernels changed since the build: it compiles another loop)
                compile_ahead.stop(self._compiling)
            self._compiling = None
        run_loop = time_loop(self.kind)
        done_total = 0
        while True:
            code, done = run_loop(*self._loop_args(n_steps - done_total, t_end, stop_array))
            done_total += done  # (the loop places every sphere before it returns)
            if not engine.GROW_CONTACTS <= code < engine.ABORT_NAN:
                return code, done_total
            self._grow(code)

    def _loop_args(self, n_steps, t_end, stop_array) -> tuple:
        """The arguments of the time loop (engine.run_loop) for a run of up to ``n_steps``
        steps, to ``t_end`` [s] or ``stop_array`` (engine.STOP_ARG_*)."""
        return (
            self.bodies,
            self.spheres,
            self.walls,
            self.mats,
            self.contacts,
            self.settings,
            self.rec,
            n_steps,
            t_end,
            stop_array,
            np.empty((2, 3)),  # scratch vectors of the loop
            self.boxes,
        )

    @property
    def kind(self) -> SceneKind:
        """What the scene holds, which decides the kernels of its time loop
        (engine.time_loop): planar kernels (as decided at the start of the last run), box
        contacts, sphere contacts."""
        return SceneKind(
            planar=self.settings.planar,
            boxes=self.boxes.body.size > 0,
            spheres=self.spheres.body.size > 0,
        )

    @property
    def planar(self) -> bool:
        """True if the scene is planar now (dem/planar.py: every body moves in one xz
        plane); the next run then uses the planar kernels, unless ``planar_kernels`` is
        False."""
        if planar_violation(self.bodies, self.spheres, self.walls) is not None:
            return False
        # a box's axis 1 along y: its axes 0 and 2 span the plane (shapes/rectangle.py)
        # (to round-off, as planar.IN_PLANE_TOLERANCE)
        return bool(np.all(np.abs(self.bodies.rot[self.boxes.body, 1, 1]) >= 1.0 - 1e-13))

    def _next_run_planar(self) -> bool:
        """Whether a run starting now uses the planar kernels (:attr:`planar` and
        :attr:`planar_kernels`)."""
        return self.planar_kernels and self.planar

    def _start_run(self, trajectory_every, energy_every, record_contact_forces):
        self.settings = self.settings._replace(planar=self._next_run_planar())
        r = self.rec
        r.energy_ref[:] = r.energy_now
        scale = engine.active_energy(r.energy_now, self.settings.track_energy)
        r.clock[engine.CLOCK_ENERGY_SCALE] = max(scale, 1e-300)
        r.touched[:] = 0
        r.ev_n[0] = 0
        r.traj_every[0] = trajectory_every
        r.traj_n[0] = 0
        r.traj_span[:] = 0, self.n_bodies  # (the first frame has every body)
        r.energy_every[0] = energy_every
        r.energy_n[0] = 0
        r.cf_on[0] = 1 if record_contact_forces else 0
        r.cf_n[0] = 0

    def _abort(self, code):
        if code == engine.ABORT_NAN:
            cause = "a position or velocity became NaN/inf"
        else:
            now = self.rec.energy_now[:N_MECHANICAL].sum()
            ref = self.rec.energy_ref[:N_MECHANICAL].sum()
            if self.settings.track_energy:
                e = self.energy()
                dissipated = sum(e[name] for name in ENERGY_NAMES if name.startswith("dissip"))
                cause = (
                    f"the energy balance broke down (the mechanical energy went from "
                    f"{ref:.6g} J to {now:.6g} J, the energy dissipated is "
                    f"{dissipated:.6g} J, the total {e['total']:.6g} J against "
                    f"{self.rec.energy_ref[E_TOTAL]:.6g} J at the start of the run)"
                )
            else:
                cause = (
                    f"the mechanical energy grew from {ref:.6g} J to {now:.6g} J (without "
                    "energy tracking; every dissipative force can only lower it)"
                )
        raise RuntimeError(
            f"DEM run aborted at t = {self.time:.6g} s: {cause}. Likely cause: the time step "
            f"dt = {self.dt:.6g} s is too large for the contact stiffness (critical estimate "
            f"{self.critical_dt:.6g} s) or bodies started deeply interpenetrated."
        )

    def _grow(self, code):
        r = self.rec
        if code == engine.GROW_BOX_CANDIDATES:
            boxes = self.boxes
            if boxes.n_cand[0] < 0:  # (build_box_candidates)
                size = 2 * boxes.cand.shape[0]
                boxes = boxes._replace(
                    cand=np.zeros(size, np.int64),
                    rev=np.zeros(size, np.int64),
                    visit=np.zeros(size, np.int64),
                )
            if boxes.n_sphere_cand[0] < 0:  # (box_sphere.build_box_sphere_candidates)
                boxes = boxes._replace(
                    sphere_cand=np.zeros(2 * boxes.sphere_cand.shape[0], np.int64)
                )
            self.boxes = boxes
        elif code == engine.GROW_CONTACTS:
            self.contacts = _grown_contacts(self.contacts)
            self.rec = r._replace(**_change_list(self.contacts.i.shape[0]))
        elif code == engine.GROW_EVENTS:
            room = self.contacts.i.shape[0] + self.boxes.changes.shape[0]  # (engine.run_loop)
            need = r.ev_n[0] + 2 * room
            self.rec = r._replace(
                **{
                    k: _grow_rows(getattr(r, k), need)
                    for k in ("ev_time", "ev_i", "ev_j", "ev_kind")
                }
            )
        elif code == engine.GROW_TRAJECTORY:  # (room for a frame of every body)
            need = 2 * r.traj_t.shape[0] + 16
            rows = 2 * r.traj_pos.shape[0] + self.n_bodies
            self.rec = r._replace(
                **{k: _grow_rows(getattr(r, k), need) for k in ("traj_t", "traj_first")},
                traj_start=_grow_rows(r.traj_start, need + 1),
                cf_start=_grow_rows(r.cf_start, need),
                **{k: _grow_rows(getattr(r, k), rows) for k in _FRAME_ROWS.values()},
            )
        elif code == engine.GROW_ENERGY:
            need = 2 * r.energy_t.shape[0] + 16
            self.rec = r._replace(
                **{k: _grow_rows(getattr(r, k), need) for k in ("energy_t", "energy_val")}
            )
        elif code == engine.GROW_CONTACT_FORCES:
            need = 2 * r.cf_first.shape[0] + self.contacts.i.shape[0]
            need += self.boxes.rows.i.shape[0] + self.boxes.dormant.i.shape[0]
            self.rec = r._replace(
                **{
                    k: _grow_rows(getattr(r, k), need)
                    for k in ("cf_first", "cf_second", "cf_point", "cf_force")
                }
            )
        else:  # pragma: no cover - defensive
            raise RuntimeError(f"unknown return code {code} of run_loop")

    def _result(self, reason, n_steps):
        r = self.rec
        f = int(r.traj_n[0])
        g = int(r.energy_n[0])
        e = int(r.ev_n[0])
        events = None
        if self.settings.record_pairs:
            events = ContactEvents(
                time=r.ev_time[:e].copy(),
                body_i=r.ev_i[:e].copy(),
                body_j=r.ev_j[:e].copy(),
                kind=r.ev_kind[:e].copy(),
            )
        return RunResult(
            stop_reason=reason,
            n_steps=n_steps,
            time=self.time,
            frames=FrameRows(
                n_bodies=self.n_bodies,
                times=r.traj_t[:f].copy(),
                first=r.traj_first[:f].copy(),
                start=r.traj_start[: f + 1].copy(),
                **{k: getattr(r, v)[: r.traj_start[f]].copy() for k, v in _FRAME_ROWS.items()},
            ),
            energy_times=r.energy_t[:g].copy(),
            energy={name: r.energy_val[:g, k].copy() for k, name in enumerate(ENERGY_NAMES)},
            events=events,
            contact_frames=self._contact_frames(f),
        )

    def _contact_frames(self, n_frames):
        r = self.rec
        if not r.cf_on[0]:
            return None
        k = int(r.cf_n[0])
        return ContactFrames(
            start=np.append(r.cf_start[:n_frames], k),
            first=r.cf_first[:k].copy(),
            second=r.cf_second[:k].copy(),
            point=r.cf_point[:k].copy(),
            force=r.cf_force[:k].copy(),
        )

    # ------------------------------------------------------------------ checkpoints
    _PER_RUN = (
        "changes",
        "change_lag",
        "ev_time",
        "ev_i",
        "ev_j",
        "ev_kind",
        "traj_t",
        "traj_first",
        "traj_start",
        "traj_span",
        *_FRAME_ROWS.values(),
        "cf_on",
        "cf_n",
        "cf_start",
        "cf_first",
        "cf_second",
        "cf_point",
        "cf_force",
        "energy_t",
        "energy_val",
    )

    def get_state(self) -> dict:
        """All state needed to resume bit-identically, as a flat dict of NumPy arrays."""
        out = {
            "state_format": np.array(STATE_FORMAT),
            "critical_dt": np.array(self.critical_dt),
            "planar_kernels": np.array(self.planar_kernels),
        }
        for prefix, tup in self._groups().items():
            for name, value in tup._asdict().items():
                if prefix == "rec" and name in self._PER_RUN:
                    continue
                out[f"{prefix}.{name}"] = np.array(value, copy=True)
        if self.boxes.body.size:  # (a scene without boxes has no box arrays)
            out.update({f"boxes.{k}": v for k, v in box_state(self.boxes).items()})
        return out

    def set_state(self, state: dict):
        """Restore a state from :meth:`get_state` (the scene layout must match)."""
        state = _upgraded(state, self.mats.friction.shape[0])
        groups = self._groups()
        new = {}
        for prefix, tup in groups.items():
            fields = {}
            for name, value in tup._asdict().items():
                key = f"{prefix}.{name}"
                if key in state:
                    arr = np.array(state[key], copy=True)
                    if isinstance(value, np.ndarray):
                        if prefix != "contacts" and arr.shape != value.shape:
                            raise ValueError(
                                f"state[{key!r}] has shape {arr.shape}, the scene needs "
                                f"{value.shape}"
                            )
                        arr = arr.astype(value.dtype)
                    else:  # a scalar setting (float, bool, int)
                        arr = type(value)(arr)
                    fields[name] = arr
                elif not (prefix == "rec" and name in self._PER_RUN):
                    raise ValueError(f"state is missing {key!r}")
            new[prefix] = tup._replace(**fields)
        capacity = new["contacts"].i.shape[0]
        new["rec"] = new["rec"]._replace(**_change_list(capacity))
        self.bodies, self.spheres, self.walls = new["bodies"], new["spheres"], new["walls"]
        self.mats, self.contacts, self.settings = new["mats"], new["contacts"], new["settings"]
        self.rec = new["rec"]
        self.boxes = _restored_boxes(self.boxes, state, self.spheres.body)
        self.critical_dt = float(state["critical_dt"])
        self.planar_kernels = bool(state["planar_kernels"])

    def save(self, path):
        """Write :meth:`get_state` to an ``.npz`` file."""
        np.savez(path, **self.get_state())

    @classmethod
    def load(cls, path) -> Simulation:
        """A Simulation restored from :meth:`save` output."""
        with np.load(path) as data:
            state = {k: data[k] for k in data.files}
        return cls.from_state(state)

    @classmethod
    def from_state(cls, state: dict) -> Simulation:
        """A Simulation restored from a :meth:`get_state` dict."""
        state = _upgraded(state, np.shape(state.get("mats.friction", ()))[0])

        def group(prefix, kind):
            missing = [n for n in kind._fields if f"{prefix}.{n}" not in state]
            if missing:
                raise ValueError(f"state is missing {prefix}.{missing[0]}")
            return kind(**{n: np.array(state[f"{prefix}.{n}"]) for n in kind._fields})

        s = group("settings", Settings)
        settings = {k: (v.item() if np.ndim(v) == 0 else v) for k, v in s._asdict().items()}
        del settings["planar"]  # (decided at each run)
        spheres = group("spheres", Spheres)
        sim = cls(
            group("bodies", Bodies),
            spheres,
            group("walls", Walls),
            group("mats", MaterialTable),
            critical_dt=float(state["critical_dt"]),
            **settings,
            boxes=_restored_boxes(empty_boxes(), state, spheres.body),
        )
        sim.set_state(state)
        return sim

    def _groups(self):
        return {
            "bodies": self.bodies,
            "spheres": self.spheres,
            "walls": self.walls,
            "mats": self.mats,
            "contacts": self.contacts,
            "settings": self.settings,
            "rec": self.rec,
        }


def _restored_boxes(boxes, state, sphere_body):
    """The box state of ``state`` (keys ``boxes.*``, dem.boxes.box_state) for a scene whose
    boxes are ``boxes`` and whose spheres belong to the bodies ``sphere_body`` (ns,); a
    state without boxes fits a scene without boxes only."""
    saved = {k[6:]: v for k, v in state.items() if k.startswith("boxes.")}
    if not saved:
        if boxes.body.size:
            raise ValueError("state is missing 'boxes.body' (the scene has boxes)")
        return boxes
    restored = boxes_from_state(saved, sphere_body)
    if boxes.body.size and not (
        np.array_equal(restored.body, boxes.body) and restored.half.shape == boxes.half.shape
    ):
        raise ValueError(
            f"state['boxes.body'] has bodies {restored.body.tolist()}, the scene's boxes are"
            f" bodies {boxes.body.tolist()}"
        )
    return restored


def _grow_rows(a, n):
    out = np.zeros((n, *a.shape[1:]), a.dtype)
    out[: a.shape[0]] = a
    return out


def _grown_contacts(c):
    """``c`` with twice its rows: the used ones copied, the new ones empty."""
    grown = empty_contacts(2 * c.i.shape[0])
    for name, value in c._asdict().items():
        getattr(grown, name)[: value.shape[0]] = value
    return grown


def _change_list(capacity):
    """The recorder's empty list of the sphere contacts that start or end in a step
    (engine.Recorder.changes, change_lag) for a Verlet list of ``capacity`` pairs."""
    return {"changes": np.zeros((capacity, 3), np.int64), "change_lag": np.zeros(capacity)}


def _empty_recorder(nb, nw, capacity, record_pairs):
    npair = nb if record_pairs else 0
    nwall = nw if record_pairs else 0
    return Recorder(
        clock=np.zeros(2),
        ledger=np.zeros(3),
        power=np.zeros(3),
        step=np.zeros(1, np.int64),
        n_rebuilds=np.zeros(1, np.int64),
        last_onset=np.array([-np.inf]),
        touched=np.zeros(nb, np.uint8),
        **_change_list(capacity),
        pair_count=np.zeros((npair, npair), np.int32),
        wall_count=np.zeros((npair, nwall), np.int32),
        first_contact=np.full((npair, npair), np.nan),
        last_separation=np.full((npair, npair), np.nan),
        n_contacts=np.zeros((npair, npair), np.int64),
        peak_force=np.zeros((npair, npair)),
        ev_n=np.zeros(1, np.int64),
        ev_time=np.zeros(0),
        ev_i=np.zeros(0, np.int64),
        ev_j=np.zeros(0, np.int64),
        ev_kind=np.zeros(0, np.int8),
        traj_every=np.zeros(1, np.int64),
        traj_n=np.zeros(1, np.int64),
        traj_t=np.zeros(0),
        traj_first=np.zeros(0, np.int64),
        traj_start=np.zeros(1, np.int64),
        traj_span=np.zeros(2, np.int64),
        traj_pos=np.zeros((0, 3)),
        traj_quat=np.zeros((0, 4)),
        traj_vel=np.zeros((0, 3)),
        traj_omega=np.zeros((0, 3)),
        cf_on=np.zeros(1, np.int64),
        cf_n=np.zeros(1, np.int64),
        cf_start=np.zeros(0, np.int64),
        cf_first=np.zeros(0, np.int64),
        cf_second=np.zeros(0, np.int64),
        cf_point=np.zeros((0, 3)),
        cf_force=np.zeros((0, 3)),
        energy_every=np.zeros(1, np.int64),
        energy_n=np.zeros(1, np.int64),
        energy_t=np.zeros(0),
        energy_val=np.zeros((0, N_ENERGIES)),
        energy_now=np.zeros(N_ENERGIES),
        energy_ref=np.zeros(N_ENERGIES),
    )
