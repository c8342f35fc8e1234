"""Rigid thin dominoes: the Efthimiou-Johnson (EJ) theory, paper section 2.1 (eqs 2-14).

Model: massless rods of height ``l`` [m] hinged at their base, point mass ``m`` at
the tip, moment of inertia ``I = m l^2`` about the hinge, spacing ``d = l sin(beta)``.
Domino ``n`` leaves its collision with domino ``n-1`` upright with angular velocity
``Omega_n`` [rad/s], falls freely to the angle ``beta`` in the time ``T_n`` and strikes
domino ``n+1``. Every function is vectorised: array arguments broadcast together
(NumPy rules) and the result has the broadcast shape.

Conventions (see ``docs/theory.md`` for the derivations):

* eq 2 is EJ's collision rule (energy + angular momentum about the next hinge);
  it is the exact impulse solution when the contact impulse is perpendicular to the
  striking domino, the line of action the compliant model of section 2.2 also uses.
* eq 9 prints ``Omega`` where it means ``Omega^2``; :func:`omega_limit` returns
  ``Omega`` in rad/s.
* eq 12 holds with SciPy's parameter ``m = kappa^2`` (``ellipk(m)``, ``ellipkinc``);
  :func:`fall_time` evaluates the same number in Carlson's form, free of the
  cancellation of ``K - F`` at small ``beta`` and of ``m -> 1`` near ``pi/2``.
* eq 14 lacks the factor ``d / 2``: ``v = d sqrt(a + c) / (2 [K - F])``.
"""

from __future__ import annotations

import numpy as np
from scipy.special import elliprf

from dominowave.checks import check_in_range
from dominowave.units import G_STANDARD

__all__ = [
    "arrival_times",
    "b_coefficient",
    "collision_map",
    "f_minus",
    "f_plus",
    "fall_time",
    "fall_time_limit",
    "mclachlan_G",
    "omega_before_collision",
    "omega_limit",
    "omega_n_squared",
    "omega_next_squared",
    "wave_speed_rigid",
]


# --- input checks shared by the theory modules -------------------------------------------


def check_beta(beta) -> np.ndarray:
    """Validate the collision angle ``beta`` in (0, pi/2) [rad] and return it as floats."""
    check_in_range("beta", beta, 0.0, np.pi / 2)
    return np.asarray(beta, dtype=float)


def check_positive_finite(name: str, value) -> np.ndarray:
    """Validate ``0 < value < inf`` and return it as a float array."""
    check_in_range(name, value, 0.0, np.inf)
    return np.asarray(value, dtype=float)


def _cos2(beta):
    return np.cos(beta) ** 2


def _one_minus_f_plus(beta):
    """``1 - f_+ = sin^4(beta) / (1 + cos^4(beta))``, exact and free of cancellation."""
    return np.sin(beta) ** 4 / (1.0 + np.cos(beta) ** 4)


def _one_minus_f_plus_squared(beta):
    """``1 - f_+^2 = [sin^2(beta) (1 + cos^2(beta)) / (1 + cos^4(beta))]^2``.

    This is the energy identity ``f_+^2 + (Omega_bn / Omega_fn)^2 = 1`` of eq 2, written so
    that it keeps full relative precision as ``beta -> 0`` (where it tends to ``beta^4``).
    """
    c = _cos2(beta)
    return (np.sin(beta) ** 2 * (1.0 + c) / (1.0 + c * c)) ** 2


# --- the collision (eqs 2-4) ---------------------------------------------------------------


def f_plus(beta):
    """Transfer factor ``f_+ = 2 / (cos^2 b + 1/cos^2 b)`` (eq 4), dimensionless.

    ``Omega_{n+1} = f_+ Omega_fn`` (eq 3). ``0 < f_+ < 1``; ``f_+ ~ 1 - beta^4 / 2``
    for small ``beta``. ``beta`` [rad] in (0, pi/2), any shape.
    """
    c = _cos2(check_beta(beta))
    return 2.0 * c / (1.0 + c * c)  # eq. 4, multiplied through by cos^2 beta


def f_minus(beta):
    """Factor ``f_- = 2 / (cos^2 b - 1/cos^2 b)`` (eq 4), dimensionless and negative.

    ``Omega_bn = Omega_{n+1} / f_-`` (eq 3): the striking domino bounces back.
    Written as ``-2 cos^2 b / (sin^2 b (1 + cos^2 b))`` (same value, no cancellation).
    """
    beta = check_beta(beta)
    c = _cos2(beta)
    return -2.0 * c / (np.sin(beta) ** 2 * (1.0 + c))  # eq. 4


def collision_map(omega_f, beta):
    """Solve the collision eq 2: angular velocities just after domino n strikes n+1.

    Parameters
    ----------
    omega_f : angular velocity ``Omega_fn`` >= 0 of the striking domino just before the
        collision [rad/s] (finite; it moves towards domino n+1), any shape.
    beta : collision angle [rad] in (0, pi/2), broadcast against ``omega_f``.

    Returns
    -------
    (omega_next, omega_back) : ``Omega_{n+1} = f_+ Omega_fn`` of the struck domino and
        ``Omega_bn = Omega_{n+1} / f_- = Omega_fn (cos^4 b - 1) / (cos^4 b + 1)`` of the
        striking one (negative: it rotates backwards), both [rad/s] (eq 3).
    """
    check_in_range("omega_f", omega_f, 0.0, np.inf, lo_inclusive=True)
    omega_f = np.asarray(omega_f, dtype=float)
    beta = check_beta(beta)
    omega_next = f_plus(beta) * omega_f  # eq. 3
    c = _cos2(beta)
    omega_back = -omega_f * np.sin(beta) ** 2 * (1.0 + c) / (1.0 + c * c)  # eq. 3: /f_-
    return omega_next, omega_back


# --- free fall and the recurrence (eqs 5-9) ------------------------------------------------


def omega_before_collision(omega_n, beta, l, g=G_STANDARD):
    """``Omega_fn``: angular velocity of domino n when it reaches ``beta`` (eq 5) [rad/s].

    Energy conservation of the falling point mass: ``Omega_fn^2 = Omega_n^2 +
    (2 g / l)(1 - cos beta)``. ``omega_n`` [rad/s] >= 0, ``l`` [m], ``g`` [m/s^2].
    """
    check_in_range("omega_n", omega_n, 0.0, np.inf, lo_inclusive=True)
    beta = check_beta(beta)
    l, g = check_positive_finite("l", l), check_positive_finite("g", g)
    one_minus_cos = 2.0 * np.sin(beta / 2.0) ** 2
    return np.sqrt(np.asarray(omega_n, dtype=float) ** 2 + 2.0 * g / l * one_minus_cos)


def b_coefficient(beta, l, g=G_STANDARD):
    """``b = (2 g / l) f_+^2 (1 - cos beta)`` of the recurrence (eq 7) [rad^2/s^2]."""
    beta = check_beta(beta)
    l, g = check_positive_finite("l", l), check_positive_finite("g", g)
    return 2.0 * g / l * f_plus(beta) ** 2 * 2.0 * np.sin(beta / 2.0) ** 2  # eq. 7


def omega_next_squared(omega_n, beta, l, g=G_STANDARD):
    """One step of the recurrence ``Omega_{n+1}^2 = f_+^2 Omega_n^2 + b`` (eq 6) [rad^2/s^2]."""
    check_in_range("omega_n", omega_n, 0.0, np.inf, lo_inclusive=True)
    return f_plus(beta) ** 2 * np.asarray(omega_n, dtype=float) ** 2 + b_coefficient(beta, l, g)


def omega_n_squared(n, omega_1, beta, l, g=G_STANDARD):
    """``Omega_n^2`` of domino ``n`` after a first push ``Omega_1`` (eq 8) [rad^2/s^2].

    ``Omega_n^2 = f_+^{2(n-1)} Omega_1^2 + b (1 - f_+^{2(n-1)}) / (1 - f_+^2)``.
    Evaluated with ``log1p``/``expm1`` and the exact ``1 - f_+^2`` so that it stays
    accurate when ``f_+ -> 1`` (small ``beta``), and with ``log f_+`` where ``f_+ < 1/2``
    (finite up to ``beta -> pi/2``, where ``f_+ -> 0``). ``n`` >= 1 (integers, any shape),
    ``omega_1`` [rad/s] >= 0, ``beta`` [rad], ``l`` [m], ``g`` [m/s^2]; all broadcast.
    """
    check_in_range("n", n, 1.0, np.inf, lo_inclusive=True)
    n = np.asarray(n, dtype=float)
    if np.any(n % 1 != 0):
        raise ValueError(f"n = {n!r} must be integers >= 1 (domino numbers)")
    check_in_range("omega_1", omega_1, 0.0, np.inf, lo_inclusive=True)
    beta = check_beta(beta)
    # log f_+: log1p keeps full precision where f_+ -> 1 (small beta); near pi/2,
    # f_+ -> 0 and 1 - f_+ rounds to 1 (log1p(-1) = -inf), so take log f_+ directly there
    one_minus_f = _one_minus_f_plus(beta)
    with np.errstate(divide="ignore"):  # the branch not taken may hit log1p(-1)
        log_f_plus = np.where(one_minus_f > 0.5, np.log(f_plus(beta)), np.log1p(-one_minus_f))
    power = 2.0 * (n - 1.0) * log_f_plus
    f_plus_2n = np.exp(power)  # f_+^{2(n-1)}
    geometric = -np.expm1(power) / _one_minus_f_plus_squared(beta)  # (1-f^{2(n-1)})/(1-f^2)
    omega_1 = np.asarray(omega_1, dtype=float)
    return f_plus_2n * omega_1**2 + b_coefficient(beta, l, g) * geometric  # eq. 8


def omega_limit(beta, l, g=G_STANDARD):
    """Limit angular velocity ``Omega = lim Omega_n`` [rad/s] (eq 9, square root taken).

    The paper's eq 9 reads ``Omega = lim Omega_n^2 = (2g/l)(1 - cos b) f_+^2/(1 - f_+^2)``:
    the right-hand side is ``Omega^2``. Simplified exactly (``docs/theory.md``)::

        Omega = sqrt(g / l) * 2 cos^2 b / (sin b * cos(b/2) * (1 + cos^2 b))

    which has no cancellation and shows ``Omega ~ sqrt(g/l) / beta`` for small beta.
    """
    beta = check_beta(beta)
    l, g = check_positive_finite("l", l), check_positive_finite("g", g)
    c = _cos2(beta)
    return np.sqrt(g / l) * 2.0 * c / (np.sin(beta) * np.cos(beta / 2.0) * (1.0 + c))


# --- free-fall time and wave speed (eqs 10-14) ---------------------------------------------


def fall_time(omega_n, beta, l, g=G_STANDARD):
    """Free-fall time ``T_n`` [s] from upright (angular velocity ``Omega_n``) to ``beta``.

    Eq 12: ``T_n = 2 / sqrt(a_n + c) [K(kappa_n) - F((pi - beta)/2, kappa_n)]`` with
    ``a_n = Omega_n^2 + 2g/l``, ``c = 2g/l``, ``kappa_n^2 = 2c / (a_n + c)``; SciPy's
    ``ellipk(m)``, ``ellipkinc(phi, m)`` take the parameter ``m = kappa^2``. Printed that
    way it loses digits at both ends: ``K - F`` cancels for small ``beta``, and near
    ``beta = pi/2`` (where ``Omega -> 0``) ``m`` rounds to 1. We evaluate the same number
    through the addition theorem ``K(m) - F(phi, m) = F(psi, m)``,
    ``tan(phi) tan(psi) = 1/sqrt(1 - m)``, and Carlson's ``F(psi, m) = sin(psi)
    R_F(cos^2 psi, 1 - m sin^2 psi, 1)``; with ``t = tan(beta/2)`` this is exactly::

        T_n = 2 t R_F(Omega_n^2, Omega_n^2 / cos^2(beta/2), Omega_n^2 + t^2 (Omega_n^2 + 4 g/l))

    (``docs/theory.md``), free of cancellation. ``omega_n`` [rad/s] > 0 (a domino at rest
    upright never falls), ``beta`` [rad], ``l`` [m], ``g`` [m/s^2]; all broadcast.
    """
    check_in_range("omega_n", omega_n, 0.0, np.inf)
    beta = check_beta(beta)
    l, g = check_positive_finite("l", l), check_positive_finite("g", g)
    w2 = np.asarray(omega_n, dtype=float) ** 2
    t = np.tan(beta / 2.0)
    return 2.0 * t * elliprf(w2, w2 / np.cos(beta / 2.0) ** 2, w2 + t**2 * (w2 + 4.0 * g / l))


def fall_time_limit(beta, l, g=G_STANDARD):
    """Limit free-fall time ``T = lim T_n`` [s] (eq 13): eq 12 at ``Omega_n = Omega``."""
    return fall_time(omega_limit(beta, l, g), beta, l, g)  # eq. 13


def wave_speed_rigid(beta, l, g=G_STANDARD):
    """EJ wave speed ``v = d / T`` [m/s] of rigid thin dominoes (eq 14), ``d = l sin b``.

    The paper's eq 14 prints ``sqrt(a + c) / (K - F)``; the factor ``d / 2`` is missing:
    ``v = d sqrt(a + c) / (2 [K(kappa) - F((pi - beta)/2, kappa)])``.
    """
    beta = check_beta(beta)
    l = check_positive_finite("l", l)
    return l * np.sin(beta) / fall_time_limit(beta, l, g)  # eq. 14 (corrected)


def mclachlan_G(d_over_l):
    """McLachlan's scaling function ``G(d/l) = v / sqrt(g l)`` of the EJ theory (eq 1, 14).

    Dimensionless; ``d_over_l`` in (0, 1), any shape. ``G ~ l / d`` for small ``d/l``.
    """
    check_in_range("d_over_l", d_over_l, 0.0, 1.0)
    return wave_speed_rigid(np.arcsin(d_over_l), 1.0, 1.0)


# --- the transient of a finite chain --------------------------------------------------------


def arrival_times(n_dominoes, omega_1, beta, l, g=G_STANDARD, collision_time=0.0):
    """Start times ``t_n`` [s] of dominoes ``n = 1 .. n_dominoes`` after a first push.

    Domino 1 is upright and receives the angular velocity ``Omega_1`` at ``t_1 = 0``.
    ``t_{n+1} = t_n + T_n + T_c / 2`` (eqs 12, 19, 20) with ``Omega_n`` from eq 8, so that

    * rigid dominoes (``collision_time = 0``): ``t_{n+1}`` is the instant domino ``n``
      strikes domino ``n+1`` (and ``n+1`` starts with ``Omega_{n+1}``);
    * compliant dominoes (``collision_time = T_c > 0``): ``t_{n+1}`` is the effective
      start of domino ``n+1`` -- after the contact it moves like a rigid domino launched
      at ``t_{n+1}`` (eq 16-19). The contact of ``n`` on ``n+1`` begins at
      ``t_{n+1} - T_c/2`` and ends at ``t_{n+1} + T_c/2``.

    Parameters
    ----------
    n_dominoes : int >= 1, number of dominoes in the chain.
    omega_1 : first push [rad/s] > 0; ``beta`` [rad]; ``l`` [m]; ``g`` [m/s^2];
    collision_time : ``T_c`` [s] >= 0 (e.g. :func:`dominowave.theory.collision_time`).
        All parameters broadcast to a common shape ``S``.

    Returns
    -------
    ndarray of shape ``S + (n_dominoes,)``, ``t[..., 0] = 0``.
    """
    if isinstance(n_dominoes, bool) or not isinstance(n_dominoes, int | np.integer):
        raise ValueError(f"n_dominoes = {n_dominoes!r} must be an integer >= 1")
    check_in_range("n_dominoes", n_dominoes, 1.0, np.inf, lo_inclusive=True)
    check_in_range("omega_1", omega_1, 0.0, np.inf)
    check_in_range("collision_time", collision_time, 0.0, np.inf, lo_inclusive=True)
    beta = check_beta(beta)
    omega_1, beta, l, g, t_c = (
        np.expand_dims(np.asarray(x, dtype=float), -1)
        for x in np.broadcast_arrays(omega_1, beta, l, g, collision_time)
    )
    n = np.arange(1, n_dominoes)  # dominoes that strike a successor
    omega_n = np.sqrt(omega_n_squared(n, omega_1, beta, l, g))
    periods = fall_time(omega_n, beta, l, g) + t_c / 2.0  # eq. 12 + eq. 19
    zero = np.zeros((*periods.shape[:-1], 1))
    return np.concatenate([zero, np.cumsum(periods, axis=-1)], axis=-1)
