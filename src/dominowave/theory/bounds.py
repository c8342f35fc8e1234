"""Range of applicability: peak contact force and base-slip regimes (section 2.4, eqs 36-42).

The theory assumes the dominoes rotate about a base that does not slip. The peak
force of the half-sine contact pulse (eq 37) tells whether friction ``mu`` with the
floor can hold the base. Section 2.4 models the struck domino as a uniform block of
height ``l``, thickness ``s`` and mass ``m`` (centre of mass at ``l/2``), struck at
height ``l cos(beta)`` by a force whose horizontal part is ``F cos(beta)`` (eq 36).
The contact is above the centre of mass for ``beta < pi/3`` and below it for
``beta > pi/3``. ``f = F_m / (m g)`` below.

Regimes of the paper's Fig 5A (integer codes of :class:`Regime`):

* I   pure rotation, no slip (the theory's assumption): eq 39 fails, ``f <= mu/cos b``.
  Eq 38 implies eq 39 (``|2 cos b - 1| <= 1``) and Cases 1, 2 require it, so I is
  exactly where no criterion of section 2.4 holds;
* II  forward rotation with base slip: eq 38 and ``beta < pi/3``;
* III backward rotation with base slip: eq 38 and ``beta > pi/3``;
* IV  translation (sliding): eq 39 and ((``beta > pi/3`` and eq 41) or eq 42).

Precedence (our choice, the paper does not state one): II/III before IV. Eq 38 says the
contact moment about the centre of mass beats every resisting moment, so the block
rotates whatever the translational criteria say; Case 1 (eq 41) excludes eq 38
explicitly, and only Case 2 can overlap with it (``cos(beta) (2 mu + 4 s/l) < s/l``).

The paper leaves a set unclassified: eq 39 holds (the base slides) but neither eq 38
nor Case 1 nor Case 2 does. There we decide with the signed moment balance about the
centre of mass of a block sliding forwards (:func:`sliding_rotation_sign`): II if it
tips forwards, IV if it translates (it never tips backwards there, that is eq 38).
:attr:`RegimeClassification.by_paper` is False on that set.

The paper's eq 38 for ``beta < pi/3`` counts friction as resisting the forward moment,
i.e. assumes friction acting forwards (base sliding backwards), while eq 39 is forward
slip. We keep the printed eq 38 (see ``docs/theory.md`` for the signed derivation).
Eq 42 is used with ``cos^2(beta)`` (typo in the paper, which prints ``cos(beta)``).
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum
from typing import NamedTuple

import numpy as np

from dominowave.checks import check_in_range, check_nonnegative
from dominowave.theory.compliant import StiffnessConvention, collision_time
from dominowave.theory.rigid import check_beta, check_positive_finite, omega_limit
from dominowave.units import G_STANDARD

__all__ = [
    "REGIME_NAMES",
    "Regime",
    "RegimeBoundaries",
    "RegimeClassification",
    "classify_regime",
    "peak_contact_force",
    "regime_boundaries",
    "sliding_rotation_sign",
]


def peak_contact_force(beta, l, m, k, g=G_STANDARD, convention: StiffnessConvention = "paper"):
    """Peak contact force ``F_m = pi m Omega l / (2 T_c cos^2 beta)`` [N] (eq 37).

    From the impulse balance eq 36: the half-sine pulse ``F_m sin(pi t / T_c)``, whose
    horizontal part is ``F cos(beta)``, gives domino ``n+1`` (mass ``m' = m / cos^2 b``
    at lever arm ``l cos b``) the velocity ``Omega l cos b``. ``Omega`` is the limit
    angular velocity (eq 9, rad/s), ``T_c`` eq 31. Equals ``k_r delta_max`` of the
    spring-mass collision. ``inf`` for ``k = inf``. Divide by ``m g`` for Fig 5B.
    """
    beta = check_beta(beta)
    l, m = check_positive_finite("l", l), check_positive_finite("m", m)
    t_c = collision_time(k, m, beta, convention)
    impulse = np.pi * m * omega_limit(beta, l, g) * l / (2.0 * np.cos(beta) ** 2)
    with np.errstate(divide="ignore"):  # T_c = 0 (rigid): infinite force, as the paper notes
        return impulse / t_c  # eq. 37


class Regime(IntEnum):
    """Mechanisms of Fig 5A."""

    PURE_ROTATION = 1
    FORWARD_ROTATION_SLIP = 2
    BACKWARD_ROTATION_SLIP = 3
    TRANSLATION = 4


REGIME_NAMES: dict[int, str] = {
    Regime.PURE_ROTATION: "I pure rotation",
    Regime.FORWARD_ROTATION_SLIP: "II forward rotation + slip",
    Regime.BACKWARD_ROTATION_SLIP: "III backward rotation + slip",
    Regime.TRANSLATION: "IV translation",
}


@dataclass(frozen=True)
class RegimeBoundaries:
    """Thresholds on ``F_m / (m g)`` as functions of ``beta`` (all arrays of one shape).

    rotation : eq 38, ``(mu + s/l) / (cos b |2 cos b - 1|)`` (infinite at ``b = pi/3``).
    sliding : eq 39, ``mu / cos b``.
    friction_moment : lower bound of eq 41, ``mu / (cos b (1 - 2 cos b))``; NaN for
        ``b <= pi/3`` where Case 1 does not apply (its upper bound is ``rotation``).
    toppling : eq 42 (corrected), ``s / (2 l cos^2 b)``.
    """

    rotation: np.ndarray
    sliding: np.ndarray
    friction_moment: np.ndarray
    toppling: np.ndarray


class RegimeClassification(NamedTuple):
    """Result of :func:`classify_regime`, arrays of one shape.

    code : integer :class:`Regime` values; name : the matching names;
    by_paper : True where the paper's criteria (eqs 38-42) decide the regime, False on
        the set they leave open (eq 39 holds, eq 38, Case 1 and Case 2 do not), decided
        by :func:`sliding_rotation_sign`.
    """

    code: np.ndarray
    name: np.ndarray
    by_paper: np.ndarray


def _check_friction_geometry(mu, s_over_l):
    check_nonnegative("mu", mu)
    check_in_range("s_over_l", s_over_l, 0.0, 1.0, lo_inclusive=True)


def regime_boundaries(beta, mu, s_over_l) -> RegimeBoundaries:
    """Boundaries of the regimes of Fig 5B on ``F_m / (m g)`` (eqs 38, 39, 41, 42).

    Derived from the balance of the horizontal force and of the moments about the
    centre of mass (eqs 38, 41) and about the front edge of the base (eq 42) of a
    block struck at height ``l cos b`` by a force of horizontal part ``F cos b``;
    ``mu`` >= 0 floor friction, ``s_over_l`` in [0, 1); all broadcast with ``beta``.
    """
    beta = check_beta(beta)
    _check_friction_geometry(mu, s_over_l)
    beta, mu, s_over_l = (
        np.asarray(x, dtype=float) for x in np.broadcast_arrays(beta, mu, s_over_l)
    )
    cos_b = np.cos(beta)
    lever = cos_b * np.abs(2.0 * cos_b - 1.0)  # moment arm of F about G, in units of l/2
    below = beta > np.pi / 3  # contact below the centre of mass
    with np.errstate(divide="ignore"):
        rotation = (mu + s_over_l) / lever  # eq. 38
        friction_moment = np.where(below, mu / lever, np.nan)[()]  # eq. 41, lower bound
    sliding = mu / cos_b  # eq. 39
    toppling = s_over_l / (2.0 * cos_b**2)  # eq. 42 with cos^2 (typo in the paper)
    return RegimeBoundaries(rotation, sliding, friction_moment, toppling)


def sliding_rotation_sign(beta, fm_over_mg, mu, s_over_l) -> np.ndarray:
    """Rotation of a block whose base slides forwards: +1 forwards, -1 backwards, 0 none.

    Signed moment balance about the centre of mass ``G`` (forward = top moving in the
    direction of the wave), in units of ``m g l / 2``, with ``f = F_m / (m g)``:

    * push, horizontal part ``f cos b`` at height ``l cos b``: ``f cos b (2 cos b - 1)``
      (forwards above ``G``, ``beta < pi/3``; backwards below it);
    * kinetic friction ``mu m g`` acting backwards at the base, ``l/2`` below ``G``: ``+mu``
      (it always turns the top forwards);
    * the normal force ``m g`` can sit anywhere on the base, ``|x_N| <= s/2``, so it
      balances any net moment up to ``s/l`` in either direction.

    Hence forward rotation iff ``f cos b (2 cos b - 1) + mu > s/l``, backward rotation iff
    ``f cos b (1 - 2 cos b) > mu + s/l`` (= eq 38 for ``beta > pi/3``), translation
    otherwise (for ``beta > pi/3``: ``mu - s/l <= f cos b (1 - 2 cos b) <= mu + s/l``,
    eq 41 with ``mu - s/l`` as lower bound). Like the paper we neglect the vertical
    part ``F sin b`` of the contact force. Meaningful where eq 39 holds (the base slides);
    all arguments broadcast; returns an integer array.
    """
    check_in_range("fm_over_mg", fm_over_mg, 0.0, np.inf, lo_inclusive=True, hi_inclusive=True)
    beta = check_beta(beta)
    _check_friction_geometry(mu, s_over_l)
    cos_b = np.cos(beta)
    arm = 2.0 * cos_b - 1.0  # signed arm of the push about G, in units of l/2
    with np.errstate(invalid="ignore"):  # F_m = inf exactly at the level of G: no moment
        push = np.where(arm == 0.0, 0.0, np.asarray(fm_over_mg, dtype=float) * cos_b * arm)
    net = push + np.asarray(mu, dtype=float)  # forward moment of push and friction
    s_over_l = np.asarray(s_over_l, dtype=float)
    return (np.sign(net) * (np.abs(net) > s_over_l)).astype(int)[()]


def classify_regime(beta, fm_over_mg, mu, s_over_l) -> RegimeClassification:
    """Classify the motion the peak contact force starts (Fig 5A), vectorised.

    Parameters
    ----------
    beta : collision angle [rad] in (0, pi/2).
    fm_over_mg : peak contact force over weight, ``F_m / (m g)`` >= 0 (may be inf).
    mu : friction coefficient with the floor, >= 0.
    s_over_l : thickness over height, in [0, 1).

    Returns
    -------
    RegimeClassification(code, name, by_paper) of the broadcast shape. I exactly where
    eq 39 fails; eq 38 gives II/III; eq 39 with Case 1 or Case 2 gives IV; the rest of
    eq 39 (not classified by the paper) is II or IV by :func:`sliding_rotation_sign`.
    """
    check_in_range("fm_over_mg", fm_over_mg, 0.0, np.inf, lo_inclusive=True, hi_inclusive=True)
    check_beta(beta)
    _check_friction_geometry(mu, s_over_l)  # before broadcasting: messages name given values
    beta, f, mu, s_over_l = (
        np.asarray(x, dtype=float) for x in np.broadcast_arrays(beta, fm_over_mg, mu, s_over_l)
    )
    bounds = regime_boundaries(beta, mu, s_over_l)
    below = beta > np.pi / 3
    slides = f > bounds.sliding  # eq. 39; eq 38 implies it
    rotates = f > bounds.rotation  # eq. 38 (as printed)
    # eq. 41; its upper bound is eq 38, enforced by the precedence below
    case_1 = below & (f > np.nan_to_num(bounds.friction_moment, nan=np.inf))
    case_2 = f < bounds.toppling  # eq. 42
    translates = slides & (case_1 | case_2)
    by_paper = ~slides | rotates | translates
    code = np.full(f.shape, int(Regime.PURE_ROTATION))
    # the set the paper leaves open: the base slides; does the block tip?
    tips_forward = sliding_rotation_sign(beta, f, mu, s_over_l) > 0
    code[~by_paper] = np.where(
        tips_forward[~by_paper], Regime.FORWARD_ROTATION_SLIP, Regime.TRANSLATION
    )
    code[translates] = Regime.TRANSLATION
    code[rotates & ~below] = Regime.FORWARD_ROTATION_SLIP
    code[rotates & below] = Regime.BACKWARD_ROTATION_SLIP
    names = np.vectorize(REGIME_NAMES.__getitem__, otypes=[object])(code)
    return RegimeClassification(code, names, by_paper)
