"""dominowave: how fast are elastic domino waves?

Three independent instruments answer the question (the map of the package:
``docs/architecture.md``):

* :mod:`dominowave.theory` -- the closed-form results of the paper
  "How Fast are Elastic Domino Waves?" (Efthimiou-Johnson rigid limit, finite
  collision time, finite thickness, P-wave bound, contact force, no-slip bounds);
* :mod:`dominowave.rods` -- the paper's own hinged-domino model, simulated with
  Newton's laws and compliant contacts;
* :mod:`dominowave.dem` -- a general discrete-element engine (spheres, rigid
  clumps, walls, linear contact, Cundall-Strack friction, local damping).

All quantities are SI inside the package; dimensionless groups appear only at
the edges (plots, command-line tables).
"""

__version__ = "0.2.0"

from dominowave.kernel_cache import install as _install_kernel_cache

# before any kernel is defined: a kernel's on-disk cache goes stale with any change of
# the package's source, not only of its own file (kernel_cache.py)
_install_kernel_cache()
