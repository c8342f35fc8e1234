"""Per-shape contact geometry of the DEM engine: pure per-pair functions (numba).

``sphere`` holds the sphere's contacts with spheres and walls.  ``cuboid`` (3D) and
``rectangle`` (2D, the xz plane) hold the rounded cuboid: a box swept by a sphere (a
sphero-polyhedron, Alonso-Marroquin 2008; Galindo-Torres et al. 2009), its mass
properties, and its contacts with planes, spheres and other rounded boxes.
"""
