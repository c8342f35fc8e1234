"""Compiled time loop of the hinged-domino chain (velocity Verlet, fixed step).

One angle per domino. Each step: half kick, drift, floor, forces (gravity + every
neighbour contact, the pure per-pair laws of :mod:`dominowave.rods.contact`), half kick,
then the measurements. The loop runs in compiled code, in resumable pieces: the whole
state of a run is a :class:`ChainState` of arrays, :func:`new_state` sets it up at
``t = 0`` and :func:`advance` integrates it by a given number of steps in place, so a
run cut into pieces (and saved and restored in between) does exactly the arithmetic of
one uninterrupted run.

Contact slots: three per domino ``i``
    0: front top edge of ``i``   against the back face  of ``i+1`` (the paper's collision);
    1: back top edge of ``i+1``  against the front face of ``i``   (``i+1`` swinging back);
    2: front top edge of ``i``   against the back face  of ``i+2`` (skipping a neighbour).
A contact starts when the overlap of a slot changes sign from <= 0 to > 0 with the
corner inside the face's extent ``0 <= w <= l`` and ends when the overlap returns to
<= 0 (or the corner slides off the face). Onset and end times are located inside the
step by *linear interpolation of the overlap* between the two step ends; the angular
velocities at those instants by linear interpolation between the full-step values.

Standing rule (exact skipping of dominoes ahead of the wave): a domino that has never
been touched stands at ``theta = 0, omega = 0``. For ``s = 0`` that is an exact (unstable)
equilibrium: gravity's torque ``m g r sin(0)`` is exactly zero in floating point, so a
thin domino stays upright forever unless touched; for ``s > 0`` it rests on the floor
under its back edge (stable). Either way, integrating it would return exactly the same
numbers, so dominoes beyond the first untouched one (``n_awake``) are not integrated
until a contact reaches them.

Floor: a rigid unilateral stop at ``theta = pi/2`` (flat on its face) and, behind, at
``theta = -pi/2`` for ``s = 0`` or ``theta = 0`` for ``s > 0`` (a block rocking back
onto its base; the hinge stays at the front edge, so a block cannot rock on its rear
edge). An impact reverses the angular velocity times ``e_floor``; a domino resting on
a stop with a torque pushing into it stays there. The change of kinetic + gravitational
energy at the floor is book-kept as ``E_floor``.
"""

from __future__ import annotations

import math
from typing import NamedTuple, get_type_hints

import numpy as np
from numba import njit

from dominowave.rods.contact import (
    corner_face_overlap,
    coulomb_friction,
    damping_coefficient,
    hertz_energy,
    hertz_force,
    linear_energy,
    linear_force,
)

LAW_LINEAR = 0
LAW_HERTZ = 1
NORMAL_GEOMETRIC = 0
NORMAL_HEAD_ON = 1

STATUS_START = -2  # forces at t = 0 not evaluated yet
STATUS_RUNNING = -1
STATUS_WAVE_PASSED = 0
STATUS_TIME_LIMIT = 1
STATUS_STALLED = 2
STATUS_BLOW_UP = 3

# columns of the event table (float64, one row per contact)
EV_LOWER, EV_UPPER, EV_KIND, EV_T_ON, EV_T_OFF, EV_F_MAX = 0, 1, 2, 3, 4, 5
EV_W_LO_ON, EV_W_UP_ON, EV_W_LO_OFF, EV_W_UP_OFF = 6, 7, 8, 9
EV_HV_UP, EV_STEPS, EV_DELTA_MAX = 10, 11, 12
EV_COLUMNS = 13

# columns of the energy samples
SA_T, SA_KIN, SA_GRAV, SA_ELASTIC, SA_DISSIPATED, SA_FLOOR = 0, 1, 2, 3, 4, 5
SA_COLUMNS = 6


@njit(cache=True)
def _gravity_height(c, sn, cm_u, cm_w):
    """Height of the centre of mass [m] for ``cos``/``sin`` of the angle."""
    return -cm_u * sn + cm_w * c


@njit(cache=True)
def _slot_geometry(kind, i, l, s):
    """(corner domino, face domino, corner u0, corner w0, face u, sigma) of a slot."""
    if kind == 0:
        return i, i + 1, 0.0, l, -s, -1.0
    if kind == 1:
        return i + 1, i, -s, l, 0.0, 1.0
    return i, i + 2, 0.0, l, -s, -1.0


class ChainParams(NamedTuple):
    """Fixed parameters of a run (SI units); build with :meth:`typed`."""

    l: float  # domino height [m]
    s: float  # thickness [m]
    pitch: float  # hinge spacing d + s [m]
    m: float  # mass [kg]
    inertia: float  # moment of inertia about the hinge [kg m^2]
    cm_u: float  # centre of mass in body coordinates [m]
    cm_w: float
    g: float  # gravity [m/s^2]
    law: int  # LAW_LINEAR or LAW_HERTZ
    k: float  # contact stiffness [N/m] (linear) or [N/m^1.5] (Hertz)
    zeta: float  # damping ratio of the contact dashpot
    mu: float  # Coulomb friction coefficient
    v_reg: float  # regularisation speed of the friction [m/s]
    normal: int  # NORMAL_GEOMETRIC or NORMAL_HEAD_ON
    e_floor: float  # restitution of a floor impact
    gravity_in_contact: bool  # False: no gravity on a domino in contact (section 2.2)
    dt: float  # time step [s]
    t_max: float  # end of the run at the latest [s]
    stall_time: float  # stop if no new domino was reached for this long [s]
    tail_time: float  # keep running this long after the wave passed [s]
    sample_every: int  # steps between energy samples
    frame_every: int  # steps between frames (0: no frames)

    @classmethod
    def typed(cls, *values) -> ChainParams:
        """The parameters in field order, each cast to its field's type.

        Python ints where floats belong would make numba compile a second version of
        the kernel (with other arithmetic); the cast makes the signature unique.
        """
        types = get_type_hints(cls)
        return cls(*(types[f](v) for f, v in zip(cls._fields, values, strict=True)))


class ChainState(NamedTuple):
    """Everything the future of a run depends on; :func:`advance` updates it in place.

    ``N`` dominoes, ``3N`` contact slots (``slot = 3 i + kind``). Scalars are shape
    ``(1,)`` arrays so that they too change in place. The records (``events``,
    ``samples``, frames) are filled up to their counters; the rest is NaN.
    """

    # mechanics (velocity Verlet carries the generalised forces at the current angles)
    theta: np.ndarray  # (N,) angles [rad]
    omega: np.ndarray  # (N,) angular velocities [rad/s]
    torque: np.ndarray  # (N,) generalised forces at theta [N m]
    step: np.ndarray  # (1,) int64: steps done; the time is step * dt
    status: np.ndarray  # (1,) int64: STATUS_*
    n_awake: np.ndarray  # (1,) int64: dominoes integrated (the standing rule)
    # contact slots, (3N,)
    active: np.ndarray  # bool: in contact
    gap_prev: np.ndarray  # last overlap [m] (geometric, or along xi when head-on)
    slot_event: np.ndarray  # int64: row of its contact in events (-1: none)
    xi_x: np.ndarray  # head-on axis [-]
    xi_y: np.ndarray
    u_hit: np.ndarray  # head-on anchor on the struck domino (body coordinates) [m]
    w_hit: np.ndarray
    head_on: np.ndarray  # bool: this contact uses the head-on law
    touched: np.ndarray  # bool: the slot has had a contact
    handover: np.ndarray  # bool: head-on spring unloaded inside the face
    # stop conditions
    t_last_arrival: np.ndarray  # (1,) time a new domino was last reached [s]
    t_stop: np.ndarray  # (1,) end of the run as known now [s]
    first_strike_done: np.ndarray  # (N,) bool: the domino's first contact has ended
    # records
    events: np.ndarray  # (max_events, EV_COLUMNS)
    n_events: np.ndarray  # (1,) int64: contacts so far (may exceed max_events)
    samples: np.ndarray  # (max_samples, SA_COLUMNS)
    n_samples: np.ndarray  # (1,) int64
    frame_t: np.ndarray  # (max_frames,) [s]
    frame_theta: np.ndarray  # (max_frames, N) [rad]
    frame_omega: np.ndarray  # (max_frames, N) [rad/s]
    n_frames: np.ndarray  # (1,) int64
    arrival: np.ndarray  # (N,) first contact time with a lower domino [s]
    hv_max: np.ndarray  # (N,) peak |H|/V of the base reaction
    lift_steps: np.ndarray  # (N,) int64: steps with V <= 0
    theta_min_after: np.ndarray  # (N,) smallest angle after the first strike [rad]
    e_diss: np.ndarray  # (1,) energy dissipated by dashpots and friction [J]
    e_floor_loss: np.ndarray  # (1,) energy lost at floor stops [J]


RECORDS = {
    "events": "n_events",
    "samples": "n_samples",
    "frame_t": "n_frames",
    "frame_theta": "n_frames",
    "frame_omega": "n_frames",
}
"""Record buffers of :class:`ChainState` and the counters of their filled rows."""


def new_state(p: ChainParams, theta, omega, n_awake, max_events, max_samples, max_frames):
    """The state at ``t = 0``: ``theta``, ``omega`` (``(N,)`` float64, used in place).

    Dominoes from ``n_awake`` on are not integrated until a contact reaches them (the
    standing rule). The forces at ``t = 0`` are evaluated (contacts already closed at
    the start are recorded with onset 0); frame 0 is the initial state.
    """
    n = theta.shape[0]
    st = ChainState(
        theta=theta,
        omega=omega,
        torque=np.zeros(n),
        step=np.array([0], dtype=np.int64),
        status=np.array([STATUS_START], dtype=np.int64),
        n_awake=np.array([n_awake], dtype=np.int64),
        active=np.zeros(3 * n, dtype=np.bool_),
        gap_prev=np.full(3 * n, -1.0 * p.l),
        slot_event=np.full(3 * n, -1, dtype=np.int64),
        xi_x=np.zeros(3 * n),
        xi_y=np.zeros(3 * n),
        u_hit=np.zeros(3 * n),
        w_hit=np.zeros(3 * n),
        head_on=np.zeros(3 * n, dtype=np.bool_),
        touched=np.zeros(3 * n, dtype=np.bool_),
        handover=np.zeros(3 * n, dtype=np.bool_),
        t_last_arrival=np.zeros(1),
        t_stop=np.full(1, p.t_max),
        first_strike_done=np.zeros(n, dtype=np.bool_),
        events=np.full((max_events, EV_COLUMNS), np.nan),
        n_events=np.array([0], dtype=np.int64),
        samples=np.full((max_samples, SA_COLUMNS), np.nan),
        n_samples=np.array([0], dtype=np.int64),
        frame_t=np.full(max_frames, np.nan),
        frame_theta=np.full((max_frames, n), np.nan),
        frame_omega=np.full((max_frames, n), np.nan),
        n_frames=np.array([0], dtype=np.int64),
        arrival=np.full(n, np.nan),
        hv_max=np.zeros(n),
        lift_steps=np.zeros(n, dtype=np.int64),
        theta_min_after=np.full(n, np.nan),
        e_diss=np.zeros(1),
        e_floor_loss=np.zeros(1),
    )
    st.arrival[0] = 0.0
    if p.frame_every > 0 and max_frames > 0:
        st.frame_t[0] = 0.0
        st.frame_theta[0, :] = theta
        st.frame_omega[0, :] = omega
        st.n_frames[0] = 1
    advance(p, st, 0)  # only the forces at t = 0
    return st


# --------------------------------------------------------------------------- per-step pieces
# The time loop (:func:`advance`) keeps its loops over dominoes and contact slots in one
# function; what a loop does for one domino or one contact is a function of scalars
# (compiled into the loop), and what happens rarely (a contact starting, an energy
# sample, a frame) a function of the few arrays it writes.


@njit(cache=True)
def _floor_impact(theta, omega, theta_hi, theta_lo, e_floor, inertia, m, g, cm_u, cm_w):
    """A domino whose drift took it past a floor stop: put it on the stop and reverse its
    angular velocity times ``e_floor``.  Returns (theta [rad], omega [rad/s], the kinetic
    + gravitational energy lost [J])."""
    stop = theta_hi if theta > theta_hi else theta_lo
    e_before = 0.5 * inertia * omega * omega + m * g * _gravity_height(
        math.cos(theta), math.sin(theta), cm_u, cm_w
    )
    omega = -e_floor * omega
    e_after = 0.5 * inertia * omega * omega + m * g * _gravity_height(
        math.cos(stop), math.sin(stop), cm_u, cm_w
    )
    return stop, omega, e_before - e_after


@njit(cache=True)
def _open_event(events, ev, lo, up, kind, t_on):
    """Row ``ev`` of the event table: a contact of dominoes ``lo < up`` in slot ``kind``
    that started at ``t_on`` [s]."""
    events[ev, EV_LOWER] = lo
    events[ev, EV_UPPER] = up
    events[ev, EV_KIND] = kind
    events[ev, EV_T_ON] = t_on
    events[ev, EV_F_MAX] = 0.0
    events[ev, EV_HV_UP] = 0.0
    events[ev, EV_STEPS] = 0.0
    events[ev, EV_DELTA_MAX] = 0.0


@njit(cache=True)
def _head_on_anchor(delta, w, u, ga, dpx, dpy, cb, sb):
    """Axis and anchor of a head-on contact at its onset: the axis xi along the path of
    the striking corner (``dp`` its derivative by the striker's angle, ``ga`` that of the
    overlap), oriented into the face; the anchor at the material point (body
    coordinates of the struck domino, angle cosine ``cb``, sine ``sb``) where the corner
    entered along xi, from the corner's face coordinates ``(u, w)`` and overlap ``delta``
    [m] (a grazing corner, ``|xi . n| < 1/4``, is anchored where it is: a far anchor
    would inject energy).  Returns (xi_x, xi_y, u_hit [m], w_hit [m])."""
    norm = math.sqrt(dpx * dpx + dpy * dpy)
    sgn = 1.0 if ga >= 0.0 else -1.0
    xi_x = sgn * dpx / norm
    xi_y = sgn * dpy / norm
    along = delta * norm / abs(ga) if 4.0 * abs(ga) >= norm else 0.0
    return xi_x, xi_y, u - along * (xi_x * cb - xi_y * sb), w - along * (xi_x * sb + xi_y * cb)


@njit(cache=True)
def _head_on_overlap(xb, cb, sb, uh, wh, nx, ny, px, py, dpx, dpy):
    """Overlap [m] of a head-on contact along its fixed axis ``xi = (nx, ny)``: the striking
    corner ``p`` (``dp`` its derivative by the striker's angle) against the anchor
    ``(uh, wh)`` (body coordinates) of the struck domino (hinge at ``xb``, angle cosine
    ``cb``, sine ``sb``).  Returns (delta, g_a, g_b) [m]: the overlap and its derivatives
    by the two angles (the lever arms of the force along xi)."""
    cx = xb + uh * cb + wh * sb
    cy = -uh * sb + wh * cb
    dcx = -uh * sb + wh * cb
    dcy = -uh * cb - wh * sb
    delta = nx * (px - cx) + ny * (py - cy)
    return delta, nx * dpx + ny * dpy, -(nx * dcx + ny * dcy)


@njit(cache=True)
def _normal_law(law, delta, delta_dot, k, zeta, reduced):
    """Normal force of a contact (the pure per-pair laws of :mod:`dominowave.rods.contact`):
    overlap ``delta`` [m] and its rate [m/s], stiffness ``k``, damping ratio ``zeta``,
    reduced mass ``reduced`` [kg].  Returns (force [N], its elastic part [N], the
    elastic energy [J])."""
    if law == LAW_LINEAR:
        c_d = damping_coefficient(zeta, k, reduced) if zeta > 0.0 else 0.0
        return linear_force(delta, delta_dot, k, c_d), k * delta, linear_energy(delta, k)
    sq = math.sqrt(delta)
    c_d = damping_coefficient(zeta, 1.5 * k * sq, reduced) if zeta > 0.0 else 0.0
    return hertz_force(delta, delta_dot, k, c_d), k * delta * sq, hertz_energy(delta, k)


@njit(cache=True)
def _elastic_energy(law, delta, k):
    """Elastic energy [J] of a contact of overlap ``delta`` [m]."""
    return linear_energy(delta, k) if law == LAW_LINEAR else hertz_energy(delta, k)


@njit(cache=True)
def _base_reaction(c, sn, torque, omega, inertia, m, g, cm_u, cm_w, fx, fy):
    """Base reaction (H, V) [N] of a domino at the angle of cosine ``c`` and sine ``sn``
    (generalised force ``torque`` [N m], angular velocity ``omega`` [rad/s], contact
    forces ``(fx, fy)`` [N] on it): ``R = m a_cm + (0, m g) - F_contact``."""
    alpha = torque / inertia
    w2 = omega * omega
    # r_c = cm_u e_u + cm_w e_w ; t_c = dr_c/dtheta = -cm_u e_w + cm_w e_u
    rcx = cm_u * c + cm_w * sn
    rcy = -cm_u * sn + cm_w * c
    tcx = -cm_u * sn + cm_w * c
    tcy = -cm_u * c - cm_w * sn
    h = m * (alpha * tcx - w2 * rcx) - fx
    v = m * (alpha * tcy - w2 * rcy) + m * g - fy
    return h, v


@njit(cache=True)
def _remove_gravity_in_contact(
    act_list, n_act, removed, torque, cos_t, sin_t, l, s, m, g, cm_u, cm_w
):
    """The theory's assumption switch (section 2.2): no gravity on a domino while it is in
    contact (non-physical: the energy ledger no longer closes).  ``act_list[:n_act]`` the
    active slots; ``removed`` (N,) bool scratch, all False on entry and on return."""
    for q in range(n_act):
        slot = act_list[q]
        i = slot // 3
        a, b, _, _, _, _ = _slot_geometry(slot - 3 * i, i, l, s)
        for j in (a, b):
            if not removed[j]:
                removed[j] = True
                torque[j] -= m * g * (cm_u * cos_t[j] + cm_w * sin_t[j])
    for q in range(n_act):
        slot = act_list[q]
        i = slot // 3
        a, b, _, _, _, _ = _slot_geometry(slot - 3 * i, i, l, s)
        removed[a] = False
        removed[b] = False


@njit(cache=True)
def _interpolate_pending(events, pend_ev, pend_end, pend_frac, n_pend, omega_old, omega):
    """The angular velocities of both dominoes at the onsets and ends of this step
    (``pend_*[:n_pend]``: event row, end or onset, fraction of the step), interpolated
    linearly between the full-step values ``omega_old`` and ``omega``."""
    for q in range(n_pend):
        ev = pend_ev[q]
        lo = int(events[ev, EV_LOWER])
        up = int(events[ev, EV_UPPER])
        fr = pend_frac[q]
        w_lo = omega_old[lo] + fr * (omega[lo] - omega_old[lo])
        w_up = omega_old[up] + fr * (omega[up] - omega_old[up])
        if pend_end[q]:
            events[ev, EV_W_LO_OFF] = w_lo
            events[ev, EV_W_UP_OFF] = w_up
        else:
            events[ev, EV_W_LO_ON] = w_lo
            events[ev, EV_W_UP_ON] = w_up


@njit(cache=True)
def _energy_sample(row, t, theta, omega, inertia, m, g, cm_u, cm_w, e_elastic, e_diss, e_floor):
    """One row of the energy samples (columns SA_*) at time ``t`` [s] [J]."""
    e_kin = 0.0
    e_grav = 0.0
    for i in range(theta.shape[0]):
        e_kin += 0.5 * inertia * omega[i] * omega[i]
        height = _gravity_height(math.cos(theta[i]), math.sin(theta[i]), cm_u, cm_w)
        e_grav += m * g * height
    row[SA_T] = t
    row[SA_KIN] = e_kin
    row[SA_GRAV] = e_grav
    row[SA_ELASTIC] = e_elastic
    row[SA_DISSIPATED] = e_diss
    row[SA_FLOOR] = e_floor


@njit(cache=True)
def _start_contact(st, pend, n_pend, slot, kind, a, b, t, dt, frac, normal):
    """A contact starts in ``slot`` (corner domino ``a``, face domino ``b``) at the
    fraction ``frac`` of the step that ends at ``t`` [s]: its event row (if there is
    room) and the onset queued in ``pend`` for the interpolation of the angular
    velocities, the arrival of the upper domino (waking it), the head-on flag of the slot
    (the head-on assumption describes the pair collision: the first contact of a slot;
    later contacts, leaning or re-collisions, are geometric).  Returns the new count of
    queued onsets and ends."""
    t_on = max(t - dt + frac * dt, 0.0)
    up = max(a, b)
    n_events = st.n_events[0]
    st.slot_event[slot] = -1
    if n_events < st.events.shape[0]:
        _open_event(st.events, n_events, min(a, b), up, kind, t_on)
        st.slot_event[slot] = n_events
        n_pend = _queue(pend, n_pend, n_events, False, frac)
    st.n_events[0] = n_events + 1
    if np.isnan(st.arrival[up]):
        st.arrival[up] = t_on
        st.t_last_arrival[0] = t
    if up >= st.n_awake[0]:
        st.n_awake[0] = up + 1
    if kind == 0 and np.isnan(st.theta_min_after[a]):
        st.theta_min_after[a] = st.theta[a]
    st.active[slot] = True
    st.head_on[slot] = normal == NORMAL_HEAD_ON and kind == 0 and not st.touched[slot]
    st.touched[slot] = True
    return n_pend


@njit(cache=True)
def _end_contact(st, pend, n_pend, slot, t, dt, delta, t_max, tail_time):
    """The contact of ``slot`` ended in the step that ends at ``t`` [s] (overlap now
    ``delta`` [m]): its end time, located by the linear interpolation of the overlap, the
    end queued in ``pend``, the end of the upper domino's first strike (at the last
    domino the run ends ``tail_time`` [s] later, at ``t_max`` at the latest).  Returns the
    new count of queued onsets and ends."""
    st.active[slot] = False
    ev = st.slot_event[slot]
    st.slot_event[slot] = -1
    if ev < 0:
        return n_pend
    prev = st.gap_prev[slot]
    frac = prev / (prev - delta) if delta <= 0.0 and prev > delta else 1.0
    st.events[ev, EV_T_OFF] = t - dt + frac * dt
    n_pend = _queue(pend, n_pend, ev, True, frac)
    up = int(st.events[ev, EV_UPPER])
    if not st.first_strike_done[up]:
        st.first_strike_done[up] = True
        if up == st.theta.shape[0] - 1:
            st.t_stop[0] = min(t_max, t + tail_time)
    return n_pend


@njit(cache=True)
def _queue(pend, n_pend, ev, end, frac):
    """Queue event row ``ev`` (its onset, or its ``end``) at fraction ``frac`` of the step
    in ``pend`` = (rows, ends, fractions); returns the new count."""
    rows, ends, fractions = pend
    rows[n_pend] = ev
    ends[n_pend] = end
    fractions[n_pend] = frac
    return n_pend + 1


@njit(cache=True)
def _finite(theta, omega, n_awake):
    """True if the angles and angular velocities of the dominoes in motion are finite."""
    for i in range(n_awake):
        if not math.isfinite(omega[i]) or not math.isfinite(theta[i]):
            return False
    return True


# --------------------------------------------------------------------------- time loop


@njit(cache=True)
def advance(p, st, n_steps):
    """Integrate up to ``n_steps`` time steps (fewer if the run ends); True when ended.

    Updates the state ``st`` (:class:`ChainState`) in place. It carries everything from
    one call to the next, so ``advance(a)`` then ``advance(b)`` does exactly the
    arithmetic of ``advance(a + b)``. A state fresh from :func:`new_state` first gets
    its forces at ``t = 0`` evaluated (and nothing else if ``n_steps = 0``).
    """
    l, s, pitch, m, inertia, cm_u, cm_w, g = p.l, p.s, p.pitch, p.m, p.inertia, p.cm_u, p.cm_w, p.g
    law, k, zeta, mu, v_reg, normal = p.law, p.k, p.zeta, p.mu, p.v_reg, p.normal
    e_floor, gravity_in_contact = p.e_floor, p.gravity_in_contact
    dt, t_max, stall_time, tail_time = p.dt, p.t_max, p.stall_time, p.tail_time
    sample_every, frame_every = p.sample_every, p.frame_every
    n = st.theta.shape[0]
    n_slots = 3 * n
    half_pi = 0.5 * math.pi
    theta_hi = half_pi
    theta_lo = 0.0 if s > 0.0 else -half_pi

    # the state (arrays change in place; scalars are copied back at the end)
    theta, omega, torque = st.theta, st.omega, st.torque
    active, gap_prev, slot_event = st.active, st.gap_prev, st.slot_event
    xi_x, xi_y, u_hit, w_hit = st.xi_x, st.xi_y, st.u_hit, st.w_hit
    head_on, handover = st.head_on, st.handover
    events, arrival, hv_max = st.events, st.arrival, st.hv_max
    theta_min_after = st.theta_min_after
    step = st.step[0]
    status = st.status[0]
    # (the counters that change only at contact onsets and ends, and t_stop, are kept in
    # st: _start_contact and _end_contact update them)
    n_samples = st.n_samples[0]
    n_frames = st.n_frames[0]
    e_diss = st.e_diss[0]
    e_floor_loss = st.e_floor_loss[0]
    t = step * dt

    # scratch of one step, recomputed every step before it is read; omega_old starts as
    # omega: a domino woken inside a step has never been integrated, so its omega is
    # still the one it started the run with
    cos_t = np.empty(n)
    sin_t = np.empty(n)
    fx = np.zeros(n)  # contact forces on each domino [N]
    fy = np.zeros(n)
    omega_old = omega.copy()
    act_list = np.empty(n_slots, dtype=np.int64)
    pend_ev = np.empty(n_slots, dtype=np.int64)  # onsets and ends of this step
    pend_end = np.empty(n_slots, dtype=np.bool_)
    pend_frac = np.empty(n_slots)
    pend = (pend_ev, pend_end, pend_frac)
    gravity_removed = np.zeros(n, dtype=np.bool_)
    hv_now = np.zeros(n)  # |H|/V of each domino at the current step (0 if undefined)

    first = status == STATUS_START  # the first pass only evaluates the forces at t = 0
    done = 0
    while first or (status == STATUS_RUNNING and done < n_steps):
        if not first:
            # ---------------- first half kick, drift, floor -------------------------------
            step += 1
            t = step * dt
            for i in range(min(st.n_awake[0], n)):
                omega_old[i] = omega[i]
                omega[i] += 0.5 * dt * torque[i] / inertia
                theta[i] += dt * omega[i]
                if theta[i] > theta_hi or theta[i] < theta_lo:
                    theta[i], omega[i], lost = _floor_impact(
                        theta[i], omega[i], theta_hi, theta_lo, e_floor, inertia, m, g, cm_u, cm_w
                    )
                    e_floor_loss += lost
        # ---------------- forces at the current positions ---------------------------------
        n_eval = min(n, st.n_awake[0] + 2)
        for i in range(n_eval):
            c = math.cos(theta[i])
            sn = math.sin(theta[i])
            cos_t[i] = c
            sin_t[i] = sn
            # gravity: Q = -dV/dtheta, V = m g (-cm_u sin + cm_w cos)
            torque[i] = m * g * (cm_u * c + cm_w * sn)
            fx[i] = 0.0
            fy[i] = 0.0
        n_act = 0
        n_pend = 0
        e_elastic = 0.0
        d_power = 0.0
        for i in range(min(st.n_awake[0], n)):  # (the range of the dominoes awake now)
            for kind in range(3):
                a, b, u0, w0, u_face, sigma = _slot_geometry(kind, i, l, s)
                if b >= n or a >= n:
                    continue
                slot = 3 * i + kind
                xa = a * pitch
                xb = b * pitch
                delta, w, u, ga, gb, px, py, dpx, dpy = corner_face_overlap(
                    xa, cos_t[a], sin_t[a], u0, w0, xb, cos_t[b], sin_t[b], u_face, sigma
                )
                inside = w >= 0.0 and w <= l
                starting = (not active[slot]) and delta > 0.0 and gap_prev[slot] <= 0.0 and inside
                if starting:
                    # ---- onset inside the step, located by the overlap's linear interpolation
                    frac = -gap_prev[slot] / (delta - gap_prev[slot])
                    n_pend = _start_contact(st, pend, n_pend, slot, kind, a, b, t, dt, frac, normal)
                    if handover[slot]:
                        # a head-on spring unloaded with the corner still inside the face:
                        # the geometric contact takes over; its initial elastic energy is
                        # book-kept (as negative dissipation) to keep the energy ledger closed
                        handover[slot] = False
                        e_diss -= _elastic_energy(law, delta, k)
                    if head_on[slot]:
                        xi_x[slot], xi_y[slot], u_hit[slot], w_hit[slot] = _head_on_anchor(
                            delta, w, u, ga, dpx, dpy, cos_t[b], sin_t[b]
                        )
                if not active[slot]:
                    gap_prev[slot] = delta
                    continue
                # ---- the contact is (or was) on: its overlap, lever arms, force direction
                delta_geo = delta
                if head_on[slot]:
                    nx = xi_x[slot]
                    ny = xi_y[slot]
                    delta, ga, gb = _head_on_overlap(
                        xb, cos_t[b], sin_t[b], u_hit[slot], w_hit[slot], nx, ny, px, py, dpx, dpy
                    )
                    touching = delta > 0.0 or starting  # anchored at zero stretch
                else:
                    nx = -sigma * cos_t[b]  # inward normal of the face: force on b
                    ny = sigma * sin_t[b]
                    touching = delta > 0.0 and inside
                ev = slot_event[slot]
                if not touching:
                    if delta > 0.0:
                        # the corner slid off the end of the face while pressed into it:
                        # the spring's energy is lost with it (book-kept as dissipated)
                        e_diss += _elastic_energy(law, delta, k)
                    n_pend = _end_contact(st, pend, n_pend, slot, t, dt, delta, t_max, tail_time)
                    # a new contact needs the corner to come from outside the face again
                    gap_prev[slot] = delta_geo
                    if head_on[slot] and delta_geo > 0.0 and inside:
                        gap_prev[slot] = 0.0
                        handover[slot] = True
                    continue
                gap_prev[slot] = delta
                act_list[n_act] = slot
                n_act += 1
                # ---- normal force law (pure per-pair function)
                delta_dot = ga * omega[a] + gb * omega[b]
                reduced = 1.0 / (ga * ga / inertia + gb * gb / inertia)
                f, f_el, energy = _normal_law(law, delta, delta_dot, k, zeta, reduced)
                e_elastic += energy
                d_power += (f - f_el) * delta_dot
                torque[a] -= f * ga
                torque[b] -= f * gb
                fx[b] += f * nx
                fy[b] += f * ny
                fx[a] -= f * nx
                fy[a] -= f * ny
                # ---- regularised Coulomb friction along the face (geometric normal only)
                if mu > 0.0:
                    tx = sin_t[b]
                    ty = cos_t[b]
                    lever_a = dpx * tx + dpy * ty
                    v_t = omega[a] * lever_a + omega[b] * u
                    f_t = coulomb_friction(f, v_t, mu, v_reg)
                    torque[a] += f_t * lever_a
                    torque[b] += f_t * u
                    fx[a] += f_t * tx
                    fy[a] += f_t * ty
                    fx[b] -= f_t * tx
                    fy[b] -= f_t * ty
                    d_power -= f_t * v_t
                if ev >= 0:
                    if f > events[ev, EV_F_MAX]:
                        events[ev, EV_F_MAX] = f
                    if delta > events[ev, EV_DELTA_MAX]:
                        events[ev, EV_DELTA_MAX] = delta
        if not gravity_in_contact:
            _remove_gravity_in_contact(
                act_list, n_act, gravity_removed, torque, cos_t, sin_t, l, s, m, g, cm_u, cm_w
            )
        if first:
            first = False
            status = STATUS_RUNNING
            continue
        e_diss += d_power * dt
        # ---------------- second half kick ------------------------------------------------
        n_move = min(st.n_awake[0], n)
        for i in range(n_move):
            omega[i] += 0.5 * dt * torque[i] / inertia
            # resting on a floor stop: the support removes velocity into the floor
            if theta[i] == theta_hi and omega[i] > 0.0:
                e_floor_loss += 0.5 * inertia * omega[i] * omega[i]
                omega[i] = 0.0
            elif theta[i] == theta_lo and omega[i] < 0.0:
                e_floor_loss += 0.5 * inertia * omega[i] * omega[i]
                omega[i] = 0.0
        # ---------------- measurements at the end of the step -----------------------------
        _interpolate_pending(events, pend_ev, pend_end, pend_frac, n_pend, omega_old, omega)
        for i in range(n_move):
            h, v = _base_reaction(
                cos_t[i], sin_t[i], torque[i], omega[i], inertia, m, g, cm_u, cm_w, fx[i], fy[i]
            )
            hv_now[i] = 0.0
            if theta[i] != theta_hi and theta[i] != theta_lo:
                if v > 0.0:
                    hv_now[i] = abs(h) / v
                    hv_max[i] = max(hv_max[i], hv_now[i])
                else:
                    st.lift_steps[i] += 1
            if not np.isnan(theta_min_after[i]) and theta[i] < theta_min_after[i]:
                theta_min_after[i] = theta[i]
        for q in range(n_act):
            ev = slot_event[act_list[q]]
            if ev >= 0:
                events[ev, EV_STEPS] += 1.0
                # peak |H|/V of the struck domino while this contact is on
                up = int(events[ev, EV_UPPER])
                events[ev, EV_HV_UP] = max(events[ev, EV_HV_UP], hv_now[up])
        # ---------------- records and stop conditions -------------------------------------
        if step % 256 == 0 and not _finite(theta, omega, n_move):
            status = STATUS_BLOW_UP
            break
        if step % sample_every == 0 and n_samples < st.samples.shape[0]:
            _energy_sample(
                st.samples[n_samples], t, theta, omega, inertia, m, g, cm_u, cm_w,
                e_elastic, e_diss, e_floor_loss,
            )  # fmt: skip
            n_samples += 1
        if frame_every > 0 and step % frame_every == 0 and n_frames < st.frame_t.shape[0]:
            st.frame_t[n_frames] = t
            st.frame_theta[n_frames, :] = theta
            st.frame_omega[n_frames, :] = omega
            n_frames += 1
        if t >= st.t_stop[0]:
            status = STATUS_WAVE_PASSED if st.t_stop[0] < t_max else STATUS_TIME_LIMIT
            break
        if st.t_stop[0] == t_max and not np.isnan(arrival[n - 1]) and theta[n - 1] == theta_hi:
            # the last domino lies flat: its first contact (if still on) is no collision
            st.t_stop[0] = min(t_max, t + tail_time)
        if t - st.t_last_arrival[0] > stall_time:
            # nothing new reached for stall_time: the wave died, or it has passed and
            # the last contact never ended (dominoes leaning on each other)
            status = STATUS_WAVE_PASSED if not np.isnan(arrival[n - 1]) else STATUS_STALLED
            break
        done += 1
    st.step[0] = step
    st.status[0] = status
    st.n_samples[0] = n_samples
    st.n_frames[0] = n_frames
    st.e_diss[0] = e_diss
    st.e_floor_loss[0] = e_floor_loss
    return status != STATUS_RUNNING


def run_chain(p: ChainParams, theta, omega, n_awake, max_events, max_samples, max_frames):
    """The whole run in one call: :func:`new_state`, then :func:`advance` to the end.

    ``p`` the run's parameters (:meth:`ChainParams.typed`); ``theta``, ``omega`` (shape
    ``(N,)``, [rad], [rad/s]) are updated in place; dominoes from ``n_awake`` on stand
    until touched; the record buffers hold ``max_events`` contacts, ``max_samples``
    energy samples and ``max_frames`` frames. Returns the final :class:`ChainState`
    (records filled up to their counters, see :data:`RECORDS`).
    """
    st = new_state(p, theta, omega, n_awake, max_events, max_samples, max_frames)
    advance(p, st, np.iinfo(np.int64).max)
    return st
