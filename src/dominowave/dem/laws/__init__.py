"""Contact laws: what a contact point does with its overlap and relative motion.

Each law is a set of pure per-point functions (scalars in, scalars out), in the style of
jax-md; the drivers of dem/ (contact.py for spheres, boxes.py for rounded cuboids and
their walls and spheres) find the contact points and their kinematics and call
:func:`point.point_law`, the one law of every contact point:

* linear.py: the linear spring-dashpot normal law, with its onset and end corrections;
* hertz.py: the Hertz normal law with the Tsuji dashpot;
* tangential.py: the Coulomb-limited shear spring and the shear kinematics;
* point.py: the law of one contact point, normal and tangential together, and the
  energy its springs store and the power of its forces (the energy ledger of every
  driver).
"""
