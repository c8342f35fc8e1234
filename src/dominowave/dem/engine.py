"""The compiled time loop, its recorders and stop conditions.

:func:`time_loop` gives the compiled loop ``run_loop`` of a kind of scene; it advances the
scene step by step entirely in numba-compiled code.  It
returns to Python only when it is done, when a stop condition fires, when a recorder
buffer or the Verlet list needs more room (Python grows it and calls again, the state
being untouched by the interrupted step), or when the run must be aborted.

One step (see integrate.py for the scheme):
rebuild the Verlet list if a body's spheres may have moved more than skin/2, or if a box
was released whose pairs the box list left out (then place every sphere; between builds
only the listed ones are moved; the candidate pairs of the boxes are rebuilt with it) ->
contact forces -> contact
onset/end bookkeeping (held bodies, events, pair statistics) -> stop conditions at t_n ->
kick -> recorders and checks at t_n -> drift -> place the listed spheres.  In the steps
where no recorder, check or energy ledger reads the state between kick and drift, kick
and drift are one pass over the bodies that also tests the Verlet list for the next step
(:func:`_body_pass`; the same arithmetic).  The optional contact-force recorder
(``rec.cf_on``) copies the forces of the active contacts at each trajectory frame; off, it
costs one test per frame.
"""

from __future__ import annotations

import functools
import math
from collections import namedtuple

from numba import njit

from dominowave.dem.box_sphere import build_box_sphere_candidates
from dominowave.dem.boxes import (
    _reach_of,
    box_contact_forces,
    box_energies,
    box_forces_general,
    box_forces_general_spheres,
    box_forces_planar,
    box_forces_planar_spheres,
    box_peak_force,
    box_power,
    build_box_candidates,
    held_flags_changed,
)
from dominowave.dem.compiled import inline_kernel, inner_kernel
from dominowave.dem.contact import (
    build_verlet_list,
    compute_forces,
    compute_forces_planar,
    mark_build,
    moved_beyond,
    needs_rebuild,
    needs_rebuild_after_drift,
)
from dominowave.dem.contact_rows import (
    END,
    ONSET,
    POWER_FRICTION,
    POWER_VISCOUS,
    rows_contact_forces,
    rows_peak_force,
    rows_power,
)
from dominowave.dem.energy import (
    E_DISSIPATED_DAMPING,
    E_DISSIPATED_FRICTION,
    E_DISSIPATED_VISCOUS,
    E_ELASTIC_NORMAL,
    E_ELASTIC_TANGENTIAL,
    E_GRAVITATIONAL,
    E_KINETIC_ROTATIONAL,
    E_KINETIC_TRANSLATIONAL,
    E_TOTAL,
    LAST_POWER_DAMPING,
    LAST_POWER_FRICTION,
    LAST_POWER_VISCOUS,
    LEDGER_DAMPING,
    LEDGER_FRICTION,
    LEDGER_VISCOUS,
    N_MECHANICAL,
    energies,
    kinetic_energy,
)
from dominowave.dem.integrate import (
    advance_body_planar,
    drift_body,
    drift_general,
    drift_planar,
    kick_body,
    kick_general,
    kick_planar,
    update_listed_sphere_positions,
    update_sphere_positions,
)

__all__ = ["Recorder", "SceneKind", "Settings", "quiet_reached", "steps_until_quiet", "time_loop"]

# return codes of run_loop
DONE_STEPS = 0
DONE_TIME = 1
STOP_NO_ONSET = 2
STOP_TOUCHED = 3
STOP_KINETIC = 4
STOP_AT_REST = 5
GROW_CONTACTS = 10
GROW_EVENTS = 11
GROW_TRAJECTORY = 12
GROW_ENERGY = 13
GROW_CONTACT_FORCES = 14
GROW_BOX_CANDIDATES = 15
ABORT_NAN = 20
ABORT_RUNAWAY = 21

# entries of run_loop's (5,) ``stop`` argument (see run_loop)
STOP_ARG_QUIET = 0
STOP_ARG_TOUCHED_BODY = 1
STOP_ARG_KINETIC_BELOW = 2
STOP_ARG_RUN_START = 3
STOP_ARG_AT_REST = 4

# entries of Recorder.clock
CLOCK_TIME = 0  # time [s]
CLOCK_ENERGY_SCALE = 1  # largest active energy so far [J] (the runaway test, active_energy)

# rows of run_loop's (2, 3) ``work`` scratch argument
WORK_KINETIC = 0  # kinetic energies (energy.kinetic_energy)
WORK_POWER = 1  # contact powers (contact_rows.rows_power)

Settings = namedtuple(
    "Settings",
    [
        "gravity",  # (3,) [m/s^2]
        "dt",  # [s]
        "damping",  # local damping coefficient
        "damp_gravity",  # bool
        "skin",  # Verlet skin [m]
        "record_pairs",  # bool: body-pair statistics and the event log
        "record_peak_force",  # bool
        "check_every",  # steps between stop/energy checks
        "track_energy",  # bool: keep the dissipation ledger (off: YADE's trackEnergy=False)
        "planar",  # bool: the scene is planar (planar.py), use the planar kernels
        "sleep_speed",  # [m/s] a box slower than this at every point may sleep; 0: never
        "sleep_time",  # [s] how long it must stay that slow (_sleep_and_wake)
    ],
)

Recorder = namedtuple(
    "Recorder",
    [
        "clock",  # (2,) time [s], energy scale for the runaway test [J]: CLOCK_*
        "ledger",  # (3,) dissipated by friction, viscous dashpots, local damping [J]:
        #   energy.LEDGER_*
        "power",  # (3,) power of dashpots, local damping, tangential forces, last step [W]:
        #   energy.LAST_POWER_*
        "step",  # (1,) int64 steps done since build
        "n_rebuilds",  # (1,) int64 Verlet-list builds since build
        "last_onset",  # (1,) time of the last body-body contact onset [s]
        "touched",  # (nb,) uint8: body had a body-body onset in this run
        "changes",  # (C, 3) int64 scratch: the sphere contacts that started or ended in
        #   this step (contact_rows.log_change: body i, body j or -(wall + 1), ONSET / END)
        "change_lag",  # (C,) scratch: how long before the step's time each did [s]
        "pair_count",  # (nb, nb) int32 touching contacts per body pair (i < j; a sphere
        #   contact each, a box body pair one: _bookkeep)
        "wall_count",  # (nb, nw) int32 touching contacts per body-wall pair (likewise)
        "first_contact",  # (nb, nb) [s], nan
        "last_separation",  # (nb, nb) [s], nan
        "n_contacts",  # (nb, nb) int64 distinct body-body contacts
        "peak_force",  # (nb, nb) largest normal force of a sphere contact or box point [N]
        "ev_n",  # (1,) int64 events logged
        "ev_time",  # (E,)
        "ev_i",  # (E,) int64
        "ev_j",  # (E,) int64 body, or -(wall + 1)
        "ev_kind",  # (E,) int8 ONSET / END
        "traj_every",  # (1,) int64, 0 = off
        "traj_n",  # (1,) int64 trajectory frames recorded
        "traj_t",  # (F,) time of each frame [s]
        "traj_first",  # (F,) int64 the body of each frame's first row (_record_frame)
        "traj_start",  # (F + 1,) int64 first row of each frame, then the rows recorded
        "traj_span",  # (2,) int64 [lo, hi): every body that may have moved since the
        #   last frame lies in range(lo, hi) (_record_frame)
        "traj_pos",  # (R, 3) [m], a row per body of a frame
        "traj_quat",  # (R, 4)
        "traj_vel",  # (R, 3) [m/s]
        "traj_omega",  # (R, 3) [rad/s]
        "cf_on",  # (1,) int64: 1 = record the contact forces at trajectory frames
        "cf_n",  # (1,) int64 contact rows recorded
        "cf_start",  # (F,) int64 first contact row of each trajectory frame
        "cf_first",  # (K,) int64 shape id (spheres, then boxes: ContactFrames), or -(wall + 1)
        "cf_second",  # (K,) int64 shape id (for a wall contact, the shape on the wall): the
        #   force acts on it
        "cf_point",  # (K, 3) contact point [m]
        "cf_force",  # (K, 3) total contact force on `cf_second` [N]
        "energy_every",  # (1,) int64, 0 = off
        "energy_n",  # (1,) int64
        "energy_t",  # (G,)
        "energy_val",  # (G, N_ENERGIES) the ENERGY_NAMES vectors, indices energy.E_*
        "energy_now",  # (N_ENERGIES,) energies at the last step
        "energy_ref",  # (N_ENERGIES,) energies at the start of the run
    ],
)


@inline_kernel()
def _free(bodies, b, t):
    """Body b, held or asleep, moves from time t [s] on (:func:`_release`)."""
    bodies.held[b] = 0
    bodies.fresh[b] = 0  # (a held body keeps the flag of its creation)
    bodies.calm_since[b] = math.nan
    if math.isnan(bodies.release_time[b]):  # (a body woken from sleep keeps its first)
        bodies.release_time[b] = t


@inner_kernel(_nrt=False)
def _release(bodies, spheres, contacts, b, t):
    """Free a held body, and (transitively) held bodies it already touches.

    A held body has been at rest, ``v_{n-1/2} = 0`` (Scene and Simulation refuse it a
    velocity), so it is not flagged ``fresh``: it takes the leapfrog's full kick
    ``v_{n+1/2} = dt a_n``, as a free body at rest would.  The half kick of a
    velocity-Verlet start would give it half of this step's impulse while its pusher
    takes the whole reaction."""
    _free(bodies, b, t)
    changed = True
    while changed:
        changed = False
        for c in range(contacts.n[0]):
            j = contacts.j[c]
            if not contacts.overlap[c] > 0.0 or j < 0:  # (not touching, or a wall)
                continue
            bi = spheres.body[contacts.i[c]]
            bj = spheres.body[j]
            if bodies.held[bi] != bodies.held[bj]:
                _free(bodies, bi if bodies.held[bi] else bj, t)
                changed = True


@inline_kernel()
def _box_speed(bodies, boxes, x):
    """Bound [m/s] on the speed of every point of box x: ``|v| + |omega| (reach + r)``,
    at the full-step velocities of the last kick."""
    v, w = bodies.vel_full[boxes.body[x]], bodies.omega_full[boxes.body[x]]
    speed = math.sqrt(v[0] ** 2 + v[1] ** 2 + v[2] ** 2)
    spin = math.sqrt(w[0] ** 2 + w[1] ** 2 + w[2] ** 2)
    return speed + spin * (_reach_of(boxes, x) + boxes.radius[x])


@inner_kernel(_nrt=False)
def _sleep_and_wake(bodies, spheres, contacts, boxes, settings, t, ledger):
    """Put resting boxes to sleep and wake sleeping ones that a moving box drives; returns
    whether a held flag changed.  Called at the check steps (every ``check_every``), after
    the kick.

    A box *sleeps* -- it is held again, as an untouched domino is (its velocity zeroed,
    its kinetic energy, below ``m v_s^2 / 2``, booked as dissipated by damping; held with
    ``bodies.calm_since`` set, where an untouched domino has NaN; its rows
    with other resting bodies and the walls put aside, boxes.box_forces) -- once every
    point of it has moved slower than ``settings.sleep_speed`` ``v_s`` for
    ``settings.sleep_time`` and every moving box it touches is that slow too (a box
    leaning on a moving one moves with it).  A sleeping box *wakes* (engine._release) at
    the onset of a new contact with a moving body, as a held one is released, or here
    when a box it touches moves at ``v_s`` or faster.  The error of the criterion is
    measured, not bounded (docs/dem.md, "Sleeping boxes")."""
    v_sleep = settings.sleep_speed
    rows = boxes.rows
    held, calm = bodies.held, bodies.calm_since
    changed = False
    restless = boxes.restless
    restless[:] = 0
    for c in range(rows.n[0]):
        i, j = rows.i[c], rows.j[c]
        if j < 0 or j >= boxes.body.shape[0]:  # (a wall, or a sphere: Scene.build refuses
            continue  # sleep in a scene with spheres)
        bi, bj = boxes.body[i], boxes.body[j]
        for rest, mover, x in ((bi, bj, j), (bj, bi, i)):
            if held[mover]:
                continue
            fast = _box_speed(bodies, boxes, x) >= v_sleep
            if held[rest] and fast and not math.isnan(calm[rest]):  # (asleep)
                _release(bodies, spheres, contacts, rest, t)
                changed = True
            if fast:  # (the partner of a box that is not slow does not sleep)
                restless[i if rest == bi else j] = 1
    for x in range(boxes.body.shape[0]):
        b = boxes.body[x]
        if held[b]:
            continue
        if _box_speed(bodies, boxes, x) >= v_sleep:
            calm[b] = math.nan
            continue
        if math.isnan(calm[b]):
            calm[b] = t
        if t - calm[b] < settings.sleep_time or restless[x]:
            continue
        kinetic = 0.0
        for k in range(3):
            kinetic += 0.5 * bodies.mass[b] * bodies.vel_full[b, k] ** 2
            kinetic += 0.5 * bodies.omega_full[b, k] * bodies.angmom_full[b, k]
            for arr in (bodies.vel, bodies.vel_full, bodies.omega, bodies.omega_full):
                arr[b, k] = 0.0
            bodies.angmom[b, k] = 0.0
            bodies.angmom_full[b, k] = 0.0
        ledger[LEDGER_DAMPING] += kinetic
        held[b] = 1  # (asleep: held with calm_since set)
        changed = True
    return changed


@inline_kernel()
def _log_event(rec, t, bi, bj, kind):
    k = rec.ev_n[0]
    rec.ev_time[k] = t
    rec.ev_i[k] = bi
    rec.ev_j[k] = bj
    rec.ev_kind[k] = kind
    rec.ev_n[0] = k + 1


@inner_kernel(_nrt=False)
def _bookkeep(bodies, spheres, contacts, rec, settings, changes, lag, n, t):
    """The body-level onsets and ends of one driver's list of contact changes (``n`` rows
    of ``changes`` (K, 3) and ``lag`` (K,): contact_rows.log_change): held-body release,
    event log, pair statistics, touched bodies.  The sphere contacts list theirs
    (Recorder.changes), the box contacts theirs (boxes.changes, one per body pair: a pair
    is in contact while any of its points is).

    Onsets are processed before ends, so that a body pair whose contact passes from one
    sphere or point to another in the same step (count 1 -> 2 -> 1) keeps one continuous
    contact.  Two held boxes have no contact rows (boxes.py), so a released box frees a
    held box it already overlaps one step later, at the onset of their first rows.  Event
    times are those of the list, within the step.  Returns whether a held body was
    released."""
    released = False
    for sweep in (ONSET, END):
        for k in range(n):
            kind = changes[k, 2]
            if kind != sweep:
                continue
            bi = changes[k, 0]
            j = changes[k, 1]
            if kind == ONSET and j >= 0 and bodies.held[bi] != bodies.held[j]:
                _release(bodies, spheres, contacts, bi if bodies.held[bi] else j, t)
                released = True
            if not settings.record_pairs:
                continue
            te = t - lag[k]
            if j >= 0:
                _count_pair_change(rec, bi, j, kind, te, t)
            else:
                _count_wall_change(rec, bi, j, kind, te)
    return released


@inner_kernel(_nrt=False)
def _count_pair_change(rec, bi, bj, kind, te, t):
    """A contact of bodies ``bi`` and ``bj`` began (``kind`` ONSET) or ended at ``te`` [s]
    (step time ``t``): the pair's count of touching contacts; its first onset and its
    last end are the body pair's events (log, pair statistics, touched bodies)."""
    a = min(bi, bj)
    b = max(bi, bj)
    if kind == ONSET:
        rec.pair_count[a, b] += 1
        if rec.pair_count[a, b] == 1:
            _log_event(rec, te, a, b, ONSET)
            rec.n_contacts[a, b] += 1
            if math.isnan(rec.first_contact[a, b]):
                rec.first_contact[a, b] = te
            rec.last_onset[0] = t
            rec.touched[a] = 1
            rec.touched[b] = 1
    else:
        rec.pair_count[a, b] -= 1
        if rec.pair_count[a, b] == 0:
            _log_event(rec, te, a, b, END)
            rec.last_separation[a, b] = te


@inner_kernel(_nrt=False)
def _count_wall_change(rec, bi, j, kind, te):
    """A contact of body ``bi`` with wall ``-j - 1`` began or ended at ``te`` [s]: the
    count of its touching contacts; the first onset and the last end are logged."""
    w = -j - 1
    if kind == ONSET:
        rec.wall_count[bi, w] += 1
        if rec.wall_count[bi, w] == 1:
            _log_event(rec, te, bi, j, ONSET)
    else:
        rec.wall_count[bi, w] -= 1
        if rec.wall_count[bi, w] == 0:
            _log_event(rec, te, bi, j, END)


@inner_kernel(_nrt=False)
def _record_frame(bodies, rec, t, first_moving, stop_moving):
    """Append trajectory frame ``traj_n`` at time t [s]: the rows of the bodies of
    ``range(lo, hi)``, the span of the bodies that may have moved since the last frame
    (``rec.traj_span``, widened by :func:`_widen_span`) and of those moving now.

    A body outside it has been held since the last frame: it is where it was, at rest,
    so the frame leaves it out and it keeps its row of an earlier frame (the first frame
    of a run has every body: Simulation._start_run sets the span to all).  A chain held until
    touched then records its moving dominoes, not all of them (simulation.FrameRows)."""
    f = rec.traj_n[0]
    span = rec.traj_span
    lo = min(span[0], first_moving)
    hi = max(span[1], stop_moving, lo)  # (lo: no body moved, an empty frame)
    row = rec.traj_start[f] - lo
    for b in range(lo, hi):
        for k in range(3):
            rec.traj_pos[row + b, k] = bodies.pos[b, k]
            rec.traj_vel[row + b, k] = bodies.vel_full[b, k]
            rec.traj_omega[row + b, k] = bodies.omega_full[b, k]
        for k in range(4):
            rec.traj_quat[row + b, k] = bodies.quat[b, k]
    rec.traj_t[f] = t
    rec.traj_first[f] = lo
    rec.traj_start[f + 1] = row + hi
    rec.traj_n[0] = f + 1
    span[0], span[1] = first_moving, stop_moving


@inline_kernel()
def _widen_span(rec, first_moving, stop_moving):
    """The moving bodies changed (a release or a sleep): the next frame records the new
    ``range(first_moving, stop_moving)`` too (``rec.traj_span``, :func:`_record_frame`)."""
    rec.traj_span[0] = min(rec.traj_span[0], first_moving)
    rec.traj_span[1] = max(rec.traj_span[1], stop_moving)


@inner_kernel()
def _record_contact_forces(contacts, rec):
    """Append the touching sphere contacts of this step as the rows of trajectory frame
    traj_n (contact_rows.rows_contact_forces)."""
    k0 = rec.cf_n[0]
    rec.cf_start[rec.traj_n[0]] = k0
    rec.cf_n[0] = k0 + rows_contact_forces(
        contacts, 0, 0, rec.cf_first[k0:], rec.cf_second[k0:], rec.cf_point[k0:],
        rec.cf_force[k0:],
    )  # fmt: skip


@inner_kernel()
def _record_box_contact_forces(rec, boxes):
    """Append the touching box contact points of this step to trajectory frame traj_n,
    after its sphere contacts (boxes.box_contact_forces)."""
    k0 = rec.cf_n[0]
    rec.cf_n[0] = k0 + box_contact_forces(
        boxes,
        rec.cf_first[k0:],
        rec.cf_second[k0:],
        rec.cf_point[k0:],
        rec.cf_force[k0:],
    )


@inline_kernel()
def _zero_forces(bodies):
    """Zero the force and torque of every body, as compute_forces does first.  For the
    steps without sphere pairs the loop does this itself: a call of a compiled function
    passes every array of its tuple arguments one by one (benchmarks/README.md,
    "Rounded-cuboid contacts", item (8))."""
    bodies.force[:, :] = 0.0
    bodies.torque[:, :] = 0.0


@inner_kernel(_nrt=False)
def _finite(bodies):
    for b in range(bodies.mass.shape[0]):
        for k in range(3):
            if not math.isfinite(bodies.pos[b, k]) or not math.isfinite(bodies.vel[b, k]):
                return False
    return True


@njit(cache=True, error_model="numpy", _nrt=False)
def active_energy(e, track_energy):
    """Scale [J] of the energies that change in a run: kinetic, elastic and (tracked)
    dissipated; the runaway test allows half of its largest value.  A dissipated energy
    counts only where it is positive: a negative one is energy the engine created (an
    unstable dashpot books its work there), which must not widen the slack meant to
    catch it."""
    active = abs(e[E_KINETIC_TRANSLATIONAL]) + abs(e[E_KINETIC_ROTATIONAL])
    active += abs(e[E_ELASTIC_NORMAL]) + abs(e[E_ELASTIC_TANGENTIAL])
    if track_energy:
        active += max(e[E_DISSIPATED_FRICTION], 0.0) + max(e[E_DISSIPATED_VISCOUS], 0.0)
        active += max(e[E_DISSIPATED_DAMPING], 0.0)
    return active


@njit(cache=True, error_model="numpy", _nrt=False)
def energy_excess(e, ref, track_energy):
    """How far the energy balance is off [J] (``e``, ``ref``: the ENERGY_NAMES vectors now
    and at the start of the run): the growth of the mechanical energy (kinetic +
    gravitational + elastic), which every non-conservative force of the engine (Coulomb
    slip, dashpots, local damping) can only decrease; with the ledger also ``|total -
    total_ref|``, conserved up to the integration error (the larger of the two: a
    blow-up whose work the ledger books as negative dissipation keeps the total but not
    the mechanical energy).  NaN if any energy is NaN or infinite."""
    mech = 0.0
    mech_ref = 0.0
    for k in range(N_MECHANICAL):
        mech += e[k]
        mech_ref += ref[k]
    excess = mech - mech_ref
    if track_energy:
        excess = max(excess, abs(e[E_TOTAL] - ref[E_TOTAL]))
    if not math.isfinite(excess) or not math.isfinite(mech):
        return math.nan
    return excess


@inline_kernel()
def quiet_reached(t, dt, since, quiet):
    """The quiet stop (``StopCondition.no_onset_for``): True if the step that starts at
    ``t`` [s] and lasts ``dt`` [s] ends at least ``quiet`` [s] after ``since`` [s] (the
    last body-body contact onset, or the start of the counting)."""
    return t + dt - since >= quiet


@njit(cache=True, error_model="numpy")
def _steps_until_quiet(t0, dt, since, quiet, limit):
    t = t0
    for k in range(limit):
        if quiet_reached(t, dt, since, quiet):
            return k + 1
        t = t + dt  # (the run loop's clock: one addition per step)
    return -1


def steps_until_quiet(t0: float, dt: float, since: float, quiet: float, limit: int) -> int | None:
    """Steps from time ``t0`` after which :func:`quiet_reached` first holds, or None.

    The run loop decides the quiet stop at the end of the step that starts at ``t`` and
    then advances its clock by ``t <- t + dt``; this walks the same clock with the same
    test (no onset assumed) for at most ``limit`` steps [s, s, s, s, -]: a caller that
    counts quiet time across several runs caps each run here (chain.stepper).
    """
    n = _steps_until_quiet(float(t0), float(dt), float(since), float(quiet), int(limit))
    return None if n < 0 else int(n)


@inline_kernel(python_entry=True)
def _moving_range(bodies):
    """``(first, stop)``: the bodies that are not held all lie in ``range(first, stop)``
    (empty if every body is held).  In a chain held until touched the moving dominoes
    are the first ones, so the fused pass (:func:`_body_pass`) looks at those and
    not at every held domino after them."""
    held = bodies.held
    first, stop = held.shape[0], 0
    for b in range(held.shape[0]):
        if not held[b]:
            first = min(first, b)
            stop = b + 1
    return first, stop


def _body_pass(PLANAR):  # (capital: a constant of the compiled kernel)
    """The fused kick and drift of a scene of the kind ``PLANAR`` (one source, compiled
    once for each kind, as contact._sphere_driver).

    Kick and drift in one pass over the bodies, for the steps in which nothing reads the
    state between the two (the same arithmetic as :func:`kick` then :func:`drift`: each
    body's update is independent of the others, and its data stays in registers); the
    Verlet-list test of the next step (:func:`needs_rebuild`) is done on the way, for the
    bodies that are not held: a held body has not moved since the last build (it is
    fixed, and the first step of a run tests every body).  Only the bodies of
    ``range(first, stop)`` are looked at, which holds every body that is not held
    (:func:`_moving_range`).  A planar scene's pass gives the same results with fewer
    operations, and without the full-step quantities that nothing reads in these steps
    (integrate.advance_body_planar).  Returns whether the list must be rebuilt."""

    @inner_kernel(_nrt=False)
    def advance_bodies(bodies, settings, first, stop):
        half_skin = 0.5 * settings.skin
        g, dt = settings.gravity, settings.dt
        damping, damp_gravity = settings.damping, settings.damp_gravity
        rebuild = False
        held = bodies.held
        for b in range(first, stop):
            if held[b]:  # (a held body does not move: nothing to advance or test)
                continue
            if PLANAR:
                advance_body_planar(bodies, b, g, dt, damping, damp_gravity)
            else:
                kick_body(bodies, b, g, dt, damping, damp_gravity)
                drift_body(bodies, b, dt)
            if not rebuild:
                rebuild = moved_beyond(bodies, b, half_skin)
        return rebuild

    return advance_bodies


_advance_general = _body_pass(False)
_advance_planar = _body_pass(True)


@njit(cache=True, error_model="numpy", _nrt=False)
def _advance_bodies(bodies, settings, first, stop):
    """The fused kick and drift of the scene's kind (``settings.planar``):
    :func:`_advance_planar` or :func:`_advance_general` (for the tests and benchmarks;
    the time loop calls its kind's)."""
    if settings.planar:
        return _advance_planar(bodies, settings, first, stop)
    return _advance_general(bodies, settings, first, stop)


SceneKind = namedtuple("SceneKind", ["planar", "boxes", "spheres"], defaults=(True,))
"""What a scene holds, which decides the kernels its time loop calls (bools): ``planar``
(the planar kernels, contact._sphere_driver, _body_pass, boxes._box_driver and
boxes._box_sphere_pass, or the general ones), ``boxes`` (rounded-cuboid contacts:
boxes.py) and ``spheres`` (sphere contacts: contact.py, and with boxes the box-sphere
points of boxes.py and their list, box_sphere.py; default True).  A scene of boxes
alone (every box chain) compiles no sphere kernel (benchmarks/README.md, "First run")."""


@functools.cache
def time_loop(kind: SceneKind):
    """The compiled time loop of a scene of ``kind`` (:class:`SceneKind`): :func:`run_loop`
    with the kernels of what the scene holds, and without the others.

    numba compiles a function with every function it calls, and in a loop that branches
    on the scene at run time that is every kernel of the engine (benchmarks/README.md,
    "First run").  Here the kind is a constant of the
    compiled function (a closure variable): numba removes the branches of the other
    kinds before it types the loop, so a clump chain compiles no box kernel and a planar
    scene no general one.  Each kind has its own entry in the disk cache (numba keys a
    closure's cache entry by the values it closes over).  The steps are the same
    arithmetic in every kind: a kind drops only calls that would have done nothing.
    """
    kind = SceneKind(*(bool(flag) for flag in kind))
    return _compile_run_loop(*kind)


def _compile_run_loop(PLANAR, BOXES, SPHERES):  # (capitals: constants of the compiled loop)
    """:func:`run_loop` for the kind ``(PLANAR, BOXES, SPHERES)`` (:func:`time_loop`).

    The flags are tested by name in every ``if`` (numba prunes a branch whose condition
    is a constant; it does not follow a constant through a variable or a ``not``)."""

    @njit(cache=True, error_model="numpy", _nrt=False)
    def run_loop(
        bodies, spheres, walls, mats, contacts, settings, rec, n_steps, t_end, stop, work, boxes
    ):
        """Advance up to ``n_steps`` steps or until ``time >= t_end`` or a stop condition.

        ``stop`` = (no_onset_for [s] or inf, touched_body or -1, kinetic_below [J] or -1,
        start time of the run [s], 1 to stop at rest or 0; entries STOP_ARG_*).
        ``work``: (2, 3) scratch array (rows WORK_*).  ``boxes``: the rounded-cuboid
        bodies and their contacts (boxes.py; zero-length without).  Returns
        ``(code, steps_done)``; see the module constants.
        Every sphere is at its place on its body when it returns (``spheres.pos``; the
        steps place only those of the Verlet list).
        ``rec.energy_now`` holds the energies of the last step done (time
        ``clock[CLOCK_TIME] - dt``).
        Compiled without numba's reference counting (dem/compiled.py): it allocates
        nothing, and it holds about 100 state arrays.
        """
        dt, skin = settings.dt, settings.skin
        ledger, changes, change_lag = rec.ledger, rec.changes, rec.change_lag
        kin = work[WORK_KINETIC]
        p_contacts = work[WORK_POWER]
        touched_body = int(stop[STOP_ARG_TOUCHED_BODY])
        shear_kinematics = mats.shear_kinematics[0]
        if BOXES:  # (the caller may have changed the held flags)
            held_flags_changed(bodies, boxes)
        rebuild_due = needs_rebuild(bodies, skin, contacts.n[0])
        # (in here only a release or a sleep changes the held flags)
        first_moving, stop_moving = _moving_range(bodies)
        outcome, steps = DONE_STEPS, n_steps
        for done in range(n_steps):
            t = rec.clock[CLOCK_TIME]
            if t >= t_end - 0.5 * dt:
                outcome, steps = DONE_TIME, done
                break
            last = done == n_steps - 1 or t + dt >= t_end - 0.5 * dt
            # room for this step's records, otherwise hand back to Python before changing
            # state
            room = contacts.i.shape[0]
            cf_room = contacts.i.shape[0]
            if BOXES:
                room += boxes.changes.shape[0]
                cf_room += boxes.rows.i.shape[0] + boxes.dormant.i.shape[0]
            if settings.record_pairs and rec.ev_time.shape[0] - rec.ev_n[0] < room:
                outcome, steps = GROW_EVENTS, done
                break
            step = rec.step[0]
            traj_due = rec.traj_every[0] > 0 and step % rec.traj_every[0] == 0
            energy_due = rec.energy_every[0] > 0 and step % rec.energy_every[0] == 0
            if traj_due and (
                rec.traj_n[0] == rec.traj_t.shape[0]
                or rec.traj_pos.shape[0] - rec.traj_start[rec.traj_n[0]] < bodies.mass.shape[0]
            ):
                outcome, steps = GROW_TRAJECTORY, done
                break
            if energy_due and rec.energy_n[0] == rec.energy_t.shape[0]:
                outcome, steps = GROW_ENERGY, done
                break
            forces_due = traj_due and rec.cf_on[0] == 1
            if forces_due and rec.cf_first.shape[0] - rec.cf_n[0] < cf_room:
                outcome, steps = GROW_CONTACT_FORCES, done
                break
            build_due = rebuild_due
            if BOXES:
                if SPHERES:
                    build_due = build_due or min(boxes.n_cand[0], boxes.n_sphere_cand[0]) < 0
                else:
                    build_due = build_due or boxes.n_cand[0] < 0
            if build_due:
                if not _finite(bodies):
                    outcome, steps = ABORT_NAN, done
                    break
                if SPHERES:
                    update_sphere_positions(bodies, spheres, PLANAR)  # (the search sees all)
                    if build_verlet_list(spheres, walls, bodies, mats, contacts, skin) < 0:
                        outcome, steps = GROW_CONTACTS, done
                        break
                else:
                    mark_build(bodies)  # (what build_verlet_list does without spheres)
                rec.n_rebuilds[0] += 1
                # (the box list with the spheres': both rely on the same displacement test)
                if BOXES:
                    if build_box_candidates(bodies, boxes, walls, skin) < 0:
                        outcome, steps = GROW_BOX_CANDIDATES, done
                        break
                    if SPHERES:
                        if build_box_sphere_candidates(bodies, spheres, boxes, walls, skin) < 0:
                            outcome, steps = GROW_BOX_CANDIDATES, done
                            break
            first = step == 0
            if SPHERES and contacts.n[0] > 0:
                sphere_forces = compute_forces_planar if PLANAR else compute_forces
                n_changes = sphere_forces(
                    bodies, spheres, walls, contacts, dt, ledger, changes, change_lag, first,
                    shear_kinematics,
                )  # fmt: skip
            else:  # (no sphere pairs listed, or no spheres at all)
                _zero_forces(bodies)  # (compute_forces' first act: a call costs more)
                n_changes = 0
            released = False
            if BOXES:  # (the choice inside: a loop without boxes compiles no box driver)
                if SPHERES:
                    box_forces = box_forces_planar_spheres if PLANAR else box_forces_general_spheres
                else:
                    box_forces = box_forces_planar if PLANAR else box_forces_general
                box_forces(bodies, spheres, boxes, walls, mats, dt, ledger, first)
                if boxes.n_changes[0] > 0:
                    released = _bookkeep(
                        bodies, spheres, contacts, rec, settings, boxes.changes,
                        boxes.change_lag, boxes.n_changes[0], t,
                    )  # fmt: skip
            if SPHERES and n_changes > 0:
                released |= _bookkeep(
                    bodies, spheres, contacts, rec, settings, changes, change_lag, n_changes, t
                )
            if released:  # (the held flags changed)
                first_moving, stop_moving = _moving_range(bodies)
                _widen_span(rec, first_moving, stop_moving)
                if BOXES:
                    held_flags_changed(bodies, boxes)
            if settings.record_peak_force:
                if SPHERES:
                    rows_peak_force(contacts, spheres.body, spheres.body, rec.peak_force)
                if BOXES:
                    box_peak_force(boxes, rec.peak_force)
            # stop conditions, decided at t_n
            code = -1
            if touched_body >= 0 and rec.touched[touched_body]:
                code = STOP_TOUCHED
            elif quiet_reached(
                t, dt, max(rec.last_onset[0], stop[STOP_ARG_RUN_START]), stop[STOP_ARG_QUIET]
            ):
                code = STOP_NO_ONSET
            elif stop[STOP_ARG_AT_REST] > 0.0 and first_moving >= stop_moving:
                # every body is held (untouched or asleep) and the walls stand still:
                # nothing moves again.  Stopped at a frame, the record ends at rest.
                if traj_due or rec.traj_every[0] == 0:
                    code = STOP_AT_REST
            # (the checks of a run's last step test its end state; a sleep decision waits
            # for the steps that are check steps in every run, so that where runs begin
            # and end changes no bit: advance(a); advance(b) == advance(a + b))
            sleep_due = (step + 1) % settings.check_every == 0
            check_due = sleep_due or last or code >= 0
            if not (traj_due or energy_due or check_due or settings.track_energy):
                # nothing reads the state between kick and drift: one pass over the bodies
                advance = _advance_planar if PLANAR else _advance_general
                rebuild_due = advance(bodies, settings, first_moving, stop_moving)
            else:
                g, damp_gravity = settings.gravity, settings.damp_gravity
                kick = kick_planar if PLANAR else kick_general
                p_damping = kick(
                    bodies, g, dt, settings.damping, damp_gravity, first_moving, stop_moving
                )
                if settings.track_energy:
                    p_contacts[POWER_VISCOUS] = 0.0
                    p_contacts[POWER_FRICTION] = 0.0
                    if SPHERES:
                        rows_power(bodies, contacts, spheres.body, spheres.body, p_contacts)
                    if BOXES:
                        box_power(bodies, boxes, p_contacts)
                    # trapezoidal rule for the work of the non-conservative forces since
                    # t_{n-1}
                    if step > 0:
                        viscous = rec.power[LAST_POWER_VISCOUS] + p_contacts[POWER_VISCOUS]
                        damping = rec.power[LAST_POWER_DAMPING] + p_damping
                        friction = rec.power[LAST_POWER_FRICTION] + p_contacts[POWER_FRICTION]
                        ledger[LEDGER_VISCOUS] -= 0.5 * dt * viscous
                        ledger[LEDGER_DAMPING] -= 0.5 * dt * damping
                        ledger[LEDGER_FRICTION] -= 0.5 * dt * friction
                    rec.power[LAST_POWER_VISCOUS] = p_contacts[POWER_VISCOUS]
                    rec.power[LAST_POWER_DAMPING] = p_damping
                    rec.power[LAST_POWER_FRICTION] = p_contacts[POWER_FRICTION]
                if forces_due:  # (before _record_frame: the frame index is traj_n)
                    if SPHERES:
                        _record_contact_forces(contacts, rec)
                    else:  # (the frame's rows start with its box rows)
                        rec.cf_start[rec.traj_n[0]] = rec.cf_n[0]
                    if BOXES:
                        _record_box_contact_forces(rec, boxes)
                if traj_due:
                    _record_frame(bodies, rec, t, first_moving, stop_moving)
                if energy_due:
                    k = rec.energy_n[0]
                    rec.energy_t[k] = t
                    energies(bodies, contacts, settings.gravity, ledger, rec.energy_val[k])
                    if BOXES:
                        box_energies(boxes, rec.energy_val[k])
                    rec.energy_n[0] = k + 1
                # sanity checks at t_n, before the drift
                if check_due:
                    energies(bodies, contacts, settings.gravity, ledger, rec.energy_now)
                    if BOXES:
                        box_energies(boxes, rec.energy_now)
                    if not _finite(bodies):
                        outcome, steps = ABORT_NAN, done
                        break
                    rec.clock[CLOCK_ENERGY_SCALE] = max(
                        rec.clock[CLOCK_ENERGY_SCALE],
                        active_energy(rec.energy_now, settings.track_energy),
                    )
                    slack = 0.5 * rec.clock[CLOCK_ENERGY_SCALE]
                    slack += 1e-9 * abs(rec.energy_ref[E_GRAVITATIONAL])
                    excess = energy_excess(rec.energy_now, rec.energy_ref, settings.track_energy)
                    # (not `excess > slack`: an overflowing energy reads NaN, and NaN > x is
                    # False)
                    if not excess <= slack:
                        outcome, steps = ABORT_RUNAWAY, done
                        break
                    if code < 0 and stop[STOP_ARG_KINETIC_BELOW] >= 0.0:
                        kinetic_energy(bodies, kin)
                        kinetic = kin[E_KINETIC_TRANSLATIONAL] + kin[E_KINETIC_ROTATIONAL]
                        if kinetic < stop[STOP_ARG_KINETIC_BELOW]:
                            code = STOP_KINETIC
                if BOXES:
                    slept = False
                    if settings.sleep_speed > 0.0 and sleep_due:
                        slept = _sleep_and_wake(
                            bodies, spheres, contacts, boxes, settings, t, ledger
                        )
                    if slept:  # (the held flags changed)
                        first_moving, stop_moving = _moving_range(bodies)
                        _widen_span(rec, first_moving, stop_moving)
                        held_flags_changed(bodies, boxes)
                drift = drift_planar if PLANAR else drift_general
                drift(bodies, dt, first_moving, stop_moving)
                rebuild_due = needs_rebuild_after_drift(
                    bodies, skin, contacts.n[0], first_moving, stop_moving
                )
            if SPHERES:
                update_listed_sphere_positions(bodies, spheres, PLANAR)
            rec.clock[CLOCK_TIME] = t + dt
            rec.step[0] = step + 1
            if code >= 0:
                outcome, steps = code, done + 1
                break
        # the loop moves only the spheres of the Verlet list: place all for Python (not
        # before the first step: the spheres still sit at the scene's centres, which the
        # first step uses, and which differ from the placed ones by round-off)
        if SPHERES and rec.step[0] > 0:
            update_sphere_positions(bodies, spheres, PLANAR)
        return outcome, steps

    return run_loop
