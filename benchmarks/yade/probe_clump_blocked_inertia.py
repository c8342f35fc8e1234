# ruff: noqa: F821  (YADE injects O, FrictMat, engines, Vector3, ... into the namespace)
"""YADE 2023.02a: a clump with blocked rotations turns with the wrong moment of inertia.

Run as ``yade -n -j1 -x benchmarks/yade/probe_clump_blocked_inertia.py`` (a second).

Finding. ``NewtonIntegrator`` switches to its *spherical* rotation integrator as soon
as one rotational DOF is blocked (``useAspherical`` requires no blocked rotation), and
that integrator computes ``angAccel[i] = torque[i] / state.inertia[i]`` with the torque
in *world* components. For a clump, ``Clump::updateProperties`` stores in
``state.inertia`` the principal moments in the clump's *body* frame, with ``state.ori``
rotating body to world, and it may permute the axes. For a planar domino (a column of
spheres in the xz plane on a two-sphere base) the body frame is a cyclic permutation:
body x = world z, body y = world x, body z = world y. A 2D domino (``blockedDOFs =
"yXZ"``, rotation about world y only) is then accelerated with ``inertia[1]`` = I_xx
(1.402774e-7 kg m^2) instead of I_yy (1.403797e-7): its angular acceleration is 7.3e-4
too large. The free clump (aspherical integrator, angular momentum in the body frame)
is exact.

This script applies a constant torque about world y and compares the moment of inertia
YADE uses, ``I_used = tau dt / delta(omega)`` per step, with the exact I_yy about the
centre of mass (closed form: sum of m (2/5 r^2 + x^2 + z^2) over the non-overlapping
members). It also applies the workaround of ``chain_yade.py``: for a clump with blocked
rotations, set ``state.inertia`` to the moments about the *world* axes,
diag(R diag(I) R^T). Measured (YADE 2023.02a):

    free clump            I_used / I_yy - 1 =  0 (round-off)
    blocked "yXZ"         I_used / I_yy - 1 = -7.3e-4   (= I_xx / I_yy - 1)
    blocked + workaround  I_used / I_yy - 1 =  0 (round-off)

In the chain cross-check this error moved domino 0's fall by 4.4e-7 m (centre of mass
height at first impact, the same at dt, dt/4, dt/16), enough to shift the third
collision of a frictionless 4-domino chain by 5.4e-4 relative at d/l = 0.6 (dt-independent).
(Damping is 0 here: NewtonIntegrator's default damping = 0.2 scales a torque that
accelerates the spin by 0.8.)
"""

from yade import utils

R = 0.0025  # sphere radius [m] (s = 5 mm), domino l = 50 mm
RHO = 1000.0
# two base spheres of radius R/2 (4x denser: same mass as one bead) + 9 beads of radius R
SPHERES = [(-R / 2, R / 2, R / 2, 4 * RHO), (R / 2, R / 2, R / 2, 4 * RHO)] + [
    (0.0, (2 * k + 1) * R, R, RHO) for k in range(1, 10)
]
TAU, DT, STEPS = 1e-6, 1e-5, 20
omega_log = []


def kick():
    omega_log.append(O.bodies[probe["clump"]].state.angVel[1])
    O.forces.addT(probe["clump"], Vector3(0, TAU, 0))


probe = {}
results = {}
for case in ("free", "blocked", "blocked + workaround"):
    O.reset()
    spheres = [
        utils.sphere((x, 0.0, z), r, material=FrictMat(density=rho)) for x, z, r, rho in SPHERES
    ]
    cid, ids = O.bodies.appendClumped(spheres)
    b = O.bodies[cid]
    probe["clump"] = cid
    com = b.state.pos
    exact = sum(
        O.bodies[i].state.mass
        * (
            0.4 * O.bodies[i].shape.radius ** 2
            + (O.bodies[i].state.pos[0] - com[0]) ** 2
            + (O.bodies[i].state.pos[2] - com[2]) ** 2
        )
        for i in ids
    )
    if case != "free":
        b.state.blockedDOFs = "yXZ"
    if case == "blocked + workaround":
        rot, inertia = b.state.ori.toRotationMatrix(), b.state.inertia
        b.state.inertia = Vector3(
            *(sum(rot[i, j] ** 2 * inertia[j] for j in range(3)) for i in range(3))
        )
    O.engines = [
        ForceResetter(),
        PyRunner(iterPeriod=1, command="kick()"),
        NewtonIntegrator(gravity=(0, 0, 0), damping=0.0),
    ]
    O.dt = DT
    omega_log.clear()
    O.run(STEPS, True)
    used = TAU * DT / (omega_log[-1] - omega_log[-2])
    results[case] = used / exact - 1.0
    print(
        f"{case:22s} state.inertia = {tuple(b.state.inertia)}; exact I_yy = {exact:.9e}; "
        f"I_used = {used:.9e}; I_used / I_yy - 1 = {results[case]:+.2e}"
    )
print("YADE_PROBE_RESULT", results)
