"""The hinged compliant-domino model of the paper (Fig 1B/1C, Fig 3): its parameters.

N identical rigid dominoes of height ``l`` and thickness ``s`` stand with a gap ``d``
between faces (pitch ``d + s``). Each turns about a hinge at its *front bottom edge*
(no slip at the base, the paper's assumption), one angle per domino. Its front top edge
(the tip, for ``s = 0``) strikes the back face of the next domino when
``l sin(theta) = d`` (``theta = beta = asin(d/l)`` for ``s = 0``).

Everything is SI. The model knows nothing of the theory: no collision rule, no
collision time; only the masses, lever arms and the contact law.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

from dominowave.checks import check_finite, check_in_range, check_nonnegative, check_positive
from dominowave.units import G_STANDARD

__all__ = [
    "CONTACT_LAWS",
    "NORMALS",
    "MassDistribution",
    "RodChain",
    "block",
    "custom_mass",
    "point_mass",
    "thin_rod",
]

CONTACT_LAWS = ("linear", "hertz")
"""``linear``: F = k delta (the paper's law); ``hertz``: F = k delta^(3/2)."""

NORMALS = ("geometric", "head-on")
"""Direction of the contact force.

``geometric``: the normal of the struck face (real dominoes, the DEM).
``head-on``: the paper's assumption of Fig 3B: the force acts along the path of the
striking corner at the onset of contact (the axis xi, perpendicular to the striker),
between the corner and the material point of the face it hit. It describes a pair
collision, so it applies to the first contact of a domino's top edge with the next
domino; later contacts of that pair (re-collisions, leaning) are geometric.
"""


@dataclass(frozen=True)
class MassDistribution:
    """Inertia of one domino about its hinge.

    Attributes: ``m`` mass [kg]; ``inertia`` moment of inertia about the hinge [kg m^2];
    ``cm_u``, ``cm_w`` centre of mass in body coordinates [m] (``u`` across, negative
    towards the back face; ``w`` up along the domino); ``name`` for tables.
    """

    m: float
    inertia: float
    cm_u: float
    cm_w: float
    name: str = "custom"

    def __post_init__(self):
        check_positive("m", self.m)
        check_positive("inertia", self.inertia)
        check_finite("cm_u", self.cm_u)
        check_nonnegative("cm_w", self.cm_w)
        r2 = self.cm_u**2 + self.cm_w**2
        # parallel-axis theorem: I_pivot >= m r_cm^2
        if self.inertia < self.m * r2 * (1.0 - 1e-12):
            raise ValueError(
                f"inertia = {self.inertia:.6g} is outside the valid range "
                f"[m r_cm^2 = {self.m * r2:.6g}, inf) (parallel-axis theorem)"
            )


def point_mass(m: float, l: float) -> MassDistribution:
    """The paper's domino: all mass ``m`` at the front top edge, ``I = m l^2``."""
    check_positive("l", l)
    return MassDistribution(m=m, inertia=m * l * l, cm_u=0.0, cm_w=l, name="point mass")


def thin_rod(m: float, l: float, s: float = 0.0) -> MassDistribution:
    """Uniform rod along the mid-plane ``u = -s/2``: ``I = m l^2/3 + m s^2/4``."""
    check_positive("l", l)
    check_nonnegative("s", s)
    return MassDistribution(
        m=m, inertia=m * (l * l / 3.0 + s * s / 4.0), cm_u=-s / 2.0, cm_w=l / 2.0, name="thin rod"
    )


def block(m: float, l: float, s: float) -> MassDistribution:
    """Uniform rectangular block ``s x l``: ``I = m (l^2 + s^2)/3`` about its edge."""
    check_positive("l", l)
    check_nonnegative("s", s)
    return MassDistribution(
        m=m, inertia=m * (l * l + s * s) / 3.0, cm_u=-s / 2.0, cm_w=l / 2.0, name="block"
    )


def custom_mass(m: float, inertia: float, cm_u: float, cm_w: float) -> MassDistribution:
    """Any mass distribution: mass, moment of inertia about the hinge, centre of mass."""
    return MassDistribution(m=m, inertia=inertia, cm_u=cm_u, cm_w=cm_w, name="custom")


@dataclass(frozen=True)
class RodChain:
    """A chain of ``n`` identical hinged dominoes and their contacts.

    Attributes
    ----------
    n : number of dominoes (>= 2).
    l, d, s : height, gap between faces, thickness [m] (``0 < d < l``, ``0 <= s < l``).
    mass : :class:`MassDistribution` of each domino.
    k : stiffness of *one contact* [N/m] (linear) or [N/m^1.5] (Hertz). In the paper's
        "paper" convention each particle has stiffness ``k`` and the contact spring is
        ``k_r = k/2`` (eq 24): pass ``k = k_paper / 2`` here.
    law : ``"linear"`` or ``"hertz"``.
    normal : ``"geometric"`` (default) or ``"head-on"`` (see :data:`NORMALS`).
    damping_ratio : dashpot ``zeta`` in [0, 1) (0 = elastic, the paper's assumption).
    mu : Coulomb friction between dominoes (0 = the paper's assumption).
    v_reg : regularisation speed of the friction [m/s] (default ``1e-3 sqrt(g l)``).
    g : gravity [m/s^2]; 0 switches it off.
    floor_restitution : ``e`` in [0, 1] of a domino hitting the floor (flat on its face,
        or rocking back onto its base when ``s > 0``); losses are book-kept.
    gravity_in_contact : ``False`` switches gravity off on every domino while it is in
        contact: the theory's assumption of section 2.2 (for testing it only; the
        energy ledger then does not close).
    """

    n: int
    l: float
    d: float
    s: float = 0.0
    mass: MassDistribution = field(default_factory=lambda: point_mass(1.0, 1.0))
    k: float = 1e4 * 9.81 / 2
    law: str = "linear"
    normal: str = "geometric"
    damping_ratio: float = 0.0
    mu: float = 0.0
    v_reg: float | None = None
    g: float = G_STANDARD
    floor_restitution: float = 0.0
    gravity_in_contact: bool = True

    def __post_init__(self):
        if int(self.n) != self.n or self.n < 2:
            raise ValueError(f"n = {self.n} is outside the valid range [2, inf) (an integer)")
        check_positive("l", self.l)
        check_in_range("d", self.d, 0.0, self.l)
        check_in_range("s", self.s, 0.0, self.l, lo_inclusive=True)
        check_positive("k", self.k)
        check_in_range("k", self.k, 0.0, math.inf)
        if self.law not in CONTACT_LAWS:
            raise ValueError(f"law = {self.law!r} is not one of {CONTACT_LAWS}")
        if self.normal not in NORMALS:
            raise ValueError(f"normal = {self.normal!r} is not one of {NORMALS}")
        check_in_range("damping_ratio", self.damping_ratio, 0.0, 1.0, lo_inclusive=True)
        check_nonnegative("mu", self.mu)
        if self.mu > 0 and self.normal != "geometric":
            raise ValueError(
                f"mu = {self.mu:.6g} is outside the valid range [0, 0] for normal='head-on' "
                "(the head-on assumption is frictionless; use normal='geometric')"
            )
        if self.v_reg is not None:
            check_positive("v_reg", self.v_reg)
        check_nonnegative("g", self.g)
        check_in_range(
            "floor_restitution",
            self.floor_restitution,
            0.0,
            1.0,
            lo_inclusive=True,
            hi_inclusive=True,
        )
        if self.mass.cm_u < -self.s - 1e-15 or self.mass.cm_w > self.l * (1 + 1e-12):
            raise ValueError(
                f"mass centre (u, w) = ({self.mass.cm_u:.6g}, {self.mass.cm_w:.6g}) is outside "
                f"the domino [-s, 0] x [0, l] = [{-self.s:.6g}, 0] x [0, {self.l:.6g}]"
            )

    @property
    def pitch(self) -> float:
        """Distance between neighbouring hinges ``d + s`` [m]."""
        return self.d + self.s

    @property
    def friction_speed(self) -> float:
        """Regularisation speed of the friction [m/s]."""
        if self.v_reg is not None:
            return self.v_reg
        return 1e-3 * math.sqrt(max(self.g, 1e-300) * self.l) if self.g > 0 else 1e-3

    def smallest_reduced_mass(self) -> float:
        """Lower bound of the reduced mass of any contact coordinate [kg].

        A contact overlap changes with each angle through a lever arm no longer than the
        domino's diagonal ``r = sqrt(l^2 + s^2)``, so ``m_r = 1/sum(g_i^2/I) >= I/(2 r^2)``.
        """
        r2 = self.l**2 + self.s**2
        return self.mass.inertia / (2.0 * r2)

    def time_step(self, steps_per_contact: float = 50.0, speed_bound: float | None = None) -> float:
        """Fixed time step [s]: at least ``steps_per_contact`` steps per contact, ever.

        Linear law: the half period ``pi sqrt(m_r/k)`` of a contact with the smallest
        possible reduced mass (a lower bound of every collision duration in the chain,
        computed from the model's inertia, not from the theory's T_c). Hertz law: the same
        with the tangent stiffness at the largest overlap a collision at ``speed_bound``
        [m/s] can reach (default ``4 sqrt(g l)``). Never more than
        ``sqrt(l/g) / (2 steps_per_contact)`` (gravity-driven motion, floor impacts).
        """
        check_in_range("steps_per_contact", steps_per_contact, 1.0, math.inf, lo_inclusive=True)
        m_r = self.smallest_reduced_mass()
        if self.law == "linear":
            k_t = self.k
        else:
            v = (
                speed_bound
                if speed_bound is not None
                else 4.0 * math.sqrt(max(self.g, 1.0) * self.l)
            )
            check_positive("speed_bound", v)
            delta_max = (1.25 * m_r * v * v / self.k) ** 0.4  # energy balance of a Hertz contact
            k_t = 1.5 * self.k * math.sqrt(delta_max)
        dt = math.pi * math.sqrt(m_r / k_t) / steps_per_contact
        if self.g > 0:
            dt = min(dt, math.sqrt(self.l / self.g) / (2.0 * steps_per_contact))
        return dt
