"""Accuracy as a setting: the softest contact whose wave speed stays within a tolerance.

A chain of real dominoes is given a material (``ChainParams.young``), and the plastic's
contact spring is stiff: the standard domino's is ``k/k* = 3.4e6``, which needs a step of
1.4e-6 s. The wave's speed, though, is set by gravity, geometry and friction, not by the
stiffness of these contacts. So a chain given a material runs, by default, with the
softest contact spring whose speed stays within a stated *tolerance* of the stiff
(material) limit -- the idea of mass scaling in explicit finite elements (Olovsson,
Simonsson and Unosson, *Int. J. Numer. Meth. Engng* 63, 1436 (2005)) and of softened
contacts in the discrete-element method (Lommen, Schott and Lodewijks, *Particuology*
12, 107 (2014)): the critical step grows as ``1/sqrt(k)``, the error is estimated and
reported.

**The estimate** (a priori, of the relative change of the front speed from the stiff
limit ``k_m`` to a softer spring ``k``)::

    eps(k) = (T_c(k) - T_c(k_m)) / (2 T_d) + (m g / d) (1/k_p(k) - 1/k_p(k_m))

* **Collision time against the time per domino.** Eq 34, ``v = (d + s) / (T + T_c / 2)``:
  a collision lasting ``T_c`` (eq 31) delays the wave by ``T_c / 2`` against a rigid one.
  That is the elastic collision; one of restitution ``e`` delays the struck domino by
  ``e T_c / (1 + e)`` (the centre of mass moves as in the rigid collision, the
  separation starts ``T_c`` late), never more than ``T_c / 2``. So softening the spring
  from ``k_m`` to ``k`` slows the wave by at most ``(T_c(k) - T_c(k_m)) / 2`` per domino,
  against the time per domino ``T_d = (d + s) / v``. The estimate keeps the elastic
  ``T_c / 2`` even for inelastic dominoes: the restitution's delay is not a bound in a
  chain. At 15.09 mm, friction 0.525 and restitution 0.1 between the dominoes, the
  spring of a 5 % tolerance slows the wave by 2.5-2.7 % (docs/real_dominoes.md section
  11), about twice the 1.2 % that ``e T_c / (1 + e)`` would give: the struck domino is
  pushed by the leaning train behind the striking one, not struck once by one domino.
* **Overlap against the gap.** A contact that lasts (dominoes leaning on each other)
  overlaps by ``F / k_p`` (``k_p``, the pair spring ``ChainParams.pair_stiffness``),
  about ``m g / k_p`` under a domino's weight; the geometry of the chain is off by that
  against the clear gap ``d`` (the speed changes with the gap more slowly than in
  proportion: the leaning train's ``d ln v / d ln d`` is about -0.1 at 9-25 mm).

``T_d`` needs the speed before the run: the leaning train's steady speed at the
chain's friction between dominoes (:func:`dominowave.theory.leaning.limit_speed`, the
rigid limit the box DEM meets within 2 %, docs/real_dominoes.md section 9); where no
train runs (the widest gaps), ``2 sqrt(g l)``, the fastest wave of the package's chains
and of the filmed rows. After the run, :meth:`ContactFidelity.error_at` gives the
estimate at the larger of that speed and the run's own.

**The step.** A chain's step is its collision time over a number of steps
(``DominoChain``'s ``steps_per_collision``): :data:`STEPS_PER_COLLISION`, which resolves a
collision alike at every stiffness, or, for a softened chain, the largest step whose
measured effect on the speed is at most :data:`STEP_SHARE` of the tolerance
(:func:`steps_per_collision`, :data:`STEP_EFFECTS`): ``T_c/10`` from 1.77 % (the default
2 % included), ``T_c/20`` from 0.6 %, ``T_c/50`` below. The step is not in the estimate:
its effect was measured instead (``docs/real_dominoes/step_convergence.py``, on the
chains of the validation at the default tolerance's spring: at most 0.20 % from T_c/50 to
T_c/20, 0.59 % at T_c/15 and 0.38 % at T_c/10), and the validation runs the softened
chains at their own step against the material's chains at T_c/50, so the estimate is
checked for both together. (At 1 % with ``T_c/10``, whose effect is 59 % of it, the
5 mm chain of the validation moved by 1.03 %: beyond the estimate, hence the share.)

**The default** (:data:`DEFAULT_TOLERANCE`, 2 %). The estimate is a bound, not the
error: on the chains of the validation the spring and step of a 2 % tolerance move the
speed by 0.05-0.92 % (the most at 15.09 mm with nearly plastic collisions, where the
effect is systematic), and a chain's own chaotic spread, which any change of the run
shows, is 0.2-0.5 % (docs/real_dominoes.md section 11). A filmed row of real dominoes
scatters by 0.8 % (felt) to 3.5 % (hardwood) from row to row (standard deviations of
the rows at one gap, docs/real_dominoes.md section 3), and the friction between
dominoes, never measured on dominoes, moves the speed by tens of per cent. So a 2 %
bound keeps the numerics below what a measurement resolves; a tighter one (``0.01``:
3.7 times the steps) or the material's own spring (``"exact"``: about 50 times the
time of the standard chain) is one option away.

**Where it applies.** Box chains given a Young's modulus with the linear law (the
presets, :func:`dominowave.chain.presets.standard_domino`), whose restitutions between
dominoes and with the floor are at most :data:`MAX_RESTITUTION` (the nominal 0.5 of the
material data). The estimate counts one collision per domino. Nearly elastic contacts
rattle: at restitution 0.9 between dominoes a 30-domino chain at friction 0.2 runs 3 %
slower at ``k/k*`` = 1e5 to 1e6 than at the plastic's 3.4e6 (the change comes between
1e6 and 3.4e6, where the estimate is a fraction of a per cent), and at restitution 0.9
with the floor 2.9 % slower at the spring of the 2 % tolerance; such a chain keeps the
material's spring at any tolerance. The paper's elastic chains, given ``stiffness_ratio``
or ``kn``, keep their stiffness: their speed depends on it (Fig 6C), the stiffness *is*
their parameter. A Hertz chain keeps the modulus too (its law is what it studies). The
estimate is validated against runs at the material stiffness in
``tests/chain/test_fidelity.py`` (docs/real_dominoes.md section 11).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

from dominowave.chain.build import ChainParams
from dominowave.chain.compare import theory_collision_time
from dominowave.checks import check_in_range

__all__ = [
    "DEFAULT_TOLERANCE",
    "EXACT",
    "MAX_RESTITUTION",
    "MAX_TOLERANCE",
    "STEPS_PER_COLLISION",
    "STEP_EFFECTS",
    "STEP_SHARE",
    "ContactFidelity",
    "Fidelity",
    "applies",
    "check_fidelity",
    "choose_contact",
    "given_materials",
    "parse_fidelity",
    "steps_per_collision",
    "tolerance_of",
]

EXACT = "exact"
"""The fidelity that keeps the material's own contact spring."""
DEFAULT_TOLERANCE = 0.02
"""Default tolerance: the estimated speed error of a softened chain is at most 2 %
(module docstring, "The default")."""
MAX_TOLERANCE = 0.1
"""Largest tolerance accepted: the estimate is of first order in ``T_c / T_d``."""
MAX_RESTITUTION = 0.5
"""Largest restitution (between dominoes and with the floor) at which a chain is
softened: the estimate is validated up to it (0.1 and 0.5); nearly elastic contacts
rattle, and the speed of such a chain still changes between ``k/k*`` = 1e6 and the
plastic's 3.4e6 (module docstring)."""

STEPS_PER_COLLISION = 50
"""Time steps per collision time ``T_c`` (eq 31) of a chain: a collision is resolved alike
at every stiffness."""
STEP_EFFECTS = ((10, 0.0059), (20, 0.0020))
"""(steps per collision time, the largest change of a softened chain's front speed from
:data:`STEPS_PER_COLLISION` measured at that step or a finer one before the next entry's),
coarsest first: ``docs/real_dominoes/step_convergence.csv``, the chains of the validation at the
default tolerance's spring (0.38 % at ``T_c/10`` and 0.59 % at ``T_c/15``: the change
does not grow monotonically with the step, it is mostly the chains' chaotic spread, so
``T_c/10`` is charged the larger)."""
STEP_SHARE = 1.0 / 3.0
"""The share of a softened chain's tolerance that its step may take (the spring's
estimate, a bound, takes the whole tolerance; the validation checks both together)."""

Fidelity = float | Literal["exact"] | None
"""``"exact"`` (the material's spring), a tolerance in ``(0, MAX_TOLERANCE]``, or None
(not set: :data:`DEFAULT_TOLERANCE` where :func:`applies`, the given stiffness elsewhere)."""


def given_materials(params: ChainParams) -> bool:
    """Whether ``params`` is a chain of given materials: a box chain given a Young's
    modulus, linear contacts (a Hertz chain keeps its law's modulus)."""
    return params.shape == "box" and params.young is not None and params.normal_law == "linear"


def applies(params: ChainParams) -> bool:
    """Whether ``params`` may be softened: a chain of given materials whose collisions,
    between dominoes and with the floor, are inelastic enough (restitution at most
    :data:`MAX_RESTITUTION`; not set is elastic)."""
    elastic = [e is None or e > MAX_RESTITUTION for e in params.restitution_pairs]
    return given_materials(params) and not any(elastic)


def check_fidelity(fidelity: Fidelity) -> Fidelity:
    """``fidelity`` checked: ``"exact"``, None, or a tolerance in ``(0, MAX_TOLERANCE]``;
    a ValueError naming the parameter, the value and the valid range otherwise."""
    if fidelity is None or fidelity == EXACT:
        return fidelity
    if isinstance(fidelity, bool) or not isinstance(fidelity, int | float):
        raise ValueError(
            f"fidelity = {fidelity!r} is not 'exact' or a tolerance in (0, {MAX_TOLERANCE}]"
        )
    check_in_range("fidelity", fidelity, 0.0, MAX_TOLERANCE, hi_inclusive=True)
    return float(fidelity)


def tolerance_of(fidelity: Fidelity) -> float | None:
    """The tolerance [1] a (checked) setting stands for: None for ``"exact"``,
    :data:`DEFAULT_TOLERANCE` when not set."""
    if fidelity == EXACT:
        return None
    return DEFAULT_TOLERANCE if fidelity is None else fidelity


def parse_fidelity(text: str | None) -> Fidelity:
    """The command line's ``--fidelity``: ``exact``, a tolerance such as ``0.01``, or
    not given (None)."""
    if text is None or text == EXACT:
        return text
    try:
        value = float(text)
    except ValueError:
        raise ValueError(
            f"--fidelity {text!r} is not 'exact' or a tolerance in (0, {MAX_TOLERANCE}]"
            " (e.g. 0.01 for 1 %)"
        ) from None
    return check_fidelity(value)


@dataclass(frozen=True)
class ContactFidelity:
    """The contact spring a chain of given materials runs with, and its estimated error.

    ``tolerance`` [1] (None: ``"exact"``), ``material_kn`` the material's spring per
    contact point [N/m] (``pi r E / 2``, eq 24), ``kn`` the spring used [N/m],
    ``stiffness_over_kstar`` its ``k/k*``, ``reference_speed`` [m/s] the a-priori speed
    of ``T_d``, ``collision_time`` ``T_c`` at ``kn`` and ``material_collision_time`` at
    ``material_kn`` [s] (eq 31), ``overlap_per_weight`` [m/N] ``1/k_p(k) - 1/k_p(k_m)``,
    ``pitch`` and ``gap`` [m], ``weight`` ``m g`` [N], ``softenable`` whether the chain
    may be softened (:func:`applies`); ``error`` the a-priori estimate [1] (module
    docstring).
    """

    tolerance: float | None
    material_kn: float
    kn: float
    stiffness_over_kstar: float
    reference_speed: float
    collision_time: float
    material_collision_time: float
    overlap_per_weight: float
    pitch: float
    gap: float
    weight: float
    softenable: bool = True

    @property
    def softened(self) -> bool:
        """Whether the chain runs softer than its material."""
        return self.kn < self.material_kn

    @property
    def error(self) -> float:
        """The a-priori estimate of the relative speed error [1] (at ``reference_speed``)."""
        return self.error_at(self.reference_speed)

    def error_at(self, speed: float) -> float:
        """The estimate [1] with the time per domino of the larger of ``speed`` [m/s]
        (a run's own, NaN if it has none) and the a-priori ``reference_speed``."""
        v = self.reference_speed if not speed > self.reference_speed else speed
        delay = (self.collision_time - self.material_collision_time) / 2.0
        return delay * v / self.pitch + self.weight * self.overlap_per_weight / self.gap

    @property
    def label(self) -> str:
        """``"exact"`` or the tolerance in per cent, e.g. ``"1 %"``."""
        return EXACT if self.tolerance is None else f"{100 * self.tolerance:g} %"

    def describe(self, error: float | None = None) -> str:
        """One line for a command's output: the fidelity, the spring and the estimated
        error ``error`` [1] (not given: the a-priori :attr:`error`)."""
        error = self.error if error is None else error
        above = ""
        if self.tolerance is not None and error > self.tolerance * (1.0 + 1e-9):
            above = ", above the tolerance: the wave ran faster than the a-priori speed"
        if not self.softened:
            why = "" if self.softenable else f", a restitution above {MAX_RESTITUTION}"
            return (
                f"contact: the material's, k_n = {self.kn:.4g} N/m (k/k* ="
                f" {self.stiffness_over_kstar:.3g}; fidelity {self.label}{why})"
            )
        return (
            f"contact softened for speed (fidelity {self.label}): k_n = {self.kn:.4g} N/m"
            f" (k/k* = {self.stiffness_over_kstar:.3g}) instead of the material's"
            f" {self.material_kn:.4g} N/m; estimated speed error"
            f" {100 * error:.2g} %{above} (fidelity exact: the material's)"
        )


def _reference_speed(params: ChainParams) -> float:
    """The a-priori front speed [m/s]: the leaning train's at the chain's friction
    between dominoes, or ``2 sqrt(g l)`` where no train runs."""
    from dominowave.theory import leaning  # (scipy: only for chains of given materials)

    v = float(
        leaning.limit_speed(
            height=params.height,
            thickness=params.thickness,
            gap=params.spacing,
            friction=params.friction_dominoes,
            g=params.g,
        )
    )
    return v if math.isfinite(v) and v > 0 else 2.0 * math.sqrt(params.g * params.height)


def steps_per_collision(contact: ContactFidelity | None) -> int:
    """The steps per collision time of a chain whose contact is ``contact``
    (:func:`choose_contact`): for a softened one the fewest of :data:`STEP_EFFECTS` whose
    measured effect on the speed is at most :data:`STEP_SHARE` of its tolerance (10 at the
    default 2 %, 20 at 1 %); :data:`STEPS_PER_COLLISION` for any other chain, and for a
    tolerance too tight for those steps (below 0.6 %)."""
    if contact is None or not contact.softened:
        return STEPS_PER_COLLISION
    for steps, effect in STEP_EFFECTS:
        if effect <= STEP_SHARE * contact.tolerance:
            return steps
    return STEPS_PER_COLLISION


def choose_contact(params: ChainParams, fidelity: Fidelity = None) -> ContactFidelity | None:
    """The contact spring of ``params`` at ``fidelity`` (module docstring).

    None for a chain not of given materials (:func:`given_materials`) when ``fidelity`` is
    not set or ``"exact"``; a tolerance given for such a chain is a ValueError (its
    stiffness is a parameter of the model, not a material's). A chain of given materials
    with too elastic collisions (:func:`applies`) keeps the material's spring at any
    tolerance. Otherwise the softest spring ``k`` with ``eps(k) = tolerance``, never
    stiffer than the material's.
    """
    fidelity = check_fidelity(fidelity)
    if not given_materials(params):
        if fidelity is None or fidelity == EXACT:
            return None
        raise ValueError(
            f"fidelity = {fidelity!r} softens a chain of given materials only (shape = 'box'"
            f" with young and normal_law = 'linear'); this chain's stiffness is a parameter"
            f" of the model (shape = {params.shape!r}, young = {params.young!r}, normal_law ="
            f" {params.normal_law!r}): leave fidelity unset or 'exact'"
        )
    tolerance = tolerance_of(fidelity)
    k_m = params.contact_stiffness
    t_m = theory_collision_time(params)
    v = _reference_speed(params)
    per_point = params.pair_stiffness / k_m  # k_p = per_point * k_n
    # eps as a function of u = k^{-1/2}: eps = a (u - u_m) + b (u^2 - u_m^2), since
    # T_c = pi sqrt(m_r / k_p) (eq 31) goes as u and the overlap as u^2
    a = t_m * math.sqrt(k_m) * v / (2.0 * params.pitch)
    b = params.mass * params.g / (per_point * params.spacing)
    u_m = 1.0 / math.sqrt(k_m)
    if tolerance is None or not applies(params):  # nearly elastic: the material's spring
        u = u_m
    else:
        c = tolerance + a * u_m + b * u_m**2
        u = 2.0 * c / (a + math.sqrt(a * a + 4.0 * b * c))  # the positive root, stably
    softer = params.with_(kn=1.0 / u**2) if u > u_m else params
    return ContactFidelity(
        tolerance=tolerance,
        material_kn=k_m,
        kn=softer.contact_stiffness,
        stiffness_over_kstar=softer.stiffness_over_kstar,
        reference_speed=v,
        collision_time=theory_collision_time(softer),
        material_collision_time=t_m,
        overlap_per_weight=1.0 / softer.pair_stiffness - 1.0 / params.pair_stiffness,
        pitch=params.pitch,
        gap=params.spacing,
        weight=params.mass * params.g,
        softenable=applies(params),
    )
