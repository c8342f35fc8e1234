"""The analytic theory of the paper (section 2): closed forms, vectorised, SI units.

* :mod:`.rigid` -- Efthimiou-Johnson rigid thin dominoes (eqs 2-14) and the transient;
* :mod:`.compliant` -- finite collision time, wave speeds, P-wave bound (eqs 15-35);
* :mod:`.bounds` -- peak contact force and the base-slip regimes (eqs 36-42);
* :mod:`.leaning` -- beyond the paper: the leaning train of real dominoes (Shaw 1978,
  van Leeuwen 2010), inelastic collisions and friction between dominoes
  (``from dominowave.theory import leaning``; ``leaning.limit_speed(...)``).

Conventions, derivations and the typos found in the paper: ``docs/theory.md``.
"""

from dominowave.theory import bounds, compliant, rigid
from dominowave.theory.bounds import *  # noqa: F403
from dominowave.theory.compliant import *  # noqa: F403
from dominowave.theory.rigid import *  # noqa: F403

# (each name declared once, in its module's own __all__)
__all__ = sorted([*bounds.__all__, *compliant.__all__, *rigid.__all__])
