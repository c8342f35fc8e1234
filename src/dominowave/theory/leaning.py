"""The leaning train of real dominoes: inelastic collisions and friction between dominoes.

Model of D. E. Shaw, Am. J. Phys. 46, 640 (1978), worked out by J. M. J. van Leeuwen,
"The domino effect", Am. J. Phys. 78, 721 (2010) (arXiv:physics/0401018): rigid
dominoes of height ``l``, thickness ``s`` and clear gap ``d`` (pitch ``lam = d + s``),
each tipping about its front-bottom edge, which neither slips nor lifts. A domino that
strikes the next one stays on it (perfectly inelastic collision): its top-front corner
slides down the next one's back face, and every domino hit so far leans on its front
neighbour -- a *train* with one degree of freedom. Coulomb friction ``mu`` acts at every
corner-on-face contact, in the leaning motion and in the collisions. Every equation
below is derived in ``docs/theory.md`` (section "The leaning train"); the papers' texts
were not at hand, so no equation number of theirs is cited.

Geometry (angles from the vertical, forward positive, domino 0 the front)::

    l sin(theta_k - theta_{k-1}) = lam cos(theta_{k-1}) - s           (contact k)

so ``theta_k = F(theta_{k-1})`` with ``F(phi) = phi + asin((lam cos phi - s) / l)``: the
front angle fixes the whole train. The front strikes the next domino at
``beta = asin(d / l)`` (= ``F(0)``, as in the paper's ``d = l sin beta``), and the tail
approaches the rest angle ``theta_* = acos(s / lam)``, where neighbours lie face to face.

Dynamics. With ``Phi_k = d theta_k / d theta_0``, Newton-Euler about each pivot,

    I theta_k'' = G(theta_k) + N_{k+1} A_{k+1} - N_k B_k,
    I = (l^2 + s^2) / 3,   G(theta) = g (l sin theta - s cos theta) / 2   (per unit mass),

with the contact force ``N_k`` [N/kg] of the corner of domino ``k`` on the back face of
``k-1``, its lever on the front domino ``A_k = r_k - mu s`` and on the back one
``B_k = l (cos delta_k + mu sin delta_k)``, ``r_k = l cos delta_k - lam sin theta_{k-1}``
the contact's height on the face and ``delta_k = theta_k - theta_{k-1}``. The corner
always slides down the face (slip rate ``-lam Phi_{k-1} cos theta_k / cos delta_k``
times ``theta_0'``), so friction has one sign. Eliminating the ``N_k`` from the tail
forward (one sweep, O(n)) gives the front's equation of motion

    theta_0'' = P(theta_0) + Q(theta_0) theta_0'^2,

which is linear in ``u = theta_0'^2`` as a function of ``theta_0``: ``du/dtheta = 2 P +
2 Q u``. The leaning phase 0 -> beta is solved exactly by an integrating factor; the
integrals are Chebyshev (spectral) quadratures. The collision is the same sweep on
impulses and gives ``omega+ = c omega-``. The steady state of the infinite train is the
fixed point of the affine map ``u -> c^2 (alpha u + b)``.

Every function broadcasts its arguments (NumPy rules); SI units throughout.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np
import scipy.fft

from dominowave.checks import check_in_range
from dominowave.units import G_STANDARD

__all__ = [
    "LeaningSteadyState",
    "LeaningTransient",
    "collision_angle",
    "gap_limits",
    "limit_speed",
    "rest_angle",
    "steady_state",
    "thin_small_gap_speed",
    "transient",
]

NODES = 48
"""Chebyshev nodes on the leaning phase 0 -> beta (spectral: 1e-13 relative, tested)."""
TAIL_TOLERANCE = 1e-16
"""The train is cut where ``Phi_k`` (the tail's share of the motion) falls below this."""
CHUNK = 32
"""Points solved together (bounds the memory of long trains: n x CHUNK x NODES floats)."""
MAX_TRAIN = 20000
"""Longest train computed; only gaps within ~1e-3 of the smallest need more."""


# --- geometry -------------------------------------------------------------------------------


def collision_angle(height, gap):
    """``beta = asin(d / l)`` [rad]: the front's tilt when it strikes the next domino."""
    check_in_range("height", height, 0.0, np.inf)
    check_in_range("gap", gap, 0.0, np.inf)
    return np.arcsin(np.minimum(np.asarray(gap, float) / np.asarray(height, float), 1.0))


def rest_angle(thickness, gap):
    """``theta_* = acos(s / (d + s))`` [rad]: the tilt of the fallen dominoes of the train."""
    check_in_range("thickness", thickness, 0.0, np.inf, lo_inclusive=True)
    check_in_range("gap", gap, 0.0, np.inf)
    s = np.asarray(thickness, float)
    return np.arccos(s / (s + np.asarray(gap, float)))


def _centre_height(theta, l, s):
    """Height of the centre of mass above the floor at tilt ``theta`` [m]."""
    return 0.5 * (l * np.cos(theta) + s * np.sin(theta))


def _train_length(l, s, lam):
    """Number of dominoes after which the tail no longer matters (at least 2).

    The train behind a front at 0 is followed until ``Phi_k < TAIL_TOLERANCE`` (the tail's
    share of the motion) and the tilt is within 1e-12 rad of ``theta_*`` (the tail's push
    is the fixed point's). Near the tail ``Phi`` shrinks by ``F'(theta_*) = 1 - lam
    sin(theta_*) / l`` a domino, slowly at small gaps.
    """
    theta, phi, rest = np.zeros_like(lam), np.ones_like(lam), np.arccos(s / lam)
    for k in range(1, MAX_TRAIN + 1):
        sin_d = (lam * np.cos(theta) - s) / l
        lcos = l * np.sqrt(1.0 - sin_d**2)
        phi = phi * np.abs(lcos - lam * np.sin(theta)) / lcos
        theta = theta + np.arcsin(sin_d)
        if np.all(phi < TAIL_TOLERANCE) and np.all(np.abs(theta - rest) < 1e-12):
            return max(k + 1, 2)
    raise ValueError(
        f"gap: a train of more than {MAX_TRAIN} dominoes would be needed; the gap is too"
        " close to the smallest at which a leaning train runs"
    )


@dataclass(frozen=True)
class _Train:
    """Tilts and contact levers of a train whose front is at ``theta[0]``.

    Arrays have shape ``(n + 1, *front)``: dominoes ``j = 0 .. n - 1`` from the front
    back, and index ``n``, the first domino of the tail beyond the train (its lever
    carries the tail's push). Contact ``k`` joins domino ``k`` to ``k - 1``; index 0 of
    the contact arrays is unused (zero).
    """

    theta: np.ndarray  # tilt [rad]
    phi: np.ndarray  # d theta_j / d theta_0 [1]
    psi: np.ndarray  # d^2 theta_j / d theta_0^2 [1/rad]
    lever_front: np.ndarray  # A_k: lever of N_k on domino k - 1 [m]
    lever_back: np.ndarray  # B_k: lever of N_k on domino k [m]
    slip: np.ndarray  # sliding of corner k down the face per front rotation [m/rad]
    height_on_face: np.ndarray  # r_k: contact height on the back face of k - 1 [m]


def _train(theta0, l, s, lam, mu, n) -> _Train:
    """The train of ``n`` dominoes (plus the tail's first) behind a front at ``theta0``."""
    shape = (n + 1, *np.shape(theta0))
    theta, phi, psi = np.zeros(shape), np.zeros(shape), np.zeros(shape)
    a, b, slip, r = np.zeros(shape), np.zeros(shape), np.zeros(shape), np.zeros(shape)
    theta[0], phi[0] = theta0, 1.0
    for k in range(1, n + 1):
        front = theta[k - 1]
        sin_d = (lam * np.cos(front) - s) / l  # the contact constraint: sin(delta_k)
        cos_d = np.sqrt(1.0 - sin_d**2)
        theta[k] = front + np.arcsin(sin_d)
        lcos = l * cos_d
        r[k] = lcos - lam * np.sin(front)
        f1 = r[k] / lcos  # F'(front)
        f2 = -lam * np.cos(front) / lcos + (lam * np.sin(front)) ** 2 * l * sin_d / lcos**3
        phi[k] = f1 * phi[k - 1]
        psi[k] = f1 * psi[k - 1] + f2 * phi[k - 1] ** 2
        a[k] = r[k] - mu * s
        b[k] = lcos + mu * l * sin_d
        slip[k] = lam * phi[k - 1] * np.cos(theta[k]) / cos_d
    return _Train(theta, phi, psi, a, b, slip, r)


def _tail_force(l, s, lam, mu, g):
    """Push [N/kg] of an endless fallen tail on the domino in front of it.

    Deep in the train the dominoes rest at ``theta_*``, where ``B = l`` and
    ``A = l - lam sin(theta_*) - mu s``, and ``N = (G + N A) / B`` has the fixed point
    ``N = G(theta_*) / (lam sin(theta_*) + mu s)``.
    """
    t_star = np.arccos(s / lam)
    grav = 0.5 * g * (l * np.sin(t_star) - s * np.cos(t_star))
    return grav / (lam * np.sin(t_star) + mu * s)


def _sweep(train: _Train, rhs: np.ndarray, tail: np.ndarray) -> np.ndarray:
    """Contact forces (or impulses) from the tail forward.

    Domino ``j``'s balance ``0 = rhs_j + N_{j+1} A_{j+1} - N_j B_j`` is solved for
    ``N_j = (rhs_j + N_{j+1} A_{j+1}) / B_j``, ``j = n-1 .. 1``, from ``N_n = tail``.
    ``rhs`` has shape ``(n, m, *front)`` (``m`` right-hand sides at once), ``tail``
    ``(m, *front)``. Returns shape ``(n + 1, m, *front)``: ``[0]`` the front's residual
    ``rhs_0 + N_1 A_1`` (zero on the solution), ``[k]`` the contact forces.
    """
    n = rhs.shape[0]
    out = np.empty((n + 1, *rhs.shape[1:]))
    out[n] = tail
    a, b = train.lever_front[:, None], train.lever_back[:, None]
    for j in range(n - 1, 0, -1):
        out[j] = (rhs[j] + out[j + 1] * a[j + 1]) / b[j]
    out[0] = rhs[0] + out[1] * a[1]
    return out


@cache
def _chebyshev(m: int):
    """Nodes ``x`` in (-1, 1) and the matrices of spectral calculus on them.

    Returns ``(x, cum, total, end)``: for values ``f`` at the nodes (last axis),
    ``f @ cum`` is ``int_{-1}^{x_i} f``, ``f @ total`` is ``int_{-1}^{1} f`` and
    ``f @ end`` is ``f(1)``, all of the Chebyshev interpolant of degree ``m - 1``.
    """
    x = np.cos(np.pi * (np.arange(m) + 0.5) / m)
    coef = scipy.fft.dct(np.eye(m), type=2, axis=0) / m  # values -> Chebyshev coefficients
    coef[0] /= 2.0
    antider = np.polynomial.chebyshev.chebint(coef, lbnd=-1.0, axis=0)
    cum = np.polynomial.chebyshev.chebval(x, antider)
    total = np.polynomial.chebyshev.chebval(1.0, antider)
    end = np.polynomial.chebyshev.chebval(1.0, coef)
    return x, cum, total, end


@dataclass(frozen=True)
class _Phase:
    """The train's front falling from 0 to beta: ``theta_0'' = P + Q theta_0'^2``.

    Node arrays have shape ``(*front, m)`` (Chebyshev nodes of [0, beta] last).
    """

    beta: np.ndarray  # collision angle [rad], shape front
    p: np.ndarray  # P [1/s^2]
    q: np.ndarray  # Q [1]
    forces: np.ndarray  # contact force per unit (1, theta'', u), shape (n + 1, 3, *front, m)
    friction: np.ndarray  # mu sum_k slip_k N_k per unit (1, theta'', u) [J/kg/rad], (3, *front, m)
    inertia_sum: np.ndarray  # S = sum_j Phi_j^2 at the nodes
    potential: np.ndarray  # g * sum_j (height of centre of mass j) [J/kg] at the nodes
    min_height_on_face: np.ndarray  # smallest r_k over the train [m], shape front


def _phase(l, s, lam, mu, g, n, infinite) -> _Phase:
    """Equation of motion of a train of ``n`` dominoes over its leaning phase.

    ``infinite``: the train continues into an endless fallen tail (its static push acts on
    the last domino); else the last domino is the first one pushed.
    """
    beta = np.arcsin((lam - s) / l)
    x = _chebyshev(NODES)[0]
    theta0 = 0.5 * beta[..., None] * (1.0 + x)
    tr = _train(theta0, l[..., None], s[..., None], lam[..., None], mu[..., None], n)
    inertia = (l**2 + s**2)[..., None] / 3.0
    grav = (
        0.5
        * g[..., None]
        * (l[..., None] * np.sin(tr.theta[:n]) - s[..., None] * np.cos(tr.theta[:n]))
    )
    rhs = np.stack([grav, -inertia * tr.phi[:n], -inertia * tr.psi[:n]], axis=1)
    tail = np.zeros(rhs.shape[1:])
    if infinite:
        tail[0] = _tail_force(l, s, lam, mu, g)[..., None]
    forces = _sweep(tr, rhs, tail)
    resid = forces[0]  # resid_c + resid_acc * theta'' + resid_u * u = 0
    p, q = -resid[0] / resid[1], -resid[2] / resid[1]
    friction = mu[..., None] * np.einsum("k...,km...->m...", tr.slip[1:n], forces[1:n])
    potential = g[..., None] * np.sum(
        _centre_height(tr.theta[:n], l[..., None], s[..., None]), axis=0
    )
    return _Phase(
        beta=beta,
        p=p,
        q=q,
        forces=forces,
        friction=friction,
        inertia_sum=np.sum(tr.phi[:n] ** 2, axis=0),
        potential=potential,
        min_height_on_face=_lowest_contact(tr, n, infinite),
    )


def _lowest_contact(tr: _Train, n: int, infinite: bool) -> np.ndarray:
    """Lowest contact height ``r_k`` on a back face over the phase [m], shape front.

    A negative height means the corner would touch below the face: the fallen dominoes
    lie flat instead of leaning (no train). The endless tail's contact is included.
    """
    last = n + 1 if infinite else n
    if last <= 1:
        return np.full(tr.theta.shape[1:-1], np.inf)
    return np.min(tr.height_on_face[1:last], axis=(0, -1))


@dataclass(frozen=True)
class _Fall:
    """The front's motion over one leaning phase, from ``u0 = theta_0'^2`` at 0."""

    u: np.ndarray  # theta_0'^2 at the nodes [1/s^2], shape (*front, m)
    u_end: np.ndarray  # theta_0'^2 at beta, shape front
    duration: np.ndarray  # time from 0 to beta [s] (nan where the front stops)
    friction_loss: np.ndarray  # work of friction over the phase [J/kg]
    min_force: np.ndarray  # smallest contact force over train and phase [N/kg]


@dataclass(frozen=True)
class _Affine:
    """The leaning phase as a map of ``u0``: ``u = growth (u0 + pushed)`` at the nodes and
    ``u(beta) = gain u0 + offset`` (the integrating factor of ``du/dtheta = 2 (P + Q u)``)."""

    growth: np.ndarray  # exp(int_0^theta 2 Q), shape (*front, m)
    pushed: np.ndarray  # int_0^theta 2 P / growth, shape (*front, m)
    gain: np.ndarray  # shape front
    offset: np.ndarray  # [1/s^2], shape front


def _affine(ph: _Phase) -> _Affine:
    """The integrating factor of the phase ``ph`` on the Chebyshev nodes (independent of
    the front's angular velocity)."""
    _, cum, total, _ = _chebyshev(NODES)
    half = 0.5 * ph.beta[..., None]  # d theta / d x
    qx, px = 2.0 * half * ph.q, 2.0 * half * ph.p
    growth = np.exp(qx @ cum)
    gain = np.exp(qx @ total)
    drive = px / growth
    return _Affine(growth, drive @ cum, gain, gain * (drive @ total))


def _fall(ph: _Phase, u0, affine: _Affine | None = None) -> _Fall:
    """Solve ``du/dtheta = 2 (P + Q u)`` exactly on the nodes from ``u(0) = u0``
    (``affine``: :func:`_affine` of ``ph``, if already at hand)."""
    _, _, total, _ = _chebyshev(NODES)
    half = 0.5 * ph.beta[..., None]  # d theta / d x
    aff = _affine(ph) if affine is None else affine
    gain, offset = aff.gain, aff.offset
    u0 = np.asarray(u0, float)[..., None]
    u = aff.growth * (u0 + aff.pushed)
    accel = ph.p + ph.q * u
    basis = np.stack([np.ones_like(u), accel, u])  # (1, theta'', u) at the nodes
    n = ph.forces.shape[0] - 1
    forces = np.einsum("km...,m...->k...", ph.forces[1:n], basis)  # the real contacts
    friction_power = np.einsum("m...,m...->...", ph.friction, basis)
    with np.errstate(invalid="ignore", divide="ignore"):
        rate = np.where(u > 0.0, 1.0 / np.sqrt(np.where(u > 0.0, u, 1.0)), np.nan)
    duration = half[..., 0] * (rate @ total)
    return _Fall(
        u=u,
        u_end=gain * u0[..., 0] + offset,
        duration=np.where(np.all(u > 0.0, axis=-1), duration, np.nan),
        friction_loss=half[..., 0] * (friction_power @ total),
        min_force=np.min(forces, axis=(0, -1)) if n > 1 else np.full(u.shape[:-1], np.inf),
    )


@dataclass(frozen=True)
class _Collision:
    """The front (at beta) strikes the next domino: ``omega+ = ratio * omega-``."""

    ratio: np.ndarray  # omega+ / omega- [1]
    kinetic_before: np.ndarray  # train's kinetic energy per unit omega-^2 [J s^2/kg]
    kinetic_after: np.ndarray  # new train's, per unit omega-^2 [J s^2/kg]
    min_impulse: np.ndarray  # smallest normal impulse per unit omega- [N s^2/kg]


def _collision(l, s, lam, mu, n) -> _Collision:
    """Impulse balance of the struck domino and the ``n - 1`` dominoes leaning behind it.

    All contacts stay closed (the collision is perfectly inelastic), so just after it the
    new train moves as one: ``omega_j+ = Phi_j omega+``. Just before, the struck domino
    rests and the old train moves with ``omega_j- = Phi_j omega-`` (``F'(0) = 1``: the
    old front turned as fast as the new one will). Domino ``j``'s angular impulse
    ``I (Phi_j omega+ - omega_j-) = J_{j+1} A_{j+1} - J_j B_j``: the sweep of the leaning
    phase, with impulses for forces. Friction impulses are ``mu J`` down the face (the
    corner slides down before, during and after).
    """
    tr = _train(np.zeros(np.shape(l)), l, s, lam, mu, n)
    inertia = (l**2 + s**2) / 3.0
    before = tr.phi[:n].copy()
    before[0] = 0.0
    rhs = np.stack([inertia * before, -inertia * tr.phi[:n]], axis=1)  # per (1, omega+)
    imp = _sweep(tr, rhs, np.zeros(rhs.shape[1:]))
    ratio = -imp[0, 0] / imp[0, 1]
    impulses = imp[1:n, 0] + ratio * imp[1:n, 1]
    return _Collision(
        ratio=ratio,
        kinetic_before=0.5 * inertia * np.sum(before**2, axis=0),
        kinetic_after=0.5 * inertia * ratio**2 * np.sum(tr.phi[:n] ** 2, axis=0),
        min_impulse=np.min(impulses, axis=0) if n > 1 else np.full(np.shape(l), np.inf),
    )


# --- public API -----------------------------------------------------------------------------


def _inputs(height, thickness, gap, friction, g):
    """Validate and broadcast the parameters; return flat float arrays and the shape."""
    check_in_range("height", height, 0.0, np.inf)
    check_in_range("thickness", thickness, 0.0, np.inf, lo_inclusive=True)
    check_in_range("friction", friction, 0.0, np.inf, lo_inclusive=True)
    check_in_range("g", g, 0.0, np.inf)
    arrays = np.broadcast_arrays(
        *(np.asarray(v, float) for v in (height, thickness, gap, friction, g))
    )
    l, s, d, mu, grav = (a.ravel().copy() for a in arrays)
    check_in_range("gap", d, 0.0, np.inf)
    if np.any(d >= l):
        bad = d[np.argmax(d >= l)]
        raise ValueError(
            f"gap = {bad:.6g} is outside the valid range (0, height): across a gap as wide"
            " as the domino is tall it never reaches the next one"
        )
    return l, s, d, mu, grav, arrays[0].shape


@dataclass(frozen=True)
class LeaningSteadyState:
    """The endless leaning train's steady wave; arrays of the broadcast input shape.

    Energies are per kilogram of domino [J/kg]: multiply by the domino's mass. Where no
    steady train runs, ``exists`` is False, ``reason`` says why and the speeds are NaN.
    """

    speed: np.ndarray  # front speed, one pitch per period [m/s]
    period: np.ndarray  # time between two collisions [s]
    omega_after: np.ndarray  # front's angular velocity just after it is struck [rad/s]
    omega_before: np.ndarray  # front's angular velocity when it strikes the next [rad/s]
    collision_ratio: np.ndarray  # omega_after / omega_before of one collision [1]
    released: np.ndarray  # potential energy released per domino [J/kg]
    collision_loss: np.ndarray  # kinetic energy lost in one collision [J/kg]
    friction_loss: np.ndarray  # work of friction between dominoes per period [J/kg]
    exists: np.ndarray  # bool
    reason: np.ndarray  # str, empty where exists


def steady_state(height, thickness, gap, friction=0.0, g=G_STANDARD) -> LeaningSteadyState:
    """Steady wave of the endless leaning train (all arguments broadcast).

    ``height`` ``l`` [m] > 0, ``thickness`` ``s`` [m] >= 0, ``gap`` ``d`` [m] in
    ``(0, l)`` (clear distance between neighbours; pitch ``d + s``), ``friction`` ``mu``
    >= 0 between dominoes, ``g`` [m/s^2]. The front angular velocity after a collision
    is the fixed point of ``u -> c^2 (alpha u + b)`` (module docstring); the speed is
    ``(d + s) / T``, ``T`` the fall of the front from 0 to ``beta``.
    """
    l, s, d, mu, g, shape = _inputs(height, thickness, gap, friction, g)
    chunks = [
        _steady(*(a[i : i + CHUNK] for a in (l, s, d, mu, g))) for i in range(0, l.size, CHUNK)
    ]
    fields = {k: np.concatenate([c[k] for c in chunks]) for k in chunks[0]}
    if shape == ():  # scalar in, scalars out (float, bool, str)
        return LeaningSteadyState(**{k: v.tolist()[0] for k, v in fields.items()})
    return LeaningSteadyState(**{k: v.reshape(shape) for k, v in fields.items()})


def _steady(l, s, d, mu, g) -> dict[str, np.ndarray]:
    """:func:`steady_state` on flat arrays: the fields of ``LeaningSteadyState``."""
    lam = d + s
    n = _train_length(l, s, lam)
    ph = _phase(l, s, lam, mu, g, n, infinite=True)
    col = _collision(l, s, lam, mu, n + 1)
    c2 = col.ratio**2
    aff = _affine(ph)
    with np.errstate(divide="ignore", invalid="ignore"):
        u_after = c2 * aff.offset / (1.0 - c2 * aff.gain)
    fall = _fall(ph, np.where(u_after > 0.0, u_after, 0.0), aff)
    rest = np.arccos(s / lam)
    released = g * (_centre_height(0.0, l, s) - _centre_height(rest, l, s))
    lowest = np.minimum(ph.min_height_on_face, l - lam * np.sin(rest))  # the endless tail's
    reason = _why_not(released, u_after, c2 * aff.gain, fall, lowest, col)
    ok = reason == ""
    nan = np.where(ok, 1.0, np.nan)
    omega_before = np.sqrt(np.abs(fall.u_end)) * nan
    return {
        "speed": lam / fall.duration * nan,
        "period": fall.duration * nan,
        "omega_after": np.sqrt(np.abs(u_after)) * nan,
        "omega_before": omega_before,
        "collision_ratio": col.ratio,
        "released": released,
        "collision_loss": (col.kinetic_before - col.kinetic_after) * omega_before**2,
        "friction_loss": fall.friction_loss * nan,
        "exists": ok,
        "reason": reason,
    }


def _why_not(released, u_after, cycle_gain, fall: _Fall, lowest, col: _Collision):
    """Why no steady train runs at each point ("" where one does)."""
    reason = np.full(released.shape, "", dtype=object)
    checks = [  # the first failing check of each point is its reason
        (
            lowest < 0.0,
            "the fallen dominoes lie flat: a corner would touch "
            "below the next one's back face (gap > sqrt(l^2 + s^2) - s)",
        ),
        (
            released <= 0.0,
            "a fallen domino is not lower than a standing one: "
            "the train releases no energy (gap too small)",
        ),
        (col.min_impulse < 0.0, "a collision would pull dominoes apart (negative impulse)"),
        (
            (cycle_gain >= 1.0) | ~(u_after > 0.0),
            "the losses exceed the energy released: no steady wave",
        ),
        (~np.isfinite(fall.duration), "the front stops before it reaches the next domino"),
        (
            fall.min_force < 0.0,
            "the front falls ahead of the train (a contact force "
            "turns negative): the dominoes separate",
        ),
    ]
    for bad, text in reversed(checks):
        reason = np.where(bad, text, reason)
    return reason


def limit_speed(*, height, thickness, gap, friction=0.0, g=G_STANDARD):
    """Asymptotic front speed of the leaning train [m/s]: one pitch ``d + s`` per period.

    Keyword arguments as :func:`steady_state` (broadcast together); NaN where no steady
    train runs (:func:`steady_state` says why).
    """
    return steady_state(height, thickness, gap, friction, g).speed


def thin_small_gap_speed(height, g=G_STANDARD):
    """``sqrt(3 g l)`` [m/s]: the train's speed for thin dominoes (s = 0) as ``d/l -> 0``.

    Derivation (``docs/theory.md``): without friction the steady front leaves each
    collision with ``omega+^2 = (2 E / I) S(beta) / S(0)``, ``E = g l / 2`` the energy a
    thin domino releases, ``I = l^2 / 3`` and ``S = sum Phi_j^2``. As ``d/l -> 0`` the
    train becomes a continuum, ``sin(theta(k)) = tanh(k d / l + c)``, so that
    ``S ~ l / d`` and ``S(beta) / S(0) -> 1``: ``omega+^2 -> 3 g / l``, the front turns
    through ``beta ~ d / l`` in ``T ~ (d / l) / omega+`` and ``v = d / T -> l omega+``,
    the tip speed of a thin rod fallen from upright to flat. The finite-gap correction is
    of order ``(d/l)^2`` (0.5 % at ``d/l = 0.2``).
    """
    check_in_range("height", height, 0.0, np.inf)
    check_in_range("g", g, 0.0, np.inf)
    return np.sqrt(3.0 * np.asarray(g, float) * np.asarray(height, float))


def gap_limits(height, thickness, friction=0.0, g=G_STANDARD, *, xtol=1e-9):
    """Smallest and largest gap [m] at which a steady leaning train runs (scalars).

    Below the lower one the train releases too little energy to pay its losses (without
    friction: a fallen domino is no lower than a standing one, ``d < 2 s^3 /
    (l^2 - s^2)``); above the upper one the fallen dominoes lie flat rather than lean
    (``d > sqrt(l^2 + s^2) - s``) or the front runs away from the train. Found by a scan
    of 64 gaps and bisection to ``xtol`` [m]; raises ``ValueError`` if no gap runs.
    """
    for name, value in (("height", height), ("thickness", thickness), ("friction", friction)):
        if np.ndim(value):
            raise ValueError(f"{name} must be a scalar, got shape {np.shape(value)}")
    l = float(height)

    def runs(d):
        return bool(steady_state(l, thickness, d, friction, g).exists)

    grid = l * np.linspace(1e-3, 0.999, 64)
    ok = steady_state(l, thickness, grid, friction, g).exists
    if not ok.any():
        raise ValueError(
            f"no gap in (0, height) gives a steady leaning train at friction = {friction:.6g}"
        )
    first, last = np.argmax(ok), len(ok) - 1 - np.argmax(ok[::-1])
    lower = _bisect(runs, grid[first - 1] if first else 0.5 * grid[0], grid[first], xtol)
    upper = _bisect(
        runs, grid[last + 1] if last + 1 < len(grid) else l * (1 - 1e-12), grid[last], xtol
    )
    return lower, upper


def _bisect(runs, outside, inside, xtol):
    """The boundary between a gap where ``runs`` is False and one where it is True."""
    while abs(inside - outside) > xtol:
        mid = 0.5 * (inside + outside)
        inside, outside = (mid, outside) if runs(mid) else (inside, mid)
    return inside


@dataclass(frozen=True)
class LeaningTransient:
    """The train growing from one pushed domino; arrays of shape ``(n_dominoes - 1,)``.

    Entry ``i`` belongs to the collision in which domino ``i + 1`` is struck. Energies
    are per kilogram of domino [J/kg], summed from the push to just after that collision:
    ``push + released = kinetic + collision_loss + friction_loss``.
    """

    push: float  # kinetic energy of the push, I omega0^2 / 2 [J/kg]
    hit_times: np.ndarray  # time of the collision, from the push [s]
    omega_before: np.ndarray  # striking domino's angular velocity just before [rad/s]
    omega_after: np.ndarray  # struck domino's angular velocity just after [rad/s]
    released: np.ndarray  # potential energy released [J/kg]
    kinetic: np.ndarray  # kinetic energy of the moving dominoes [J/kg]
    collision_loss: np.ndarray  # [J/kg]
    friction_loss: np.ndarray  # [J/kg]


def transient(height, thickness, gap, friction=0.0, *, n_dominoes, omega0=None, g=G_STANDARD):
    """The wave from a push: domino 0 starts upright with angular velocity ``omega0``.

    Scalars: ``height``, ``thickness``, ``gap`` [m], ``friction`` [1] as in
    :func:`steady_state`; ``n_dominoes`` >= 2; ``omega0`` [rad/s] (default
    ``sqrt(g / l)``, the DEM chains' push) must carry domino 0 over its tipping point.
    The train of the first ``L`` dominoes leans with its last one as the tail (nothing
    behind it); trains longer than the steady state's cut are that cut's train.
    Raises ``ValueError`` where the model breaks down (the wave stops, or a contact
    force or impulse turns negative), naming the domino.
    """
    l, s, d, mu, g, _ = _inputs(height, thickness, gap, friction, g)
    if l.size != 1:
        raise ValueError("transient: height, thickness, gap, friction and g must be scalars")
    check_in_range("n_dominoes", n_dominoes, 2, np.inf, lo_inclusive=True)
    lam = d + s
    inertia = (l**2 + s**2) / 3.0
    tip = g * (np.hypot(l, s) / 2.0 - _centre_height(0.0, l, s))  # [J/kg] to the tipping point
    w0 = np.sqrt(g / l) if omega0 is None else np.asarray(omega0, float).reshape(1)
    check_in_range("omega0", w0, np.sqrt(2.0 * tip / inertia)[0], np.inf)
    n_cut = _train_length(l, s, lam)
    rows, u, time, lost_c, lost_f = [], w0**2, 0.0, 0.0, 0.0
    phase, col = None, None
    for length in range(1, int(n_dominoes)):
        if length <= n_cut:  # beyond the cut the train's phase and collision repeat
            phase = _phase(l, s, lam, mu, g, length, infinite=False)
            col = _collision(l, s, lam, mu, min(length + 1, n_cut))
        fall = _fall(phase, u)
        if not (np.isfinite(fall.duration[0]) and fall.min_force[0] >= 0.0):
            raise ValueError(f"the leaning train stops or separates before domino {length}")
        if col.min_impulse[0] < 0.0:
            raise ValueError(f"the collision with domino {length} pulls dominoes apart")
        time += fall.duration[0]
        u_before, u = fall.u_end, col.ratio**2 * fall.u_end
        lost_c += (col.kinetic_before - col.kinetic_after)[0] * u_before[0]
        lost_f += fall.friction_loss[0]
        angles = _train(np.zeros(1), l, s, lam, mu, length + 1).theta[: length + 1, 0]
        released = g[0] * np.sum(_centre_height(0.0, l, s) - _centre_height(angles, l, s))
        kinetic = col.kinetic_after[0] / col.ratio[0] ** 2 * u[0]
        rows.append((time, np.sqrt(u_before[0]), np.sqrt(u[0]), released, kinetic, lost_c, lost_f))
    push = 0.5 * inertia[0] * w0[0] ** 2
    return LeaningTransient(push, *(np.array(col) for col in zip(*rows, strict=True)))
