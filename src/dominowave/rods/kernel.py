"""Compiled time loop of the hinged-domino chain (velocity Verlet, fixed step).

One angle per domino. Each step: half kick, drift, floor, forces (gravity + every
neighbour contact, the pure per-pair laws of :mod:`dominowave.rods.contact`), half kick,
then the measurements. The whole loop runs in compiled code.

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


@njit(cache=True)
def run_chain(
    theta,
    omega,
    n_awake,
    l,
    s,
    pitch,
    m,
    inertia,
    cm_u,
    cm_w,
    g,
    law,
    k,
    zeta,
    mu,
    v_reg,
    normal,
    e_floor,
    gravity_in_contact,
    dt,
    t_max,
    stall_time,
    tail_time,
    sample_every,
    max_events,
    max_samples,
    frame_every,
    max_frames,
):
    """Integrate the chain from ``t = 0`` until the wave has passed (or a limit).

    ``theta``, ``omega`` (shape ``(N,)``, [rad], [rad/s]) are updated in place. Returns
    ``(status, t_end, n_steps, events, n_events (may exceed max_events), samples,
    n_samples, arrival, hv_max, lift_steps, theta_min_after, n_awake, frame_t,
    frame_theta, frame_omega, n_frames)``: ``events`` shape ``(max_events, EV_COLUMNS)``,
    ``samples`` shape ``(max_samples, SA_COLUMNS)``, per-domino arrays shape ``(N,)``,
    frames (every ``frame_every`` steps, none if 0) shapes ``(max_frames,)`` and
    ``(max_frames, N)``.
    """
    n = theta.shape[0]
    n_slots = 3 * n
    half_pi = 0.5 * math.pi
    theta_hi = half_pi
    theta_lo = 0.0 if s > 0.0 else -half_pi

    cos_t = np.empty(n)
    sin_t = np.empty(n)
    torque = np.zeros(n)  # generalised force [N m]
    fx = np.zeros(n)  # contact forces on each domino [N]
    fy = np.zeros(n)
    omega_old = omega.copy()

    active = np.zeros(n_slots, dtype=np.bool_)
    gap_prev = np.full(n_slots, -1.0 * l)  # last overlap (geometric, or along xi when head-on)
    slot_event = np.full(n_slots, -1, dtype=np.int64)
    xi_x = np.zeros(n_slots)
    xi_y = np.zeros(n_slots)
    u_hit = np.zeros(n_slots)  # head-on anchor on the struck domino (body coordinates)
    w_hit = np.zeros(n_slots)
    head_on = np.zeros(n_slots, dtype=np.bool_)  # this contact uses the head-on law
    touched = np.zeros(n_slots, dtype=np.bool_)  # the slot has had a contact
    handover = np.zeros(n_slots, dtype=np.bool_)
    act_list = np.empty(n_slots, dtype=np.int64)

    events = np.full((max_events, EV_COLUMNS), np.nan)
    n_events = 0
    pend_ev = np.empty(n_slots, dtype=np.int64)
    pend_end = np.empty(n_slots, dtype=np.bool_)
    pend_frac = np.empty(n_slots)

    samples = np.full((max_samples, SA_COLUMNS), np.nan)
    n_samples = 0
    frame_t = np.full(max_frames, np.nan)
    frame_theta = np.full((max_frames, n), np.nan)
    frame_omega = np.full((max_frames, n), np.nan)
    n_frames = 0
    if frame_every > 0 and max_frames > 0:  # the initial state is frame 0
        frame_t[0] = 0.0
        frame_theta[0, :] = theta
        frame_omega[0, :] = omega
        n_frames = 1

    arrival = np.full(n, np.nan)
    arrival[0] = 0.0
    first_strike_done = np.zeros(n, dtype=np.bool_)
    hv_max = np.zeros(n)
    lift_steps = np.zeros(n, dtype=np.int64)
    theta_min_after = np.full(n, np.nan)
    gravity_removed = np.zeros(n, dtype=np.bool_)
    hv_now = np.zeros(n)  # |H|/V of each domino at the current step (0 if undefined)

    e_diss = 0.0
    e_floor_loss = 0.0
    e_elastic = 0.0
    t = 0.0
    t_last_arrival = 0.0
    t_stop = t_max
    status = STATUS_TIME_LIMIT
    step = 0

    first = True  # the first pass only evaluates the forces at t = 0
    while True:
        # ---------------- forces at the current positions --------------------------------
        n_eval = min(n, n_awake + 2)
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
        for i in range(min(n_awake, n)):
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
                    frac = -gap_prev[slot] / (delta - gap_prev[slot])
                    lo = min(a, b)
                    up = max(a, b)
                    if n_events < max_events:
                        ev = n_events
                        events[ev, EV_LOWER] = lo
                        events[ev, EV_UPPER] = up
                        events[ev, EV_KIND] = kind
                        events[ev, EV_T_ON] = max(t - dt + frac * dt, 0.0)
                        events[ev, EV_F_MAX] = 0.0
                        events[ev, EV_HV_UP] = 0.0
                        events[ev, EV_STEPS] = 0.0
                        events[ev, EV_DELTA_MAX] = 0.0
                        slot_event[slot] = ev
                        pend_ev[n_pend] = ev
                        pend_end[n_pend] = False
                        pend_frac[n_pend] = frac
                        n_pend += 1
                    else:
                        slot_event[slot] = -1
                    n_events += 1
                    if np.isnan(arrival[up]):
                        arrival[up] = max(t - dt + frac * dt, 0.0)
                        t_last_arrival = t
                    if up >= n_awake:
                        n_awake = up + 1
                    if kind == 0 and np.isnan(theta_min_after[a]):
                        theta_min_after[a] = theta[a]
                    active[slot] = True
                    # the head-on assumption describes the pair collision: the first
                    # contact of a slot; later contacts (leaning, re-collisions) are geometric
                    head_on[slot] = normal == NORMAL_HEAD_ON and kind == 0 and not touched[slot]
                    touched[slot] = True
                    if handover[slot]:
                        # a head-on spring unloaded with the corner still inside the face:
                        # the geometric contact takes over; its initial elastic energy is
                        # book-kept (as negative dissipation) to keep the energy ledger closed
                        handover[slot] = False
                        e_diss -= (
                            linear_energy(delta, k) if law == LAW_LINEAR else hertz_energy(delta, k)
                        )
                    if head_on[slot]:
                        # fix the axis xi along the path of the striking corner, oriented
                        # into the face; anchor the spring at the material point of b where
                        # the corner entered along xi (a grazing corner, |xi . n| < 1/4, is
                        # anchored where it is: a far anchor would inject energy)
                        norm = math.sqrt(dpx * dpx + dpy * dpy)
                        sgn = 1.0 if ga >= 0.0 else -1.0
                        xi_x[slot] = sgn * dpx / norm
                        xi_y[slot] = sgn * dpy / norm
                        along = delta * norm / abs(ga) if 4.0 * abs(ga) >= norm else 0.0
                        u_hit[slot] = u - along * (xi_x[slot] * cos_t[b] - xi_y[slot] * sin_t[b])
                        w_hit[slot] = w - along * (xi_x[slot] * sin_t[b] + xi_y[slot] * cos_t[b])
                if not active[slot]:
                    gap_prev[slot] = delta
                    continue
                # ---- the contact is (or was) on: its overlap, lever arms, force direction
                delta_geo = delta
                if head_on[slot]:
                    uh = u_hit[slot]
                    wh = w_hit[slot]
                    cx = xb + uh * cos_t[b] + wh * sin_t[b]
                    cy = -uh * sin_t[b] + wh * cos_t[b]
                    dcx = -uh * sin_t[b] + wh * cos_t[b]
                    dcy = -uh * cos_t[b] - wh * sin_t[b]
                    nx = xi_x[slot]
                    ny = xi_y[slot]
                    delta = nx * (px - cx) + ny * (py - cy)
                    ga = nx * dpx + ny * dpy
                    gb = -(nx * dcx + ny * dcy)
                    touching = delta > 0.0 or starting  # anchored at zero stretch
                else:
                    nx = -sigma * cos_t[b]  # inward normal of the face: force on b
                    ny = sigma * sin_t[b]
                    touching = delta > 0.0 and inside
                ev = slot_event[slot]
                if not touching:
                    active[slot] = False
                    if delta > 0.0:
                        # the corner slid off the end of the face while pressed into it:
                        # the spring's energy is lost with it (book-kept as dissipated)
                        e_diss += (
                            linear_energy(delta, k) if law == LAW_LINEAR else hertz_energy(delta, k)
                        )
                    if ev >= 0:
                        prev = gap_prev[slot]
                        frac = prev / (prev - delta) if delta <= 0.0 and prev > delta else 1.0
                        events[ev, EV_T_OFF] = t - dt + frac * dt
                        pend_ev[n_pend] = ev
                        pend_end[n_pend] = True
                        pend_frac[n_pend] = frac
                        n_pend += 1
                        up = int(events[ev, EV_UPPER])
                        if not first_strike_done[up]:
                            first_strike_done[up] = True
                            if up == n - 1:
                                t_stop = min(t_max, t + tail_time)
                    slot_event[slot] = -1
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
                if law == LAW_LINEAR:
                    c_d = damping_coefficient(zeta, k, reduced) if zeta > 0.0 else 0.0
                    f = linear_force(delta, delta_dot, k, c_d)
                    f_el = k * delta
                    e_elastic += linear_energy(delta, k)
                else:
                    sq = math.sqrt(delta)
                    c_d = damping_coefficient(zeta, 1.5 * k * sq, reduced) if zeta > 0.0 else 0.0
                    f = hertz_force(delta, delta_dot, k, c_d)
                    f_el = k * delta * sq
                    e_elastic += hertz_energy(delta, k)
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
            # assumption switch of the theory (section 2.2): no gravity on a domino while
            # it is in contact (non-physical: the energy ledger no longer closes)
            for q in range(n_act):
                slot = act_list[q]
                i = slot // 3
                a, b, _, _, _, _ = _slot_geometry(slot - 3 * i, i, l, s)
                for j in (a, b):
                    if not gravity_removed[j]:
                        gravity_removed[j] = True
                        torque[j] -= m * g * (cm_u * cos_t[j] + cm_w * sin_t[j])
            for q in range(n_act):
                slot = act_list[q]
                i = slot // 3
                a, b, _, _, _, _ = _slot_geometry(slot - 3 * i, i, l, s)
                gravity_removed[a] = False
                gravity_removed[b] = False
        if first:
            first = False
        else:
            e_diss += d_power * dt
            # ---------------- second half kick -----------------------------------------
            for i in range(min(n_awake, n)):
                omega[i] += 0.5 * dt * torque[i] / inertia
                # resting on a floor stop: the support removes velocity into the floor
                if theta[i] == theta_hi and omega[i] > 0.0:
                    e_floor_loss += 0.5 * inertia * omega[i] * omega[i]
                    omega[i] = 0.0
                elif theta[i] == theta_lo and omega[i] < 0.0:
                    e_floor_loss += 0.5 * inertia * omega[i] * omega[i]
                    omega[i] = 0.0
            # ---------------- measurements at the end of the step ------------------------
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
            for i in range(min(n_awake, n)):
                # base reaction R = m a_cm + (0, m g) - sum of contact forces
                c = cos_t[i]
                sn = sin_t[i]
                alpha = torque[i] / inertia
                w2 = omega[i] * omega[i]
                # r_c = cm_u e_u + cm_w e_w ; t_c = dr_c/dtheta = -cm_u e_w + cm_w e_u
                rcx = cm_u * c + cm_w * sn
                rcy = -cm_u * sn + cm_w * c
                tcx = -cm_u * sn + cm_w * c
                tcy = -cm_u * c - cm_w * sn
                h = m * (alpha * tcx - w2 * rcx) - fx[i]
                v = m * (alpha * tcy - w2 * rcy) + m * g - fy[i]
                hv_now[i] = 0.0
                if theta[i] != theta_hi and theta[i] != theta_lo:
                    if v > 0.0:
                        hv_now[i] = abs(h) / v
                        hv_max[i] = max(hv_max[i], hv_now[i])
                    else:
                        lift_steps[i] += 1
                if not np.isnan(theta_min_after[i]) and theta[i] < theta_min_after[i]:
                    theta_min_after[i] = theta[i]
            for q in range(n_act):
                ev = slot_event[act_list[q]]
                if ev >= 0:
                    events[ev, EV_STEPS] += 1.0
                    # peak |H|/V of the struck domino while this contact is on
                    up = int(events[ev, EV_UPPER])
                    events[ev, EV_HV_UP] = max(events[ev, EV_HV_UP], hv_now[up])
            # ---------------- stop conditions ------------------------------------------
            if step % 256 == 0:
                for i in range(min(n_awake, n)):
                    if not math.isfinite(omega[i]) or not math.isfinite(theta[i]):
                        status = STATUS_BLOW_UP
                if status == STATUS_BLOW_UP:
                    break
            if step % sample_every == 0 and n_samples < max_samples:
                e_kin = 0.0
                e_grav = 0.0
                for i in range(n):
                    e_kin += 0.5 * inertia * omega[i] * omega[i]
                    height = _gravity_height(math.cos(theta[i]), math.sin(theta[i]), cm_u, cm_w)
                    e_grav += m * g * height
                samples[n_samples, SA_T] = t
                samples[n_samples, SA_KIN] = e_kin
                samples[n_samples, SA_GRAV] = e_grav
                samples[n_samples, SA_ELASTIC] = e_elastic
                samples[n_samples, SA_DISSIPATED] = e_diss
                samples[n_samples, SA_FLOOR] = e_floor_loss
                n_samples += 1
            if frame_every > 0 and step % frame_every == 0 and n_frames < max_frames:
                frame_t[n_frames] = t
                frame_theta[n_frames, :] = theta
                frame_omega[n_frames, :] = omega
                n_frames += 1
            if t >= t_stop:
                status = STATUS_WAVE_PASSED if t_stop < t_max else STATUS_TIME_LIMIT
                break
            if t_stop == t_max and not np.isnan(arrival[n - 1]) and theta[n - 1] == theta_hi:
                # the last domino lies flat: its first contact (if still on) is no collision
                t_stop = min(t_max, t + tail_time)
            if t - t_last_arrival > stall_time:
                # nothing new reached for stall_time: the wave died, or it has passed and
                # the last contact never ended (dominoes leaning on each other)
                status = STATUS_WAVE_PASSED if not np.isnan(arrival[n - 1]) else STATUS_STALLED
                break
        # ---------------- first half kick, drift, floor ----------------------------------
        step += 1
        t = step * dt
        for i in range(min(n_awake, n)):
            omega_old[i] = omega[i]
            omega[i] += 0.5 * dt * torque[i] / inertia
            theta[i] += dt * omega[i]
            if theta[i] > theta_hi or theta[i] < theta_lo:
                stop = theta_hi if theta[i] > theta_hi else theta_lo
                e_before = 0.5 * inertia * omega[i] * omega[i] + m * g * _gravity_height(
                    math.cos(theta[i]), math.sin(theta[i]), cm_u, cm_w
                )
                theta[i] = stop
                omega[i] = -e_floor * omega[i]
                e_after = 0.5 * inertia * omega[i] * omega[i] + m * g * _gravity_height(
                    math.cos(stop), math.sin(stop), cm_u, cm_w
                )
                e_floor_loss += e_before - e_after
    return (
        status,
        t,
        step,
        events,
        n_events,
        samples,
        n_samples,
        arrival,
        hv_max,
        lift_steps,
        theta_min_after,
        n_awake,
        frame_t,
        frame_theta,
        frame_omega,
        n_frames,
    )
