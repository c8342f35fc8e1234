"""The analytic theory of the paper (section 2): closed forms, vectorised, SI units.

* :mod:`.rigid` -- Efthimiou-Johnson rigid thin dominoes (eqs 2-14) and the transient;
* :mod:`.compliant` -- finite collision time, wave speeds, P-wave bound (eqs 15-35);
* :mod:`.bounds` -- peak contact force and the base-slip regimes (eqs 36-42);
* :mod:`.leaning` -- beyond the paper: the leaning train of real dominoes (Shaw 1978,
  van Leeuwen 2010), inelastic collisions and friction between dominoes
  (``from dominowave.theory import leaning``; ``leaning.limit_speed(...)``).

Conventions, derivations and the typos found in the paper: ``docs/theory.md``.
"""

from dominowave.theory.bounds import (
    REGIME_NAMES,
    Regime,
    RegimeBoundaries,
    RegimeClassification,
    classify_regime,
    peak_contact_force,
    regime_boundaries,
    sliding_rotation_sign,
)
from dominowave.theory.compliant import (
    StiffnessConvention,
    collision_time,
    collision_time_from_material,
    contact_stiffness,
    contact_stiffness_from_material,
    p_wave_speed,
    p_wave_speed_thick,
    pair_regime_holds,
    reduced_mass,
    struck_effective_mass,
    wave_speed,
    wave_speed_thick,
)
from dominowave.theory.rigid import (
    arrival_times,
    b_coefficient,
    collision_map,
    f_minus,
    f_plus,
    fall_time,
    fall_time_limit,
    mclachlan_G,
    omega_before_collision,
    omega_limit,
    omega_n_squared,
    omega_next_squared,
    wave_speed_rigid,
)

__all__ = [
    "REGIME_NAMES",
    "Regime",
    "RegimeBoundaries",
    "RegimeClassification",
    "StiffnessConvention",
    "arrival_times",
    "b_coefficient",
    "classify_regime",
    "collision_map",
    "collision_time",
    "collision_time_from_material",
    "contact_stiffness",
    "contact_stiffness_from_material",
    "f_minus",
    "f_plus",
    "fall_time",
    "fall_time_limit",
    "mclachlan_G",
    "omega_before_collision",
    "omega_limit",
    "omega_n_squared",
    "omega_next_squared",
    "p_wave_speed",
    "p_wave_speed_thick",
    "pair_regime_holds",
    "peak_contact_force",
    "reduced_mass",
    "regime_boundaries",
    "sliding_rotation_sign",
    "struck_effective_mass",
    "wave_speed",
    "wave_speed_rigid",
    "wave_speed_thick",
]
