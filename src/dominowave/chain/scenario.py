"""A domino chain on the DEM engine: build, push, run, record, measure (paper section 3).

``DominoChain(params).run(push)`` builds the scene of ``chain.build`` in
``dominowave.dem``, pushes domino 0, runs until the wave has died out, and returns
a ``ChainRun`` with the events of every domino (``chain.events``), the wave
measurement (``chain.wave``) and the theory for the same parameters
(``chain.compare``). ``DominoChain(params).ensemble(push, members, seed)`` runs
seeded, slightly perturbed pushes: the chain is chaotic, so a speed is only
reproducible as an ensemble mean with its standard error.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from dominowave import dem
from dominowave.chain.build import (
    ChainParams,
    chain_positions,
    domino_box,
    domino_shape,
    place_domino,
    placement,
    yaw_matrix,
)
from dominowave.chain.compare import (
    effective_domino,
    theory_collision_time,
    theory_first_contacts,
    theory_speed,
)
from dominowave.chain.events import (
    ChainRecord,
    DominoEvents,
    analyse_events,
    critical_tilt,
    merge_contacts,
    neighbour_intervals,
)
from dominowave.chain.fidelity import ContactFidelity, Fidelity, choose_contact
from dominowave.chain.fidelity import steps_per_collision as default_steps_per_collision
from dominowave.chain.stepper import ChainStepper
from dominowave.chain.wave import (
    EnsembleStats,
    SecondaryWave,
    SteadySpeed,
    check_fit_from,
    ensemble_arrival_stats,
    ensemble_stats,
    first_and_second_onsets,
    fit_speed,
    secondary_wave,
    speed_from,
    steady_speed,
)
from dominowave.checks import check_in_range, check_memory, check_nonnegative, check_positive

__all__ = [
    "ChainEnsemble",
    "ChainRun",
    "DominoChain",
    "Push",
    "default_speed_bound",
    "member_placement_seed",
    "member_push_factor",
    "scene_kind",
]


def scene_kind(params: ChainParams) -> dem.SceneKind:
    """What the DEM scene of a chain ``params`` holds, which decides the kernels its time
    loop compiles and runs (``dem.engine.time_loop``): the planar kernels for the 2D
    model, box contacts for boxes, sphere contacts for clumps."""
    boxes = params.shape == "box"
    return dem.SceneKind(planar=params.model == "2d", boxes=boxes, spheres=not boxes)


def member_push_factor(seed: int, member: int, jitter: float) -> float:
    """The push scale of ensemble member ``member``: ``1 + jitter N(0, 1)`` [-].

    The normal draw comes from ``numpy.random.default_rng([seed, member])``, so each
    member is reproducible on its own, whichever process runs it and in which order.
    """
    return 1.0 + jitter * np.random.default_rng([seed, member]).standard_normal()


def member_placement_seed(seed: int, member: int) -> int:
    """The placement seed (``ChainParams.asymmetry_seed``) of ensemble member ``member``
    when each member is set up anew: an integer in ``[0, 2**31)`` drawn from
    ``numpy.random.default_rng([seed, member, 1])`` (a stream apart from the push's)."""
    return int(np.random.default_rng([seed, member, 1]).integers(2**31))


@dataclass(frozen=True)
class Push:
    """How domino 0 is set in motion at ``t = 0``.

    Exactly one of: ``omega`` -- initial angular velocity [rad/s] about the floor
    contact of its pivot (a clump's front base sphere, a box's front bottom edge), a
    rolling start: that contact point is at rest, ``v = omega x (x - x_contact)``;
    ``impulse`` -- a horizontal impulse [N s] at ``height`` [m] above the floor
    (default: the top sphere's centre, or a box's top minus ``s/2``) on the free
    domino. Neither: ``DominoChain`` uses ``omega = sqrt(g / l)``.
    """

    omega: float | None = None
    impulse: float | None = None
    height: float | None = None

    def __post_init__(self):
        if self.omega is not None and self.impulse is not None:
            raise ValueError("give the push as omega or as impulse, not both")
        if self.omega is not None:
            check_positive("omega", self.omega)
        if self.impulse is not None:
            check_positive("impulse", self.impulse)
        if self.height is not None:
            check_positive("height", self.height)

    def scaled(self, factor: float) -> Push:
        """The same push, ``factor`` times as strong (ensemble perturbations)."""
        if self.impulse is not None:
            return Push(impulse=self.impulse * factor, height=self.height)
        if self.omega is None:
            raise ValueError("resolve the default push first (DominoChain.resolve)")
        return Push(omega=self.omega * factor)


@dataclass
class ChainRun:
    """Result of one run (SI units; arrays over dominoes have shape (N,)).

    ``positions`` x of each domino's axis; ``arrival`` first-contact times (the
    wave); ``events`` per-domino events; ``wave`` steady-speed fit; ``secondary``
    the re-contact wave (None if absent); ``omega_1`` the push as an angular
    velocity about the base contact (theory's Omega_1); ``theory_speed`` eq 34
    (clump mapping) and ``theory_arrival`` the transient from ``omega_1``;
    ``theory_window_speed`` the same least-squares fit applied to the theory's
    transient over the dominoes of ``wave`` (NaN if not settled): the like-for-like
    comparison for a finite chain, where the limit may be far;
    ``dt``, ``n_steps``, ``wall_time`` [s], ``stop_reason`` of the engine;
    ``fidelity`` the contact spring of a chain of given materials and its estimated
    error (:mod:`dominowave.chain.fidelity`; None for a chain whose stiffness is a
    parameter of the model).
    """

    params: ChainParams
    push: Push
    positions: np.ndarray
    arrival: np.ndarray
    events: DominoEvents
    wave: SteadySpeed
    secondary: SecondaryWave | None
    omega_1: float
    theory_speed: float
    theory_arrival: np.ndarray
    theory_window_speed: float
    dt: float
    n_steps: int
    wall_time: float
    stop_reason: str
    record: ChainRecord | None = field(default=None, repr=False)
    fidelity: ContactFidelity | None = None

    @property
    def stiffness_error(self) -> float:
        """The estimated relative speed error [1] of a softened contact at this run's
        steady speed (:meth:`ContactFidelity.error_at`); 0 at the material's spring or
        for a chain without a material."""
        if self.fidelity is None:
            return 0.0
        speed = self.wave.speed if self.wave.settled else math.nan
        return self.fidelity.error_at(speed)

    @property
    def theory_window_gap(self) -> float:
        """How far the theory's transient over the fitted dominoes still is from its
        limit: ``theory_window_speed / theory_speed - 1`` [1] (negative: below it, the
        theory's wave still accelerating there); NaN if the wave did not settle."""
        return self.theory_window_speed / self.theory_speed - 1.0

    @property
    def settled_in_transient(self) -> bool:
        """Whether the wave settled, by the data, over dominoes where by the theory it is
        still in its transient: :attr:`theory_window_gap` is larger than twice the fit's
        relative standard error, a change the fit could have resolved.  A short undamped
        chain can show one plateau of its staircase profile (docs/chain.md, "Speed
        jumps") as a settled stretch; a longer chain tells.  Meaningful where the paper's
        theory describes the chain; the wave of real dominoes with a small gap is a
        leaning train (theory.leaning), far from the paper's transient."""
        w = self.wave
        return w.settled and abs(self.theory_window_gap) > 2.0 * w.speed_err / w.speed

    @property
    def contact_columns(self) -> dict[str, float]:
        """The run's contact as the columns of its tables and summary: ``contact_kn``
        the spring it ran with [N/m], ``material_kn`` the material's [N/m] (NaN for a
        chain without a material) and ``stiffness_error`` (:attr:`stiffness_error`, [1])."""
        return {
            "contact_kn": self.params.contact_stiffness,
            "material_kn": math.nan if self.fidelity is None else self.fidelity.material_kn,
            "stiffness_error": self.stiffness_error,
        }

    @property
    def reached_all(self) -> bool:
        """Whether the wave reached the last domino."""
        return bool(np.isfinite(self.arrival[-1]))

    @property
    def cut_short(self) -> bool:
        """Whether the run ended at its ``max_time`` before the wave reached the last
        domino or went quiet (no new contact for the quiet time, which ends a run whose
        wave died): the dominoes after :attr:`front` may still have fallen."""
        return self.stop_reason == "until" and not self.reached_all

    def cut_short_text(self, max_time: float) -> str:
        """How a :attr:`cut_short` run ended, in words: "ended at max_time = 1.2 s with
        the wave at domino 17 of 29" (``max_time`` [s], the run's limit).  The command
        line and a study's ``speed_note`` say it so."""
        return (
            f"ended at max_time = {max_time:.4g} s with the wave at domino {self.front}"
            f" of {self.params.n_dominoes - 1}"
        )

    @property
    def front(self) -> int:
        """The highest domino the wave reached (domino 0, pushed, counts)."""
        return int(np.flatnonzero(np.isfinite(self.arrival)).max())


@dataclass
class ChainEnsemble:
    """Ensemble of perturbed runs: speed statistics and per-domino arrival statistics.

    ``speed`` is over the members' ``fits``: each run's settled-region fit
    (``run.wave``, ``fit_from`` None) or its fit from domino ``fit_from`` on
    (:func:`dominowave.chain.wave.speed_from`, pitch-based, as cameras measure).
    """

    runs: list[ChainRun]
    speed: EnsembleStats
    arrival_mean: np.ndarray
    arrival_std: np.ndarray
    arrival_stderr: np.ndarray
    theory_speed: float
    theory_window_speed: EnsembleStats
    fits: list[SteadySpeed] = field(default_factory=list)
    fit_from: int | None = None


BYTES_PER_DOMINO = 60e3
"""Engine state of one 10-sphere domino with its candidate pairs [bytes] (measured with
tracemalloc on 100- and 1000-domino chains: about 52 kB)."""
BYTES_PER_FRAME_DOMINO = 13 * 8
"""One domino in one trajectory frame: position, quaternion, velocity, spin [bytes]."""

MAX_STEPS = 1e10
"""Most time steps a chain run may need (about a day of engine time at N = 300)."""
SLEEP_SPEED = 1e-2
"""A box domino sleeps once every point of it has moved slower than this times
``sqrt(g l)`` for :data:`SLEEP_TIME` (``DominoChain(sleep=True)``, the default of box
chains; ``dem.Scene.build``'s ``sleep_speed``): 7 mm/s for the standard domino, against
front speeds of about ``sqrt(g l)``.  Chosen by the measured error (docs/shape.md,
"Sleeping dominoes"): it moves the front speeds and the arrivals of the measured chains
by at most 3.5e-4, a fiftieth of the fidelity's default tolerance; twice this speed, or
half of :data:`SLEEP_TIME`, moves them three to four times as much and saves a fifth to a
third of the 300-domino chain's time, and stricter criteria take up to 2.3 times the
time."""
SLEEP_TIME = 0.5
"""... for this times ``sqrt(l/g)``, the time scale of a domino's fall (35 ms for the
standard domino)."""


def default_speed_bound(params: ChainParams) -> float:
    """The wave speed [m/s] the default ``max_time`` of a run allows for: the smaller of
    the limit speed of eq 34 and ``sqrt(g l)``.

    Eq 34 is the speed of frictionless elastic dominoes; friction and inelastic contacts
    between dominoes slow a chain far below it (a standard 48 mm domino at d/l = 0.1:
    eq 34 19 m/s, a DEM chain with friction 0.4 m/s = 0.6 sqrt(g l),
    docs/real_dominoes.md section 8), while the chains of the package and the filmed
    rows run at 0.6 to 2 sqrt(g l).  Three times the travel time at this bound (the
    default ``max_time``) covers any wave faster than a third of ``sqrt(g l)``; a slower
    one is dying, which ends the run by the quiet time."""
    return min(theory_speed(params), math.sqrt(params.g * params.height))


class DominoChain:
    """The DEM model of a domino chain for parameters ``params`` (``ChainParams``).

    Parameters of the run (not of the physics): ``dt`` [s] (default: the theory's
    collision time ``T_c`` (eq 31, clump mapping) divided by ``steps_per_collision``, not
    set 50, so a collision is resolved alike at every stiffness, or for a softened contact
    the steps its tolerance allows, 10 at the default 2 %
    (:func:`dominowave.chain.fidelity.steps_per_collision`); the engine refuses a
    step above its critical one), ``frame_interval`` [s] between trajectory frames used
    for the event analysis, ``quiet_time`` [s] without any new contact after which
    the run stops (the wave died; default ``10 sqrt(l/g)``), ``max_time`` [s] hard
    limit (default: three times the travel time at :func:`default_speed_bound` plus
    the quiet time; a run that reaches it before the wave reaches the last domino is
    ``ChainRun.cut_short``),
    ``tail_time`` [s] run on after the wave reached the last domino, to record the
    aftermath (default ``5 sqrt(l/g)``; 0: none, for a run that wants the arrivals
    only); it ends sooner once every domino is at rest (held: asleep or never
    touched).  ``safety`` (instead of ``dt``): the step as that fraction of the
    engine's critical estimate for the built scene (``dem.Scene.build``, timestep.py),
    e.g. for a Hertz chain (``normal_law = "hertz"``), whose collisions the linear
    theory's ``T_c`` does not describe.

    ``fidelity`` (a numerical setting too): a chain of given materials (a box chain given
    ``young``, e.g. the presets) runs with the softest contact spring whose estimated
    speed error stays within the tolerance (default 2 %), ``"exact"`` with the material's
    own (:mod:`dominowave.chain.fidelity`). ``material_params`` are the parameters given,
    ``params`` those simulated (``kn`` in place of ``young`` when softened), and
    ``contact`` the choice with its estimate (None where the setting does not apply).

    ``sleep`` (box chains): a domino that has come to rest is put to sleep, held again at
    no cost until a moving body touches or drives it: once every point of it has moved
    slower than ``sleep_speed sqrt(g l)`` for ``sleep_time sqrt(l/g)`` (defaults
    :data:`SLEEP_SPEED`, :data:`SLEEP_TIME`; ``dem.Scene.build``). It changes the front
    speeds of the measured chains by at most 3.5e-4 and makes a 300-domino chain nine
    times faster than awake (docs/shape.md, "Sleeping dominoes"); ``sleep=False`` keeps
    every domino awake.
    """

    def __init__(
        self,
        params: ChainParams,
        *,
        dt: float | None = None,
        steps_per_collision: int | None = None,
        frame_interval: float | None = None,
        quiet_time: float | None = None,
        max_time: float | None = None,
        tail_time: float | None = None,
        safety: float | None = None,
        fidelity: Fidelity = None,
        sleep: bool = True,
        sleep_speed: float = SLEEP_SPEED,
        sleep_time: float = SLEEP_TIME,
    ):
        self.material_params = params
        self.contact = choose_contact(params, fidelity)
        if self.contact is not None and self.contact.softened:
            params = params.with_(kn=self.contact.kn)
        self.params = params
        self._options = {
            "dt": dt,
            "safety": safety,
            "fidelity": fidelity,
            "steps_per_collision": steps_per_collision,
            "frame_interval": frame_interval,
            "quiet_time": quiet_time,
            "max_time": max_time,
            "tail_time": tail_time,
            "sleep": sleep,
            "sleep_speed": sleep_speed,
            "sleep_time": sleep_time,
        }
        self.sleep = bool(sleep)
        self.sleep_speed = check_in_range("sleep_speed", sleep_speed, 0.0, math.inf)
        self.sleep_time = check_in_range("sleep_time", sleep_time, 0.0, math.inf)
        if steps_per_collision is None:
            steps_per_collision = default_steps_per_collision(self.contact)
        check_in_range("steps_per_collision", steps_per_collision, 10, math.inf, lo_inclusive=True)
        if safety is not None:
            check_in_range("safety", safety, 0.0, 1.0, hi_inclusive=True)
            if dt is not None:
                raise ValueError(f"give dt or safety, not both (got dt = {dt}, safety = {safety})")
        self.dt = dt if dt is not None else theory_collision_time(params) / steps_per_collision
        check_positive("dt", self.dt)
        scale = math.sqrt(params.height / params.g)
        self.frame_interval = frame_interval or 0.01 * scale
        self.quiet_time = quiet_time or 10.0 * scale
        self.tail_time = 5.0 * scale if tail_time is None else tail_time
        check_in_range("tail_time", self.tail_time, 0.0, math.inf, lo_inclusive=True)
        check_positive("frame_interval", self.frame_interval)
        check_positive("quiet_time", self.quiet_time)
        if max_time is None:
            travel = params.n_dominoes * params.pitch / default_speed_bound(params)
            max_time = 3.0 * travel + self.quiet_time
        self.max_time = check_positive("max_time", max_time)
        self.shape = domino_shape(params) if params.shape == "clump" else domino_box(params)
        # the nominal positions n (d + s): where the wave is measured (pitch-based); the
        # dominoes stand at these plus their placement errors
        self.positions = chain_positions(params)
        self.placement = placement(params)
        # refuse what the DEM cannot represent before anything is allocated
        self._check_sink()
        frames = (self.max_time + self.tail_time) / self.frame_interval
        check_memory(
            params.n_dominoes * (BYTES_PER_DOMINO + frames * BYTES_PER_FRAME_DOMINO),
            f"its bodies, contacts and up to {frames:.3g} trajectory frames",
            f"n_dominoes = {params.n_dominoes}",
        )
        if safety is not None:  # (the critical estimate needs the built scene)
            sim, _ = self._build_scene(self.resolve(None), dt=None, safety=safety)
            self.dt = sim.dt
        self._check_steps()

    def _stiffness_text(self) -> str:
        p = self.params
        if p.normal_law == "hertz":
            return f"Young's modulus young = {p.young:.4g} Pa (Hertz law)"
        text = f"the contact stiffness k_n = {p.contact_stiffness:.4g} N/m (k/k* = "
        return text + f"{p.stiffness_over_kstar:.4g})"

    def _check_sink(self) -> None:
        """Too soft: a domino standing on the floor would sink more than one sphere
        radius (edge rounding) into it under its own weight (``_sink``), so contacts are
        no longer small overlaps of rigid spheres (the premise of the contact models);
        such a chain ran one time step longer than the whole wave and reported it."""
        p = self.params
        sink = self._sink() / p.contact_radius
        radii = "sphere radii" if p.shape == "clump" else "edge roundings r"
        if sink <= 1.0:
            return
        if p.normal_law == "hertz":  # (the sink goes as E^{-2/3})
            law, bound = "m g / 4 = K delta^{3/2}", f"young >= {p.young * sink**1.5:.3g} Pa"
        else:
            law, bound = "m g / k_n", f"k/k* >= {p.stiffness_over_kstar * sink:.3g}"
        raise ValueError(
            f"{self._stiffness_text()} is too soft: a standing domino would sink {sink:.3g}"
            f" {radii} into the floor under its weight ({law}); the DEM needs well below 1"
            f" ({bound} for this chain)"
        )

    def _check_steps(self) -> None:
        """Too stiff: the time step resolving the collision would need more than
        ``MAX_STEPS`` steps for the run."""
        stiffness = self._stiffness_text()
        steps = (self.max_time + self.tail_time) / self.dt
        if not steps <= MAX_STEPS:
            raise ValueError(
                f"{stiffness} needs dt = {self.dt:.3g} s to resolve a collision: {steps:.3g}"
                f" steps for this run, more than the {MAX_STEPS:.0e} allowed"
            )

    # --- scene --------------------------------------------------------------------------
    def resolve(self, push: Push | None) -> Push:
        """``push`` with the default filled in: ``omega = sqrt(g / l)``."""
        if push is None or (push.omega is None and push.impulse is None):
            return Push(omega=math.sqrt(self.params.g / self.params.height))
        return push

    def _sink(self) -> float:
        """Static overlap of an upright domino with the floor [m]."""
        p = self.params
        if p.normal_law == "hertz":  # m g / 4 = K delta^{3/2} on the four corners
            return (p.mass * p.g / (4 * p.hertz_coefficient)) ** (2.0 / 3.0)
        if p.shape == "box":  # four corners (a planar box: two, each counted twice)
            return p.mass * p.g / (4 * p.contact_stiffness)
        n_base = int(self.shape.bottom.sum())
        return p.mass * p.g / (n_base * p.contact_stiffness)

    def _push_velocities(self, push: Push) -> tuple[np.ndarray, np.ndarray, float]:
        """Initial (v_com, omega) of domino 0 and the theory's Omega_1 [rad/s]."""
        p = self.params
        com = self.shape.centre_of_mass
        inertia_pivot = effective_domino(p).inertia_pivot
        if push.impulse is None:
            # rolling about the pivot's floor contact: v_com = omega x (com - contact)
            w = np.array([0.0, push.omega, 0.0])
            return np.cross(w, com - self.shape.pivot_contact), w, push.omega
        h = push.height if push.height is not None else p.height - p.radius
        i_cm = self.shape.inertia_about_y(com)  # the box's: y is a principal axis
        v = np.array([push.impulse / p.mass, 0.0, 0.0])
        w = np.array([0.0, (h - com[2]) * push.impulse / i_cm, 0.0])
        # theory's Omega_1: the same impulse on a domino hinged at its base contact
        return v, w, push.impulse * h / inertia_pivot

    def _stands(self, v0: np.ndarray, w0: np.ndarray):
        """Where each domino stands, ``(x, y, yaw)`` [m, m, rad] with its placement errors,
        and how it starts: the keywords ``blocked``, ``velocity``, ``angular_velocity`` and
        ``held`` of ``dem.Scene.add_clump`` and ``add_box``. Domino 0 moves with ``v0``
        [m/s] and ``w0`` [rad/s]; the others stand still (held, if the chain holds them)."""
        p = self.params
        errors = self.placement
        stands = zip(self.positions + errors.along, errors.across, errors.yaw, strict=True)
        for n, (x, y, yaw) in enumerate(stands):
            moving = n == 0
            start = {
                "blocked": "y rx rz" if p.model == "2d" else "",
                "velocity": v0 if moving else (0.0, 0.0, 0.0),
                "angular_velocity": w0 if moving else (0.0, 0.0, 0.0),
                "held": p.held and not moving,
            }
            yield x, y, yaw, start

    def build(self, push: Push, record: bool = True, track_energy: bool = True):
        """The ``dem`` simulation with domino ``n`` as body ``n``; returns (sim, omega_1).

        ``record=False`` switches the engine's contact event log and pair statistics
        off (engines-only timing); the chain analysis needs them on.  ``track_energy``:
        the engine's dissipation ledger (``dem.Scene.build``; off for engines-only
        timing, as YADE's default).
        """
        return self._build_scene(push, self.dt, None, record, track_energy)

    def _build_scene(self, push, dt, safety, record=True, track_energy=True):
        """``build`` with the step ``dt`` [s] or (dt None) ``safety`` x the critical one."""
        p = self.params
        step = {"dt": dt} if safety is None else {"dt": None, "safety": safety}
        scene = dem.Scene(
            gravity=(0.0, 0.0, -p.g),
            stiffness_rule="paper",
            shear_kinematics=p.shear_kinematics,
            normal_law=p.normal_law,
        )
        if p.shape == "box":
            return self._build_boxes(scene, push, record, track_energy, step)
        kw = {"kn": p.contact_stiffness, "kt_ratio": p.kt_ratio, "restitution": p.restitution}
        densities = np.unique(self.shape.density)
        mat_face = {
            rho: scene.add_material(dem.Material(density=rho, friction=p.friction_dominoes, **kw))
            for rho in densities
        }
        mat_base = {
            rho: scene.add_material(dem.Material(density=rho, friction=p.friction_floor, **kw))
            for rho in densities
        }
        floor = scene.add_material(dem.Material(density=p.density, friction=p.friction_floor, **kw))
        scene.add_wall(point=(0.0, 0.0, 0.0), normal=(0.0, 0.0, 1.0), material=floor)
        materials = [
            (mat_base if bottom else mat_face)[rho]
            for rho, bottom in zip(self.shape.density, self.shape.bottom, strict=True)
        ]
        v0, w0, omega_1 = self._push_velocities(push)
        sink = self._sink()
        for x, y, yaw, start in self._stands(v0, w0):
            scene.add_clump(
                place_domino(self.shape, x, yaw, sink, y), self.shape.radii, materials, **start
            )
        sim = scene.build(
            **step,
            damping=p.damping,
            # a Verlet skin of one sphere radius: the list is rebuilt ~3x less often than
            # with the generic 0.3 R, at ~3x more (cheap, inactive) candidate pairs -- a
            # clump chain has few neighbours per sphere; the trajectory does not depend
            # on the skin (test_validate_results_independent_of_verlet_skin)
            skin=p.radius,
            record_pairs=record,
            track_energy=track_energy,
            overlap_tolerance=1.01 * sink / float(self.shape.radii.min()) + 1e-9,
        )
        return sim, omega_1

    def _build_boxes(self, scene, push: Push, record: bool, track_energy: bool, step: dict):
        """The box chain's simulation (``build`` with ``shape = "box"``); ``step`` the
        keywords ``dt`` / ``safety`` of ``dem.Scene.build``."""
        p = self.params
        e_dominoes, e_floor = p.restitution_pairs
        kw = {"kn": p.contact_stiffness, "kt_ratio": p.kt_ratio}
        if p.normal_law == "hertz":  # (the tangential spring: pi r E / 2, as kn's)
            kw = {"young": p.young, "poisson": p.poisson_ratio, "kt_ratio": p.kt_ratio}
        box = scene.add_material(dem.Material(density=p.density, **kw))
        floor = scene.add_material(dem.Material(density=p.density, **kw))
        # friction and restitution by material pair, not the min rule of one value per body
        scene.set_pair(box, box, friction=p.friction_dominoes, restitution=e_dominoes)
        scene.set_pair(box, floor, friction=p.friction_floor, restitution=e_floor)
        scene.add_wall(point=(0.0, 0.0, 0.0), normal=(0.0, 0.0, 1.0), material=floor)
        v0, w0, omega_1 = self._push_velocities(push)
        sink = self._sink()
        shape = self.shape
        for x, y, yaw, start in self._stands(v0, w0):
            scene.add_box(
                (x, y, shape.half_extents[2] - sink),
                shape.half_extents,
                shape.rounding,
                box,
                orientation=yaw_matrix(yaw),
                **start,
            )
        sim = scene.build(
            **step,
            damping=p.damping,
            # a skin of one thickness, not of the rounding (s/20): the list is rebuilt
            # ~20 times less often while dominoes fall, and the bounding spheres of
            # neighbours (half-diagonals ~l/2) list nearly the same pairs; the trajectory
            # does not depend on the skin (dem/boxes.py: the list is a superset of the
            # pairs that touch, visited in pair order)
            skin=p.thickness,
            record_pairs=record,
            track_energy=track_energy,
            **(self._sleep_settings() if self.sleep else {}),
        )
        return sim, omega_1

    def _sleep_settings(self) -> dict[str, float]:
        """The sleep criterion of a box chain (``dem.Scene.build``): every point slower than
        ``sleep_speed sqrt(g l)`` for ``sleep_time sqrt(l/g)``."""
        p = self.params
        return {
            "sleep_speed": self.sleep_speed * math.sqrt(p.g * p.height),
            "sleep_time": self.sleep_time * math.sqrt(p.height / p.g),
        }

    def initial_frame(self, sim, push: Push) -> dict[str, np.ndarray]:
        """The bodies of ``sim`` before the run as a trajectory frame (the arrays of
        :meth:`record` with one row): only domino 0 moves, pushed by ``push``."""
        v0, w0, _ = self._push_velocities(push)
        b = sim.bodies
        velocity, omega = np.zeros_like(b.pos), np.zeros_like(b.pos)
        velocity[0], omega[0] = v0, w0
        return {
            "times": np.array([sim.time], dtype=float),
            "positions": b.pos[None].copy(),
            "quaternions": b.quat[None].copy(),
            "velocities": velocity[None],
            "angular_velocities": omega[None],
        }

    # --- running ------------------------------------------------------------------------
    def stepper(self, push: Push | None = None, contact_forces: bool = False) -> ChainStepper:
        """The run pushed by ``push``, to be advanced in pieces (checkpoints, progress);
        ``contact_forces``: also record the contact forces at the frames (for VTK).
        The push is scaled by the chain's own push error (``ChainParams.push_error``)."""
        push = self.resolve(push)
        factor = self.placement.push_factor
        if factor != 1.0:
            push = push.scaled(factor)
        return ChainStepper(self, push, contact_forces=contact_forces)

    def run(self, push: Push | None = None, keep_record: bool = False) -> ChainRun:
        """Push domino 0, run until quiet or ``max_time``, analyse; see ``ChainRun``.

        One uninterrupted advance of :meth:`stepper` (:mod:`dominowave.chain.stepper`
        has the two phases: until the last domino is touched, then the tail).
        """
        stepper = self.stepper(push)
        stepper.advance(np.iinfo(np.int64).max)
        return stepper.result(keep_record=keep_record)

    def analyse(
        self,
        push: Push,
        omega_1: float,
        record: ChainRecord,
        *,
        dt: float,
        n_steps: int,
        wall_time: float,
        stop_reason: str,
        keep_record: bool = False,
    ) -> ChainRun:
        """The ``ChainRun`` of a run's ``record``: events, wave fit, theory beside it."""
        p = self.params
        events = analyse_events(
            record, critical_angle=self.critical_angle, min_gap=self.collision_time()
        )
        wave = steady_speed(events.arrival, self.positions)
        theory_arrival = theory_first_contacts(p, omega_1)
        window = (
            fit_speed(theory_arrival, self.positions, wave.first, wave.last).speed
            if wave.settled
            else math.nan
        )
        return ChainRun(
            params=p,
            push=push,
            positions=self.positions,
            arrival=events.arrival,
            events=events,
            wave=wave,
            secondary=self._secondary(record),
            omega_1=omega_1,
            theory_speed=theory_speed(p),
            theory_arrival=theory_arrival,
            theory_window_speed=window,
            dt=dt,
            n_steps=n_steps,
            wall_time=wall_time,
            stop_reason=stop_reason,
            record=record if keep_record else None,
            fidelity=self.contact,
        )

    def ensemble(
        self,
        push: Push | None = None,
        members: int = 8,
        seed: int = 0,
        jitter: float = 1e-3,
        keep_records: bool = False,
        fit_from: int | None = None,
        vary_placement: bool = False,
    ) -> ChainEnsemble:
        """``members`` runs with pushes scaled by ``1 + jitter * N(0, 1)`` (seeded).

        Member ``i`` draws from ``numpy.random.default_rng([seed, i])``
        (:func:`member_push_factor`), so a member is reproducible on its own and the
        ensemble is bit-identical for a seed. ``fit_from = K``: each member's speed is the
        fit from domino ``K`` on (:func:`~dominowave.chain.wave.speed_from`) instead of
        the settled-region fit. ``vary_placement``: each member also stands anew, with
        its own placement errors (``asymmetry_seed`` of member ``i`` from
        :func:`member_placement_seed`), as a real chain set up again for each run;
        otherwise every member has this chain's placement.
        """
        check_in_range("members", members, 1, math.inf, lo_inclusive=True)
        check_in_range("seed", seed, 0, math.inf, lo_inclusive=True)  # NumPy's seeds are >= 0
        check_nonnegative("jitter", jitter)
        if fit_from is not None:  # checked before any run
            check_fit_from(fit_from, self.params.n_dominoes)
        push = self.resolve(push)
        runs = []
        for i in range(members):
            factor = member_push_factor(seed, i, jitter)
            chain = self
            if vary_placement:
                member_params = self.material_params.with_(
                    asymmetry_seed=member_placement_seed(seed, i)
                )
                chain = DominoChain(member_params, **self._options)
            runs.append(chain.run(push.scaled(factor), keep_record=keep_records))
        arrivals = np.array([r.arrival for r in runs])
        mean, std, se = ensemble_arrival_stats(arrivals)
        fits = [r.wave if fit_from is None else self.speed_from(r, fit_from) for r in runs]
        return ChainEnsemble(
            fits=fits,
            fit_from=fit_from,
            runs=runs,
            speed=ensemble_stats([f.speed for f in fits]),
            arrival_mean=mean,
            arrival_std=std,
            arrival_stderr=se,
            theory_speed=theory_speed(self.params),
            theory_window_speed=ensemble_stats([r.theory_window_speed for r in runs]),
        )

    # --- analysis -----------------------------------------------------------------------
    @staticmethod
    def speed_from(run: ChainRun, fit_from: int) -> SteadySpeed:
        """The front speed of ``run`` fitted from domino ``fit_from`` on [m/s]
        (:func:`dominowave.chain.wave.speed_from`, on the nominal pitch positions)."""
        return speed_from(run.arrival, run.positions, fit_from)

    @property
    def critical_angle(self) -> float:
        """Tilt past which a domino topples by itself [rad].

        Two-sphere base: the centre of mass passes over the front base sphere's floor
        contact. A single sphere has no stable upright, so we use the tilt of the
        flat-based domino of the same thickness, ``atan(s / l)``. A box rolls on its
        rounded front edge: the centre of mass passes over that edge's centre,
        ``atan((s/2 - r) / (l/2 - r))``.
        """
        p = self.params
        if p.shape == "box":
            pivot = self.shape.pivot_point
            return critical_tilt(float(pivot[0]), float(self.shape.centre_of_mass[2] - pivot[2]))
        if p.base_layout == "two":
            return critical_tilt(p.radius / 2.0, float(self.shape.centre_of_mass[2]))
        return critical_tilt(p.thickness / 2.0, p.height / 2.0)

    def record(self, frames: dict, events: dict, end_time: float, tracks=None) -> ChainRecord:
        """A ``ChainRecord`` from engine recordings: ``frames`` the trajectory arrays of a
        ``dem`` run result (``times (F,)``, ``positions``, ``quaternions``, ``velocities``,
        ``angular_velocities`` (F, N, 3 or 4)), ``events`` its contact event arrays
        (``time``, ``body_i``, ``body_j``, ``kind``), ``end_time`` [s] of the run.
        ``tracks``: each domino's stored frames (``chain.frames.Track``), for a record
        whose ``frames`` hold the times alone."""
        shape = self.shape
        com0 = shape.centre_of_mass
        # the pivot: a clump's front base sphere centre, a box's front bottom edge centre
        pivot = shape.centres[shape.pivot] if self.params.shape == "clump" else shape.pivot_point
        top = np.array([0.0, 0.0, self.params.height])
        n = self.params.n_dominoes
        return ChainRecord(
            times=frames["times"],
            com=frames.get("positions"),
            quat=frames.get("quaternions"),
            velocity=frames.get("velocities"),
            angular_velocity=frames.get("angular_velocities"),
            axis=np.tile([0.0, 0.0, 1.0], (n, 1)),
            base_offset=np.tile(pivot - com0, (n, 1)),
            top_offset=np.tile(top - com0, (n, 1)),
            ev_time=events["time"].astype(float),
            ev_i=events["body_i"],
            ev_j=events["body_j"],
            ev_kind=events["kind"],
            end_time=float(end_time),
            tracks=None if tracks is None else tuple(tracks),
        )

    def _secondary(self, record: ChainRecord) -> SecondaryWave | None:
        """Wave of second collisions (contacts closer than ``T_c`` merged, as in events)."""
        t_c = self.collision_time()
        pairs = neighbour_intervals(record, self.params.n_dominoes)
        onsets = [merge_contacts(on, off, t_c)[0] for on, off in pairs]
        first, second = first_and_second_onsets(onsets)
        return secondary_wave(first, second, self.positions[1:], merge_lag=t_c)

    def collision_time(self) -> float:
        """Theory's ``T_c`` [s] for these parameters (eq 31, clump mapping)."""
        return theory_collision_time(self.params)
