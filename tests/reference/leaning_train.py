"""The leaning domino train (Shaw 1978; van Leeuwen 2010) by brute-force multibody dynamics.

Model (2D, SI units throughout: m, s, rad, rad/s, kg, N, J). Identical rigid rectangular
dominoes of height ``h``, thickness ``s`` and mass ``m`` (a parameter, 1 kg by default; the
kinematics do not depend on it, forces and energies scale with it) stand at pitch
``lam = gap + s``. Domino i occupies x in [i lam - s, i lam] when upright and tips forward by
the angle ``theta_i`` >= 0 about its front-bottom edge P_i = (i lam, 0), a fixed pivot (no
slip, no lift). In body coordinates (u across the domino, forward; w along it, up) a point
is P_i + u e_u + w e_w with e_u = (cos theta, -sin theta) and e_w = (sin theta, cos theta);
the domino is u in [-s, 0], w in [0, h]. Moment of inertia about the pivot
I = m (h^2 + s^2) / 3, gravity torque (forward positive) m g (h sin theta - s cos theta) / 2.

Once domino i's top-front corner C_i = P_i + h e_w(theta_i) has touched the back face
(u = -s) of domino i+1, it stays on that face for ever (perfectly inelastic, persistent
contact) and slides along it with Coulomb friction ``mu``. The struck dominoes form the
"train".

Method: N rigid bodies with N - 1 bilateral constraints and Lagrange multipliers, not a
reduction to one degree of freedom. Each domino keeps its own angle and angular velocity
as state variables. At a contact between the rear domino i and the front domino j = i+1,
with the normal n = e_u(theta_j) (into j) and the tangent t = e_w(theta_j) (up j's face):

- the contact point is C_i; its lever arms are r_i = C_i - P_i and r = C_i - P_j;
- the penetration is delta = r . n + s (zero on the constraint), its rate the relative
  normal velocity v_n = G_n omega with G_n[i] = r_i^perp . n, G_n[j] = -r^perp . n, where
  r^perp = (r_y, -r_x) is the velocity of the point r per unit forward angular velocity;
- the slip speed of the corner over the face is v_t = G_t omega, built the same way with t;
- the normal force N >= 0 pushes j along +n and i along -n; friction T = mu sigma N,
  sigma = sign(v_t), pushes j along +t and the corner along -t. Their torques about the
  pivots (forward positive: r^perp . F) are the generalized force -(G_n + mu S G_t)^T N,
  S = diag(sigma).

Every right-hand-side evaluation solves the constrained Newton-Euler equations for the
angular accelerations and the normal forces at once (a dense (N + C) x (N + C) system):

    I theta'' + (G_n + mu S G_t)^T N = tau_gravity,
    G_n theta'' = -kappa - 2 a v_n - a^2 delta          (Baumgarte stabilisation, rate a),

where kappa = -omega_i^2 r_i . n - 2 omega_i omega_j r_i^perp . t - omega_j^2 r . n is the
velocity-dependent part of delta'' (so delta'' = G_n theta'' + kappa). Two extra states
integrate the friction loss mu sum N |v_t| and the work sum N v_n of the normal forces on
the (Baumgarte-controlled) constraint drift, which closes the energy balance:

    potential released + push = kinetic + collision loss + friction loss + constraint work,

the push being the initial kinetic energy I omega0^2 / 2 and the constraint work a
numerical residual (~1e-14 of the potential released).

A collision (domino k's corner reaches domino k+1: h sin theta_k = gap, found by an event
of ``solve_ivp``) is a linear impulse problem over the whole train: the post-impact angular
velocities and the normal impulses P at all contacts (the new one and all persistent ones)
with tangential impulses mu sigma P,

    I (omega+ - omega-) + (G_n + mu S G_t)^T P = 0,      G_n omega+ = 0,

so that after the impulse every contact, old and new, holds at velocity level. Friction
direction in an impact: sigma is the sign of the POST-impact slip velocity (found by
iterating from the pre-impact sign until self-consistent; an inconsistency raises). With
all impulses applied proportionally, the slip velocity varies linearly between its pre-
and post-impact values, so it reverses within the impulse exactly when the two signs
differ; such contacts are counted in ``slip_reversals`` (with the rule above, the friction
of the whole impulse acts against the final sliding direction). A persistent contact must
keep N >= 0 and P >= 0; a negative value, a reversal of the sliding direction during the
continuous motion, a front that stalls (its angular velocity reaches zero) or a corner that
leaves the face raise ``RuntimeError``. Contacts other than corner-on-face (e.g. with the
floor, or of domino i with i+2) are not modelled.

Why this is independent of a one-degree-of-freedom reduction: there is no elimination of
the constraints and no kinematic chain rule relating the angles. The constraints enter only
through the vector geometry above (lever arms, normals, tangents); the normal forces and
impulses are unknowns of linear systems, and the train's single degree of freedom emerges
from the constraint forces. Energies are bookkept separately rather than used to advance
the motion.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.integrate import solve_ivp

G = 9.81  # standard gravity [m/s^2]
BAUMGARTE = 10.0  # Baumgarte rate a, in units of sqrt(g / h)
FORCE_TOL = 1e-9  # tolerated negative normal force / impulse, relative to m g / m g sqrt(h/g)


@dataclass(frozen=True)
class Train:
    """Domino geometry and material: height ``h``, thickness ``s``, gap [m], friction
    coefficient ``mu`` [-], mass ``m`` [kg], gravity ``g`` [m/s^2]."""

    h: float
    s: float
    gap: float
    mu: float
    m: float = 1.0
    g: float = G

    @property
    def pitch(self) -> float:
        """lam = gap + s [m], the distance between neighbouring pivots."""
        return self.gap + self.s

    @property
    def inertia(self) -> float:
        """Moment of inertia about the pivot edge, m (h^2 + s^2) / 3 [kg m^2]."""
        return self.m * (self.h**2 + self.s**2) / 3.0

    @property
    def baumgarte(self) -> float:
        """Baumgarte stabilisation rate a [1/s]."""
        return BAUMGARTE * math.sqrt(self.g / self.h)


def _perp(r):
    """Velocity per unit forward (clockwise) angular velocity of the point at ``r`` from
    its pivot: (r_y, -r_x). ``r``: shape (..., 2)."""
    return np.stack([r[..., 1], -r[..., 0]], axis=-1)


def _dot(a, b):
    """Row-wise dot product of (..., 2) arrays."""
    return np.sum(a * b, axis=-1)


@dataclass(frozen=True)
class Contacts:
    """Kinematics of the C = N - 1 contacts of a train of N dominoes.

    ``g_n``, ``g_t``: shape (C, N), normal and tangential velocity Jacobians [m];
    ``delta``: penetration [m] (C,); ``v_n``: normal approach velocity [m/s] (C,);
    ``v_t``: slip velocity of the corner up the face [m/s] (C,); ``kappa``: the
    velocity-dependent part of delta'' [m/s^2] (C,); ``w``: the contact's distance from the
    bottom of the front domino's back face [m] (C,)."""

    g_n: np.ndarray
    g_t: np.ndarray
    delta: np.ndarray
    v_n: np.ndarray
    v_t: np.ndarray
    kappa: np.ndarray
    w: np.ndarray


def contacts(p: Train, theta, omega) -> Contacts:
    """Contact kinematics of the train (angles ``theta`` [rad], angular velocities ``omega``
    [rad/s], shape (N,)): corner of domino i on the back face of domino i + 1."""
    a, b = theta[:-1], theta[1:]
    wa, wb = omega[:-1], omega[1:]
    r_i = p.h * np.stack([np.sin(a), np.cos(a)], axis=-1)  # corner from the rear pivot
    r = r_i - np.array([p.pitch, 0.0])  # corner from the front pivot
    n = np.stack([np.cos(b), -np.sin(b)], axis=-1)
    t = np.stack([np.sin(b), np.cos(b)], axis=-1)
    pi, pr = _perp(r_i), _perp(r)
    c, k = len(a), np.arange(len(a))
    g_n, g_t = np.zeros((c, c + 1)), np.zeros((c, c + 1))
    g_n[k, k], g_n[k, k + 1] = _dot(pi, n), -_dot(pr, n)
    g_t[k, k], g_t[k, k + 1] = _dot(pi, t), -_dot(pr, t)
    kappa = -(wa**2) * _dot(r_i, n) - 2.0 * wa * wb * _dot(pi, t) - wb**2 * _dot(r, n)
    return Contacts(
        g_n=g_n,
        g_t=g_t,
        delta=_dot(r, n) + p.s,
        v_n=g_n @ omega,
        v_t=g_t @ omega,
        kappa=kappa,
        w=_dot(r, t),
    )


def gravity_torque(p: Train, theta):
    """Forward gravity torque about each pivot [N m], m g (h sin theta - s cos theta) / 2,
    shape of ``theta``."""
    return 0.5 * p.m * p.g * (p.h * np.sin(theta) - p.s * np.cos(theta))


def potential_released(p: Train, theta) -> float:
    """Potential energy released [J] by dominoes at angles ``theta`` (N,) since upright:
    sum of m g (h/2 - y_cm), y_cm = (s sin theta + h cos theta) / 2."""
    y_cm = 0.5 * (p.s * np.sin(theta) + p.h * np.cos(theta))
    return float(p.m * p.g * np.sum(0.5 * p.h - y_cm))


def _saddle(p: Train, kin: Contacts, sigma, rhs_top, rhs_bottom):
    """Solve [[I 1, B^T], [G_n, 0]] [x; f] = [rhs_top; rhs_bottom], B = G_n + mu S G_t:
    (x (N,), f (C,))."""
    n, c = kin.g_n.shape[1], kin.g_n.shape[0]
    a = np.zeros((n + c, n + c))
    a[:n, :n] = p.inertia * np.eye(n)
    a[:n, n:] = (kin.g_n + p.mu * sigma[:, None] * kin.g_t).T
    a[n:, :n] = kin.g_n
    sol = np.linalg.solve(a, np.concatenate([rhs_top, rhs_bottom]))
    return sol[:n], sol[n:]


def accelerations(p: Train, theta, omega, sigma):
    """Angular accelerations [rad/s^2] (N,) and normal forces [N] (C,) of the train, with
    sliding directions ``sigma`` (C,) (+1: the corner slides up the face)."""
    kin = contacts(p, theta, omega)
    a = p.baumgarte
    bottom = -kin.kappa - 2.0 * a * kin.v_n - a * a * kin.delta
    acc, normal = _saddle(p, kin, sigma, gravity_torque(p, theta), bottom)
    return acc, normal, kin


def _impulse_once(p: Train, kin: Contacts, omega, sigma):
    """Post-impact angular velocities (N,) and normal impulses (C,) for fixed ``sigma``."""
    d_omega, impulse = _saddle(p, kin, sigma, np.zeros_like(omega), -kin.v_n)
    return omega + d_omega, impulse


def impact(p: Train, theta, omega):
    """The collision impulse problem over the whole train (angles ``theta`` [rad] and
    pre-impact angular velocities ``omega`` [rad/s], shape (N,), all N - 1 contacts closed).

    Returns (omega_after (N,) [rad/s], normal impulses (C,) [N s], sigma (C,), number of
    contacts whose sliding direction reverses within the impulse). ``sigma`` is the sign
    of the post-impact slip, found self-consistently starting from the pre-impact one."""
    kin = contacts(p, theta, omega)
    sigma_before = np.where(kin.v_t > 0.0, 1.0, -1.0)
    sigma = sigma_before.copy()
    for _ in range(len(sigma) + 2):
        after, impulse = _impulse_once(p, kin, omega, sigma)
        v_t = kin.g_t @ after
        new = np.where(v_t > 0.0, 1.0, np.where(v_t < 0.0, -1.0, sigma))
        if np.array_equal(new, sigma) or p.mu == 0.0:
            return after, impulse, sigma, int(np.sum(sigma != sigma_before))
        sigma = new
    raise RuntimeError("no self-consistent sliding direction in the impact")


def _rhs(_t, y, p: Train, sigma):
    """ODE right-hand side: y = [theta (N), omega (N), friction loss, constraint work]."""
    n = (len(y) - 2) // 2
    theta, omega = y[:n], y[n : 2 * n]
    acc, normal, kin = accelerations(p, theta, omega, sigma)
    friction = p.mu * float(normal @ (sigma * kin.v_t))
    work = float(normal @ kin.v_n)
    return np.concatenate([omega, acc, [friction, work]])


def _events(p: Train, sigma, atol):
    """Terminal events of one segment: the front domino's corner reaches the next domino
    (h sin theta_front - gap rising through zero); the front stalls (omega_front falling
    through zero); a contact's sliding reverses (min sigma v_t falling through -10 atol h,
    a noise floor: far behind the front the dominoes come to rest geometrically, their
    angular velocities shrinking ~0.7x per domino, and may fall below ``atol``)."""
    floor = 10.0 * atol * p.h

    def hit(_t, y):
        n = (len(y) - 2) // 2
        return p.h * math.sin(y[n - 1]) - p.gap

    def stall(_t, y):
        return y[len(y) - 3]

    def slip(_t, y):
        n = (len(y) - 2) // 2
        if n < 2:
            return 1.0
        return float(np.min(sigma * contacts(p, y[:n], y[n : 2 * n]).v_t)) + floor

    for event in (hit, stall, slip):
        event.terminal, event.direction = True, -1
    hit.direction = 1
    return [hit, stall, slip]


def _check_segment(p: Train, sol, sigma, stats):
    """Normal forces >= 0 and the corners on their faces at every accepted step of a
    segment; updates ``stats`` (min force, max |delta|)."""
    n = (sol.y.shape[0] - 2) // 2
    if n < 2:
        return
    for y in sol.y.T:
        _, normal, kin = accelerations(p, y[:n], y[n : 2 * n], sigma)
        stats["min_normal_force"] = min(stats["min_normal_force"], float(normal.min()))
        stats["max_penetration"] = max(stats["max_penetration"], float(np.abs(kin.delta).max()))
        if normal.min() < -FORCE_TOL * p.m * p.g:
            raise RuntimeError(f"negative normal force {normal.min():.3g} N: a contact opens")
        if kin.w.min() <= 0.0 or kin.w.max() >= p.h:
            raise RuntimeError("a corner left the face it leans on")


def _fall(p: Train, t0, y0, sigma, rtol, atol, stats):
    """Integrate one segment until the front's corner reaches the next domino: (time of
    the hit [s], state there)."""
    t_end = t0 + 1e3 * math.sqrt(p.h / p.g)
    sol = solve_ivp(lambda t, y: _rhs(t, y, p, sigma), (t0, t_end), y0, method="DOP853",
                    rtol=rtol, atol=atol, events=_events(p, sigma, atol))  # fmt: skip
    if sol.status != 1:
        raise RuntimeError(f"no impact before t = {t_end:.3g} s ({sol.message})")
    _check_segment(p, sol, sigma, stats)
    if sol.t_events[1].size:
        raise RuntimeError(f"the train stalled at t = {sol.t_events[1][0]:.6g} s")
    if sol.t_events[2].size:
        raise RuntimeError(f"a contact's sliding reversed at t = {sol.t_events[2][0]:.6g} s")
    return sol.t_events[0][0], sol.y_events[0][0]


def _check_push(p: Train, omega0):
    """Raise ValueError if the geometry is invalid or domino 0 cannot pass its tipping
    point: (1/2) I omega0^2 must exceed m g (sqrt(h^2 + s^2) - h) / 2."""
    if not 0.0 < p.gap < p.h or p.s <= 0.0 or p.mu < 0.0:
        raise ValueError("need 0 < gap < height, thickness > 0 and friction >= 0")
    barrier = 0.5 * p.m * p.g * (math.hypot(p.h, p.s) - p.h)
    if 0.5 * p.inertia * omega0**2 <= barrier:
        raise ValueError(
            f"omega0 = {omega0:.6g} rad/s does not carry domino 0 over its tipping point "
            f"(needs > {math.sqrt(2 * barrier / p.inertia):.6g} rad/s)"
        )


def _collide(p: Train, y, stats, record):
    """Add the upright next domino to the train state ``y`` at the hit and apply the
    impulse: (new state, sliding directions for the next segment)."""
    n = (len(y) - 2) // 2
    theta = np.append(y[:n], 0.0)
    before = np.append(y[n : 2 * n], 0.0)
    after, impulse, sigma, reversals = impact(p, theta, before)
    scale = p.m * math.sqrt(p.g * p.h)
    if impulse.min() < -FORCE_TOL * scale:
        raise RuntimeError(f"negative normal impulse {impulse.min():.3g} N s")
    kinetic = 0.5 * p.inertia
    record["collision_loss"] += float(kinetic * (before @ before - after @ after))
    record["omega_front_before"].append(before[-2])
    record["omega_front_after"].append(after[-1])
    record["omega_striker_after"].append(after[-2])
    record["normal_impulses"].append(impulse)
    stats["min_normal_impulse"] = min(stats["min_normal_impulse"], float(impulse.min()))
    stats["slip_reversals"] += reversals
    v_n = contacts(p, theta, after).v_n
    stats["max_post_impact_v_n"] = max(stats["max_post_impact_v_n"], float(np.abs(v_n).max()))
    post = contacts(p, theta, after).v_t
    sigma = np.where(post > 0.0, 1.0, -1.0)
    return np.concatenate([theta, after, y[2 * n :]]), sigma


def simulate_train(
    *,
    height,
    thickness,
    gap,
    friction,
    omega0,
    n_dominoes,
    g=G,
    rtol=1e-10,
    atol=1e-12,
    mass=1.0,
) -> dict:
    """Simulate the leaning train from the push of domino 0 (upright, angular velocity
    ``omega0`` [rad/s] at t = 0) until domino ``n_dominoes - 1`` is struck.

    ``height``, ``thickness``, ``gap`` [m]; ``friction``: Coulomb coefficient at the
    corner-on-face contacts; ``mass`` [kg] (1 kg default; only forces and energies depend on
    it); ``rtol``, ``atol``: DOP853 tolerances (``atol`` applies to angles [rad], angular
    velocities [rad/s] and the energy states [J]).

    Returns a dict: ``hit_times`` [s] (n-1,), the time domino i+1 is struck;
    ``omega_front_after`` [rad/s] (n-1,), the struck domino's angular velocity just after;
    ``omega_front_before`` / ``omega_striker_after`` [rad/s] (n-1,), the striker's just
    before / after; ``normal_impulses``: list of n-1 arrays [N s] (shapes (1,)..(n-1,)),
    the impulses at contacts 0..k of collision k; ``theta_final``, ``omega_final`` (n,)
    right after the last collision; ``energy``: dict of ``potential_released``,
    ``kinetic`` (final), ``initial_kinetic`` (the push, I omega0^2 / 2),
    ``collision_loss``, ``friction_loss``, ``constraint_work`` (normal forces times the
    constraint drift rate, integrated; ~0) and ``residual`` (potential_released +
    initial_kinetic - kinetic - collision_loss - friction_loss) [J]; diagnostics
    ``min_normal_force`` [N], ``min_normal_impulse`` [N s], ``max_penetration`` [m],
    ``max_post_impact_v_n`` [m/s], ``slip_reversals`` (count of impact reversals),
    ``pitch`` [m], ``inertia`` [kg m^2].

    Raises ValueError if the push cannot tip domino 0; RuntimeError if a contact would open
    (negative force or impulse), a sliding direction reverses, or the train stalls.
    """
    if n_dominoes < 2:
        raise ValueError("need at least two dominoes")
    p = Train(height, thickness, gap, friction, mass, g)
    _check_push(p, omega0)
    record = {"collision_loss": 0.0, "omega_front_before": [], "omega_front_after": [],
              "omega_striker_after": [], "normal_impulses": []}  # fmt: skip
    stats = {"min_normal_force": math.inf, "min_normal_impulse": math.inf, "max_penetration": 0.0,
             "max_post_impact_v_n": 0.0, "slip_reversals": 0}  # fmt: skip
    t, y, sigma, hits = 0.0, np.array([0.0, omega0, 0.0, 0.0]), np.zeros(0), []
    for _ in range(n_dominoes - 1):
        t, y = _fall(p, t, y, sigma, rtol, atol, stats)
        hits.append(t)
        y, sigma = _collide(p, y, stats, record)
    return _result(p, omega0, y, hits, record, stats)


def _result(p: Train, omega0, y, hits, record, stats) -> dict:
    """Assemble the output dict of ``simulate_train`` from the final state ``y``."""
    n = (len(y) - 2) // 2
    theta, omega = y[:n], y[n : 2 * n]
    energy = {
        "potential_released": potential_released(p, theta),
        "kinetic": 0.5 * p.inertia * float(omega @ omega),
        "collision_loss": record["collision_loss"],
        "friction_loss": float(y[2 * n]),
        "constraint_work": float(y[2 * n + 1]),
        "initial_kinetic": 0.5 * p.inertia * omega0**2,
    }
    energy["residual"] = (
        energy["potential_released"]
        + energy["initial_kinetic"]
        - energy["kinetic"]
        - energy["collision_loss"]
        - energy["friction_loss"]
    )
    out = {key: np.array(record[key]) for key in
           ("omega_front_before", "omega_front_after", "omega_striker_after")}  # fmt: skip
    out.update(stats)
    out.update(hit_times=np.array(hits), normal_impulses=record["normal_impulses"],
               theta_final=theta.copy(), omega_final=omega.copy(), energy=energy,
               pitch=p.pitch, inertia=p.inertia)  # fmt: skip
    return out
