"""Contact detection and contact laws.

Each contact law is a small pure function of one pair (jax-md style); the driver
:func:`compute_forces` maps it over the Verlet list.

Laws (Cundall & Strack 1979, Geotechnique 29:47; YADE's Law2_ScGeom_FrictPhys_CundallStrack):

* normal: ``F_n = k_n * delta`` (linear spring, delta = overlap) plus an optional viscous
  dashpot ``-c_n * v_n``;
* tangential: elastic shear displacement ``u_s`` accumulated from the tangential relative
  velocity, ``F_s = -k_t u_s``, Coulomb limit ``|F_s| <= mu k_n delta``; on sliding ``u_s`` is
  shortened to the limit; the energy this dissipates (YADE's plasticDissipation ``(|F_trial|
  - |F_s|) |F_s| / k_t`` in steady sliding) is booked as the work of the tangential forces
  that the springs do not store (:func:`contact_power`).  When the contact frame moves,
  ``u_s`` is projected onto the new tangent plane with its length kept, then turned about
  the normal by the mean spin of the two bodies (as YADE's ScGeom::rotate, but norm preserving).

Sign convention: the unit normal ``n`` points from sphere ``i`` to its partner ``j``; the
returned force acts on ``j`` (``-F`` on ``i``).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = [
    "RULE_PAPER",
    "RULE_YADE",
    "active_contact_forces",
    "build_verlet_list",
    "compute_forces",
    "contact_power",
    "needs_rebuild",
    "pair_stiffness",
    "viscous_coefficient",
]

RULE_PAPER = 0
RULE_YADE = 1

ONSET = 1
END = 0


@njit(cache=True, error_model="numpy")
def particle_stiffness(modulus, radius, given_kn, rule):
    """Stiffness of one particle [N/m]: pi R E ("paper", eq. 20), E R ("yade") or kn."""
    if given_kn:
        return modulus
    if rule == RULE_PAPER:
        return math.pi * radius * modulus
    return modulus * radius


@njit(cache=True, error_model="numpy")
def pair_stiffness(k1, k2, given_kn, rule):
    """Contact stiffness of two particles [N/m].

    "paper": springs in series ``k1 k2 / (k1 + k2)`` (eq. 21, equal spheres: pi R E / 2);
    "yade" and given kn: ``2 k1 k2 / (k1 + k2)`` (Ip2_FrictMat_FrictMat_FrictPhys).
    """
    if k1 <= 0.0 or k2 <= 0.0:
        return 0.0
    series = k1 * k2 / (k1 + k2)
    if rule == RULE_PAPER and not given_kn:
        return series
    return 2.0 * series


@njit(cache=True, error_model="numpy")
def viscous_coefficient(restitution, m_eff, kn):
    """Dashpot coefficient c_n [N s/m] giving restitution ``e`` for a linear spring-dashpot.

    Damped oscillator ``m x'' + c x' + k x = 0`` released at zero overlap, contact ended when
    the overlap returns to zero: ``e = exp(-zeta pi / sqrt(1 - zeta^2))`` with
    ``zeta = c / (2 sqrt(m k))``, i.e. ``zeta = -ln e / sqrt(pi^2 + ln^2 e)``
    (e.g. Schwager & Poeschel, Phys. Rev. E 75, 051304 (2007), eq. 2-5; Antypov & Elliott,
    EPL 94, 50004 (2011)).
    """
    if restitution >= 1.0:
        return 0.0
    log_e = math.log(restitution)
    zeta = -log_e / math.sqrt(math.pi * math.pi + log_e * log_e)
    return 2.0 * zeta * math.sqrt(m_eff * kn)


@njit(cache=True, error_model="numpy", _nrt=False)
def pair_properties(si, sj_or_wall, spheres, walls, bodies, mats, out):
    """kn, kt, mu, cn of a candidate pair into ``out[0:4]``."""
    rule = mats.rule[0]
    mi = spheres.material[si]
    Ri = spheres.radius[si]
    bi = spheres.body[si]
    if sj_or_wall >= 0:
        mj = spheres.material[sj_or_wall]
        Rj = spheres.radius[sj_or_wall]
        bj = spheres.body[sj_or_wall]
        m_eff = bodies.mass[bi] * bodies.mass[bj] / (bodies.mass[bi] + bodies.mass[bj])
    else:
        mj = walls.material[-sj_or_wall - 1]
        Rj = Ri  # a wall takes the radius of the sphere touching it
        m_eff = bodies.mass[bi]
    given = mats.given_kn[mi] == 1
    ki = particle_stiffness(mats.stiffness[mi], Ri, given, rule)
    kj = particle_stiffness(mats.stiffness[mj], Rj, given, rule)
    kn = pair_stiffness(ki, kj, given, rule)
    kt = pair_stiffness(ki * mats.kt_ratio[mi], kj * mats.kt_ratio[mj], given, rule)
    out[0] = kn
    out[1] = kt
    out[2] = min(mats.friction[mi], mats.friction[mj])
    out[3] = viscous_coefficient(min(mats.restitution[mi], mats.restitution[mj]), m_eff, kn)


# --------------------------------------------------------------------------- neighbours


@njit(cache=True, error_model="numpy", _nrt=False)
def needs_rebuild(bodies, skin, n_candidates):
    """True if a member sphere of some body may have moved more than skin/2 since the last
    Verlet-list build.

    Tested per body, not per sphere: a sphere at ``x + R u`` moves by at most
    ``|x - x0| + |R - R0| |u|``, and the spectral norm of ``R - R0`` is ``2 sin(theta/2)``
    for the angle theta of the rotation between the two orientations; ``|u| <= extent``.
    With ``d = |q - q0|`` (q0 taken with the sign that makes ``q . q0 >= 0``),
    ``d = 2 sin(theta/4)`` and ``sin(theta/2) = d sqrt(1 - d^2/4)``, free of the
    cancellation of ``sqrt(1 - (q . q0)^2)`` at small angles.  The bound is attained by
    a sphere at distance ``extent`` moving along the translation, so the list is rebuilt no
    earlier than a per-sphere test would; the forces do not depend on when it is (inactive
    pairs contribute nothing, active pairs are kept in key order).
    """
    if n_candidates < 0:
        return True
    pos, pos0, quat, quat0 = bodies.pos, bodies.pos_at_build, bodies.quat, bodies.quat_at_build
    half = 0.5 * skin
    for b in range(pos.shape[0]):
        dx = pos[b, 0] - pos0[b, 0]
        dy = pos[b, 1] - pos0[b, 1]
        dz = pos[b, 2] - pos0[b, 2]
        dot = quat[b, 0] * quat0[b, 0] + quat[b, 1] * quat0[b, 1]
        dot += quat[b, 2] * quat0[b, 2] + quat[b, 3] * quat0[b, 3]
        sign = 1.0 if dot >= 0.0 else -1.0
        d2 = 0.0
        for k in range(4):
            diff = quat[b, k] - sign * quat0[b, k]
            d2 += diff * diff
        sin_half = math.sqrt(d2 * max(0.0, 1.0 - 0.25 * d2))
        if math.sqrt(dx * dx + dy * dy + dz * dz) + 2.0 * sin_half * bodies.extent[b] > half:
            return True
    return False


@njit(cache=True, error_model="numpy")
def _candidate_pairs(spheres, walls, skin):
    """All sphere-sphere (different bodies) and sphere-wall pairs closer than the skin.

    Linked-cell search with cells of edge >= 2 R_max + skin.  Returns sorted int64 keys
    ``i * (ns + nw) + jj`` with ``jj = j`` for spheres and ``ns + w`` for walls.
    """
    pos, radius = spheres.pos, spheres.radius
    ns = pos.shape[0]
    rmax = 0.0
    lo = np.empty(3)
    hi = np.empty(3)
    for d in range(3):
        lo[d] = np.inf
        hi[d] = -np.inf
    for s in range(ns):
        rmax = max(rmax, radius[s])
        for d in range(3):
            lo[d] = min(lo[d], pos[s, d])
            hi[d] = max(hi[d], pos[s, d])
    cell = 2.0 * rmax + skin
    ncell = np.empty(3, np.int64)
    total = 1
    for d in range(3):
        ncell[d] = max(1, min(int(min((hi[d] - lo[d]) / cell, 1e9)), 8 * ns + 64))
        total *= ncell[d]
    # keep memory proportional to the number of spheres in sparse scenes
    while total > 8 * ns + 64:
        for d in range(3):
            ncell[d] = max(1, ncell[d] // 2)
        total = ncell[0] * ncell[1] * ncell[2]
    width = np.empty(3)
    for d in range(3):
        width[d] = max((hi[d] - lo[d]) / ncell[d], 1e-300)
    head = -np.ones(total, np.int64)
    nxt = -np.ones(ns, np.int64)
    cidx = np.empty((ns, 3), np.int64)
    _bin_spheres(pos, lo, width, ncell, head, nxt, cidx)
    keys = np.empty(16 * ns + 16, np.int64)
    n = _scan_cells(spheres, walls, skin, ncell, head, nxt, cidx, keys)
    while n < 0:  # keys too short: the scan wrote nothing that counts, redo with room
        keys = np.empty(2 * keys.shape[0], np.int64)
        n = _scan_cells(spheres, walls, skin, ncell, head, nxt, cidx, keys)
    return np.sort(keys[:n])


# The two loops of the search are compiled without numba's reference counting
# (``_nrt=False``): they allocate nothing, and with it the loops paid atomic increments and
# decrements of the arrays' reference counts that numba could not prune (a list build of
# the paper chain took 28 us, now 14 us).  The per-step kernels are compiled the same way
# for the same reason (engine.run_loop).


@njit(cache=True, error_model="numpy", _nrt=False)
def _bin_spheres(pos, lo, width, ncell, head, nxt, cidx):
    """Linked lists of the spheres in each cell: ``head[cell]`` -> ``nxt[s]`` -> ...;
    ``cidx[s]`` the (3,) cell index of sphere s."""
    for s in range(pos.shape[0]):
        for d in range(3):
            c = int((pos[s, d] - lo[d]) / width[d])
            cidx[s, d] = min(max(c, 0), ncell[d] - 1)
        flat = (cidx[s, 0] * ncell[1] + cidx[s, 1]) * ncell[2] + cidx[s, 2]
        nxt[s] = head[flat]
        head[flat] = s


@njit(cache=True, error_model="numpy", _nrt=False)
def _scan_cells(spheres, walls, skin, ncell, head, nxt, cidx, keys):
    """Write the keys of all pairs closer than the skin into ``keys``; return their number,
    or -1 if ``keys`` is too short."""
    pos, radius, body = spheres.pos, spheres.radius, spheres.body
    wall_point, wall_normal = walls.point, walls.normal
    ns = pos.shape[0]
    nw = wall_point.shape[0]
    stride = ns + nw
    capacity = keys.shape[0]
    n = 0
    for s in range(ns):
        for ox in range(-1, 2):
            cx = cidx[s, 0] + ox
            if cx < 0 or cx >= ncell[0]:
                continue
            for oy in range(-1, 2):
                cy = cidx[s, 1] + oy
                if cy < 0 or cy >= ncell[1]:
                    continue
                for oz in range(-1, 2):
                    cz = cidx[s, 2] + oz
                    if cz < 0 or cz >= ncell[2]:
                        continue
                    t = head[(cx * ncell[1] + cy) * ncell[2] + cz]
                    while t >= 0:
                        if t > s and body[t] != body[s]:
                            dx = pos[t, 0] - pos[s, 0]
                            dy = pos[t, 1] - pos[s, 1]
                            dz = pos[t, 2] - pos[s, 2]
                            reach = radius[s] + radius[t] + skin
                            if dx * dx + dy * dy + dz * dz < reach * reach:
                                if n == capacity:
                                    return -1
                                keys[n] = s * stride + t
                                n += 1
                        t = nxt[t]
        for w in range(nw):
            dist = 0.0
            for d in range(3):
                dist += (pos[s, d] - wall_point[w, d]) * wall_normal[w, d]
            if dist < radius[s] + skin:
                if n == capacity:
                    return -1
                keys[n] = s * stride + ns + w
                n += 1
    return n


@njit(cache=True, error_model="numpy")
def build_verlet_list(spheres, walls, bodies, mats, contacts, skin):
    """Rebuild the Verlet list, carrying the history of every existing pair over.

    Returns the number of pairs, or ``-needed`` if the contact arrays are too short (the
    caller grows them and calls again; nothing has been changed then).
    """
    ns = spheres.pos.shape[0]
    nw = walls.point.shape[0]
    stride = ns + nw
    keys = _candidate_pairs(spheres, walls, skin)
    n_new = keys.shape[0]
    if n_new > contacts.i.shape[0]:
        return -n_new
    n_old = contacts.n[0]
    old_key = np.empty(max(n_old, 0), np.int64)
    old_active = np.empty(max(n_old, 0), np.uint8)
    old_shear = np.empty((max(n_old, 0), 3))
    old_state = np.empty((max(n_old, 0), 4))  # overlap, vn, fn, fn_viscous
    for c in range(n_old):
        j = contacts.j[c]
        jj = j if j >= 0 else ns - j - 1
        old_key[c] = contacts.i[c] * stride + jj
        old_active[c] = contacts.active[c]
        for d in range(3):
            old_shear[c, d] = contacts.shear[c, d]
        old_state[c, 0] = contacts.overlap[c]
        old_state[c, 1] = contacts.vn[c]
        old_state[c, 2] = contacts.fn[c]
        old_state[c, 3] = contacts.fn_viscous[c]
    props = np.empty(4)
    o = 0
    for c in range(n_new):
        k = keys[c]
        i = k // stride
        jj = k - i * stride
        j = jj if jj < ns else -(jj - ns) - 1
        contacts.i[c] = i
        contacts.j[c] = j
        while o < n_old and old_key[o] < k:
            o += 1  # old pairs now out of range: their contacts have ended already
        if o < n_old and old_key[o] == k:
            # the whole history: the dashpot extrapolates vn, an ending contact needs
            # its last overlap (end_impulse)
            contacts.active[c] = old_active[o]
            for d in range(3):
                contacts.shear[c, d] = old_shear[o, d]
            contacts.overlap[c] = old_state[o, 0]
            contacts.vn[c] = old_state[o, 1]
            contacts.fn[c] = old_state[o, 2]
            contacts.fn_viscous[c] = old_state[o, 3]
        else:
            contacts.active[c] = 0
            for d in range(3):
                contacts.shear[c, d] = 0.0
            contacts.fn_viscous[c] = 0.0
        pair_properties(i, j, spheres, walls, bodies, mats, props)
        contacts.kn[c] = props[0]
        contacts.kt[c] = props[1]
        contacts.mu[c] = props[2]
        contacts.cn[c] = props[3]
    contacts.n[0] = n_new
    _list_spheres(spheres, contacts)
    for b in range(bodies.mass.shape[0]):
        for d in range(3):
            bodies.pos_at_build[b, d] = bodies.pos[b, d]
        for d in range(4):
            bodies.quat_at_build[b, d] = bodies.quat[b, d]
    return n_new


@njit(cache=True, error_model="numpy")
def _list_spheres(spheres, contacts):
    """``spheres.listed``: the spheres of the Verlet list, the only ones whose positions
    the contact kernels read until the next build (the engine updates just these)."""
    ns = spheres.pos.shape[0]
    seen = np.zeros(ns, np.uint8)
    for c in range(contacts.n[0]):
        seen[contacts.i[c]] = 1
        if contacts.j[c] >= 0:
            seen[contacts.j[c]] = 1
    k = 0
    for s in range(ns):
        if seen[s]:
            spheres.listed[k] = s
            k += 1
    spheres.n_listed[0] = k


# --------------------------------------------------------------------------- contact law


@njit(cache=True, error_model="numpy", inline="always")
def rotate_shear(shear, c, n, spin):
    """Carry the shear displacement ``shear[c]`` into the new tangent plane (norm kept),
    then turn it about ``n`` by the angle ``spin`` [rad] (mean rotation of the two bodies
    about n).  ``shear``: (C, 3), row ``c`` changed in place (rows are indexed, not taken
    as views: a view costs numba an atomic reference-count pair)."""
    old = math.sqrt(shear[c, 0] ** 2 + shear[c, 1] ** 2 + shear[c, 2] ** 2)
    if old == 0.0:
        return
    un = shear[c, 0] * n[0] + shear[c, 1] * n[1] + shear[c, 2] * n[2]
    for d in range(3):
        shear[c, d] -= un * n[d]
    new = math.sqrt(shear[c, 0] ** 2 + shear[c, 1] ** 2 + shear[c, 2] ** 2)
    if new > 0.0:
        for d in range(3):
            shear[c, d] *= old / new
    if spin != 0.0:
        # Rodrigues for a vector perpendicular to n: u cos + (n x u) sin, with the Cayley
        # (rational) cos/sin of the small angle: an exact rotation (norm kept) by
        # 2 atan(spin/2) = spin (1 - spin^2/12 + ...), without trigonometric calls
        h = 0.25 * spin * spin
        cos_ = (1.0 - h) / (1.0 + h)
        sin_ = spin / (1.0 + h)
        x = n[1] * shear[c, 2] - n[2] * shear[c, 1]
        y = n[2] * shear[c, 0] - n[0] * shear[c, 2]
        z = n[0] * shear[c, 1] - n[1] * shear[c, 0]
        shear[c, 0] = shear[c, 0] * cos_ + x * sin_
        shear[c, 1] = shear[c, 1] * cos_ + y * sin_
        shear[c, 2] = shear[c, 2] * cos_ + z * sin_


@njit(cache=True, error_model="numpy", inline="always")
def onset_averaged_overlap(overlap, vn, dt, new_contact):
    """Contact onset inside a kick interval: the overlap averaged over the interval.

    Leapfrog applies the force at t_n for the whole interval [t_n - dt/2, t_n + dt/2].
    When a contact starts inside it, the force law has a kink (elastic) or a jump
    (dashpot) there and the midpoint rule errs by O(dt^2) resp. O(dt) per collision.
    With the overlap linear in time, ``delta(t) = delta_n + |vn| (t - t_n)`` (``vn < 0``
    approaching), the part of the interval spent in contact is ``w = 1/2 + delta_n / (|vn|
    dt)``, including the part of the preceding interval whose step saw no overlap, and the
    average elastic overlap is ``|vn| dt w^2 / 2``.  Returns ``(w, averaged overlap)``.

    Only a *new* contact that approaches is modified: a contact that has been closed
    before is never changed while it stays closed (it may turn around near zero overlap
    without opening); its end is corrected afterwards, see :func:`end_impulse`.
    """
    ramp = -vn * dt
    if not new_contact or overlap >= ramp:  # (also every vn >= 0: ramp <= 0 < overlap)
        return 1.0, overlap
    w = 0.5 + overlap / ramp
    return w, 0.5 * ramp * w * w


@njit(cache=True, error_model="numpy", inline="always")
def end_impulse(last_overlap, gap, kn, cn, dt):
    """Normal force [N] for one kick that supplies the impulse missed when a contact ended.

    Called at the first step ``n+1`` that sees no overlap (``gap = delta_{n+1} <= 0``)
    after the overlap ``delta_n > 0`` of step ``n``.  The overlap fell linearly,
    ``delta(t) = delta_n - v (t - t_n)`` with ``v = (delta_n - delta_{n+1}) / dt``, and
    reached zero at ``t_n + r dt``, ``r = delta_n / (v dt)`` in (0, 1].  The exact
    elastic impulse from ``t_n - dt/2`` on is ``kn v dt^2 (r + 1/2)^2 / 2``; the kick of
    step n applied ``kn delta_n dt``; the difference ``kn v dt^2 (r - 1/2)^2 / 2 >= 0`` is
    applied now.  The dashpot (``-cn v`` while in contact) missed ``-cn v dt (r - 1/2)``.
    Returns ``(elastic force, dashpot force)`` = missed impulses / dt.  The impulse
    arrives one kick late, which leaves the momentum transfer of the collision exact to
    the order of the linear overlap model (the restitution error stays fourth order).
    """
    ramp = last_overlap - gap
    if ramp <= 0.0 or last_overlap <= 0.0:
        return 0.0, 0.0
    r = last_overlap / ramp
    return 0.5 * kn * ramp * (r - 0.5) ** 2, -cn * ramp / dt * (r - 0.5)


@njit(cache=True, error_model="numpy", inline="always")
def cundall_strack(shear, c, kt, mu, fn_elastic, out_force):
    """Tangential force ``-kt u_s`` with Coulomb limit ``mu fn_elastic``.

    ``shear[c]`` (row c of a (C, 3) array) is the trial displacement ``t`` (last step's
    displacement carried into the new tangent plane plus this step's tangential
    increment); on sliding it is shortened in place to ``b = t limit / |t|`` (YADE's
    Law2_ScGeom_FrictPhys_CundallStrack).  Writes the force on partner j into ``out_force``.

    The energy this removes is booked by the driver as the work of the tangential forces
    that is not stored in the springs (see :func:`contact_power`), not as YADE's plastic
    work ``(|t| - |b|) kt |b|`` per step: the latter pairs the force of one instant with a
    displacement over the step and lets the balance drift at first order in dt.
    """
    tt = shear[c, 0] * shear[c, 0] + shear[c, 1] * shear[c, 1] + shear[c, 2] * shear[c, 2]
    trial = kt * math.sqrt(tt)
    limit = mu * fn_elastic
    if trial > limit:
        s = limit / trial
        for d in range(3):
            shear[c, d] *= s
    for d in range(3):
        out_force[d] = -kt * shear[c, d]


@njit(cache=True, error_model="numpy", inline="always")
def _point_velocity(pos, vel, omega, b, point, out):
    """Velocity of the material point ``point`` of body b: v + omega x (point - x).

    ``vel``/``omega`` are the body velocities to use: the half-step ones for the
    contact law, the full-step ones for the energy ledger.
    """
    rx = point[0] - pos[b, 0]
    ry = point[1] - pos[b, 1]
    rz = point[2] - pos[b, 2]
    out[0] = vel[b, 0] + omega[b, 1] * rz - omega[b, 2] * ry
    out[1] = vel[b, 1] + omega[b, 2] * rx - omega[b, 0] * rz
    out[2] = vel[b, 2] + omega[b, 0] * ry - omega[b, 1] * rx


@njit(cache=True, error_model="numpy", inline="always")
def _apply(bodies, b, point, f, sign):
    bodies.force[b, 0] += sign * f[0]
    bodies.force[b, 1] += sign * f[1]
    bodies.force[b, 2] += sign * f[2]
    rx = point[0] - bodies.pos[b, 0]
    ry = point[1] - bodies.pos[b, 1]
    rz = point[2] - bodies.pos[b, 2]
    bodies.torque[b, 0] += sign * (ry * f[2] - rz * f[1])
    bodies.torque[b, 1] += sign * (rz * f[0] - rx * f[2])
    bodies.torque[b, 2] += sign * (rx * f[1] - ry * f[0])


@njit(cache=True, error_model="numpy", inline="always")
def _separate(bodies, spheres, contacts, c, bi, bj, n, gap, dt, point, f):
    """End contact c at the first step without overlap (``gap <= 0``, normal ``n``).

    Applies the impulse the last kick in contact missed (:func:`end_impulse`) and keeps
    ``overlap = gap`` and ``vn`` = the separation speed of the last drift, from which the
    event time is interpolated.  Returns the tangential elastic energy, which the Coulomb
    limit (-> 0 with the normal force) releases by slip at separation (booked as friction
    dissipation: minus the change of the stored energy).
    """
    last = contacts.overlap[c]
    f_elastic, f_viscous = end_impulse(last, gap, contacts.kn[c], contacts.cn[c], dt)
    contacts.fn[c] = f_elastic + f_viscous
    contacts.fn_viscous[c] = f_viscous
    contacts.vn[c] = (last - gap) / dt
    contacts.overlap[c] = gap
    if f_elastic + f_viscous != 0.0:
        for d in range(3):
            f[d] = (f_elastic + f_viscous) * n[d]
        if bj >= 0:
            _apply(bodies, bj, point, f, 1.0)
        _apply(bodies, bi, point, f, -1.0)
    u = contacts.shear
    released = 0.5 * contacts.kt[c] * (u[c, 0] * u[c, 0] + u[c, 1] * u[c, 1] + u[c, 2] * u[c, 2])
    contacts.active[c] = 0
    for d in range(3):
        u[c, d] = 0.0
    return released


@njit(cache=True, error_model="numpy", _nrt=False)
def compute_forces(bodies, spheres, walls, contacts, dt, ledger, changes, first_step, work):
    """Contact forces and torques on all bodies for the current positions.

    ``ledger[0]`` -= change of the energy stored in the tangential springs (the work of
    the tangential and dashpot forces is booked after the kick, from
    :func:`contact_power` with the full-step velocities).  Every contact that
    starts or ends is appended to ``changes`` as ``(c, kind)`` rows; returns their count.
    ``first_step``: the initial configuration, no shear increment (no previous step).
    ``work``: (6, 3) scratch array, preallocated by the caller (no allocation per step).
    """
    bodies.force[:, :] = 0.0
    bodies.torque[:, :] = 0.0
    n = work[0]
    point = work[1]
    vi = work[2]
    vj = work[3]
    fs = work[4]
    f = work[5]
    n_changes = 0
    for c in range(contacts.n[0]):
        i = contacts.i[c]
        j = contacts.j[c]
        bi = spheres.body[i]
        Ri = spheres.radius[i]
        if j >= 0:
            bj = spheres.body[j]
            dx = spheres.pos[j, 0] - spheres.pos[i, 0]
            dy = spheres.pos[j, 1] - spheres.pos[i, 1]
            dz = spheres.pos[j, 2] - spheres.pos[i, 2]
            rsum = Ri + spheres.radius[j]
            d2 = dx * dx + dy * dy + dz * dz
            if d2 >= rsum * rsum and not contacts.active[c]:
                if contacts.fn_viscous[c] != 0.0:  # (store only if needed: most pairs idle)
                    contacts.fn_viscous[c] = 0.0
                continue
            dist = math.sqrt(d2)
            n[0] = dx / dist
            n[1] = dy / dist
            n[2] = dz / dist
            overlap = rsum - dist
        else:
            bj = -1
            w = -j - 1
            dist = 0.0
            for d in range(3):
                dist += (spheres.pos[i, d] - walls.point[w, d]) * walls.normal[w, d]
            if dist >= Ri and not contacts.active[c]:
                if contacts.fn_viscous[c] != 0.0:
                    contacts.fn_viscous[c] = 0.0
                continue
            for d in range(3):
                n[d] = -walls.normal[w, d]
            overlap = Ri - dist
        # contact point midway through the overlap (as YADE's ScGeom)
        for d in range(3):
            point[d] = spheres.pos[i, d] + (Ri - 0.5 * overlap) * n[d]
        if overlap <= 0.0:  # an active contact opened in the last drift
            ledger[0] += _separate(bodies, spheres, contacts, c, bi, bj, n, overlap, dt, point, f)
            changes[n_changes, 0] = c
            changes[n_changes, 1] = END
            n_changes += 1
            continue
        new_contact = not contacts.active[c]
        if new_contact:
            contacts.active[c] = 1
            for d in range(3):
                contacts.shear[c, d] = 0.0
            changes[n_changes, 0] = c
            changes[n_changes, 1] = ONSET
            n_changes += 1
        _point_velocity(bodies.pos, bodies.vel, bodies.omega, bi, point, vi)
        spin = 0.0
        if bj >= 0:
            _point_velocity(bodies.pos, bodies.vel, bodies.omega, bj, point, vj)
            for d in range(3):
                spin += 0.5 * n[d] * (bodies.omega[bi, d] + bodies.omega[bj, d])
        else:
            for d in range(3):
                vj[d] = 0.0  # walls are fixed
                spin += 0.5 * n[d] * bodies.omega[bi, d]
        vn = 0.0
        for d in range(3):
            vn += (vj[d] - vi[d]) * n[d]
        # tangential: rotate history, add the tangential relative displacement of this step
        shear = contacts.shear
        stored = shear[c, 0] * shear[c, 0] + shear[c, 1] * shear[c, 1] + shear[c, 2] * shear[c, 2]
        rotate_shear(shear, c, n, spin * dt)
        # (none at the first step: the initial positions have no previous step)
        increment = 0.0 if first_step else dt
        for d in range(3):
            shear[c, d] += (vj[d] - vi[d] - vn * n[d]) * increment
        weight, overlap_kick = onset_averaged_overlap(overlap, vn, dt, new_contact)
        fn_elastic = contacts.kn[c] * overlap_kick
        cundall_strack(shear, c, contacts.kt[c], contacts.mu[c], fn_elastic, fs)
        # friction ledger, part 1: minus the change of the energy stored in the spring
        stored -= shear[c, 0] * shear[c, 0] + shear[c, 1] * shear[c, 1] + shear[c, 2] * shear[c, 2]
        ledger[0] += 0.5 * contacts.kt[c] * stored
        # dashpot: the normal velocity at t_n, extrapolated from the last two half steps
        vn_dashpot = vn if new_contact else 1.5 * vn - 0.5 * contacts.vn[c]
        contacts.vn[c] = vn
        fn_viscous = -contacts.cn[c] * vn_dashpot * weight
        fn = fn_elastic + fn_viscous
        contacts.overlap[c] = overlap
        contacts.fn[c] = fn
        contacts.fn_viscous[c] = fn_viscous
        for d in range(3):
            f[d] = fn * n[d] + fs[d]
        if bj >= 0:
            _apply(bodies, bj, point, f, 1.0)
        _apply(bodies, bi, point, f, -1.0)
    return n_changes


@njit(cache=True, error_model="numpy", _nrt=False)
def contact_power(bodies, spheres, walls, contacts, out, work):
    """Power [W] at t_n of the dashpot forces (``out[0]``) and of the tangential forces
    (``out[1]``) on the bodies: ``F . v_rel`` with the full-step relative velocity of the
    contact point (``v_n``, the velocity in which the kinetic-energy change of velocity
    Verlet is exact to O(dt^3) per step).  The caller integrates them with the trapezoidal
    rule; the friction dissipation is minus the tangential work minus the change of the
    energy stored in the springs (booked in :func:`compute_forces`), which closes the
    balance to O(dt^2) with rotating bodies and turning contact frames as well.

    The dashpot force is ``contacts.fn_viscous`` (including the dashpot part of an end
    impulse, :func:`end_impulse`).  The elastic onset/end corrections are part of the
    elastic force and are not booked, for elastic and viscous materials alike.
    ``work``: (>= 4, 3) scratch array.
    """
    n = work[0]
    point = work[1]
    vi = work[2]
    vj = work[3]
    p_viscous = 0.0
    p_friction = 0.0
    for c in range(contacts.n[0]):
        fd = contacts.fn_viscous[c]
        u = contacts.shear
        if fd == 0.0 and (not contacts.active[c] or u[c, 0] == u[c, 1] == u[c, 2] == 0.0):
            continue  # (ended contacts have zero shear)
        i = contacts.i[c]
        j = contacts.j[c]
        bi = spheres.body[i]
        if j >= 0:
            dist = 0.0
            for d in range(3):
                n[d] = spheres.pos[j, d] - spheres.pos[i, d]
                dist += n[d] * n[d]
            dist = math.sqrt(dist)
            for d in range(3):
                n[d] /= dist
        else:
            for d in range(3):
                n[d] = -walls.normal[-j - 1, d]
        for d in range(3):
            point[d] = spheres.pos[i, d] + (spheres.radius[i] - 0.5 * contacts.overlap[c]) * n[d]
        _point_velocity(bodies.pos, bodies.vel_full, bodies.omega_full, bi, point, vi)
        if j >= 0:
            _point_velocity(
                bodies.pos, bodies.vel_full, bodies.omega_full, spheres.body[j], point, vj
            )
        else:
            for d in range(3):
                vj[d] = 0.0
        kt = contacts.kt[c]
        for d in range(3):
            dv = vj[d] - vi[d]
            p_viscous += fd * n[d] * dv
            p_friction -= kt * u[c, d] * dv
    out[0] = p_viscous
    out[1] = p_friction


@njit(cache=True, error_model="numpy")
def active_contact_forces(spheres, walls, contacts, first, second, point, force):
    """The contact forces of the last :func:`compute_forces`, one row per active contact.

    Writes from row 0 on and returns the number of rows.  Sphere-sphere contact:
    ``first = i``, ``second = j`` (sphere ids), ``force`` the force on ``j``
    (``fn n - kt u_s``, normal + tangential, as applied in the last kick).  Sphere-wall
    contact: ``first = -(wall + 1)``, ``second = i``, ``force`` the force on the sphere
    (so that ``force`` always acts on ``second``).  ``point`` (3,) [m] the contact point
    midway through the overlap (as in :func:`compute_forces`).  The end impulse of a
    contact that opened in the last drift (:func:`end_impulse`) is not recorded.
    Row arrays: ``first, second`` (K,) int64, ``point, force`` (K, 3), K >= active count.
    """
    k = 0
    for c in range(contacts.n[0]):
        if not contacts.active[c]:
            continue
        i = contacts.i[c]
        j = contacts.j[c]
        u = contacts.shear[c]
        kt = contacts.kt[c]
        fn = contacts.fn[c]
        if j >= 0:
            dist = 0.0
            for d in range(3):  # (point[k] holds the centre-to-centre vector first)
                point[k, d] = spheres.pos[j, d] - spheres.pos[i, d]
                dist += point[k, d] * point[k, d]
            dist = math.sqrt(dist)
            reach = spheres.radius[i] - 0.5 * contacts.overlap[c]
            for d in range(3):
                nd = point[k, d] / dist
                force[k, d] = fn * nd - kt * u[d]
                point[k, d] = spheres.pos[i, d] + reach * nd
            first[k] = i
            second[k] = j
        else:
            reach = spheres.radius[i] - 0.5 * contacts.overlap[c]
            for d in range(3):
                nd = -walls.normal[-j - 1, d]
                force[k, d] = -(fn * nd - kt * u[d])  # on the sphere
                point[k, d] = spheres.pos[i, d] + reach * nd
            first[k] = j
            second[k] = i
        k += 1
    return k
