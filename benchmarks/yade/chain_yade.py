# ruff: noqa: F821  (YADE injects O, FrictMat, engines, Vector3, ... into the namespace)
"""YADE side of the chain cross-check: build the scene described in a JSON file, run it.

Run as ``yade -n -j1 -x chain_yade.py`` with ``CHAIN_SCENE=<in.json> CHAIN_OUT=<out.json>``
(``compare_yade.py`` does this). The JSON is written by dominowave's ``DominoChain`` so
both codes get identical spheres, masses, stiffnesses, friction, damping, push, time
step and standing rule: a two-sphere base, or ``"held": true`` (record mode only): every
domino but the first is fixed (all DOFs blocked) until a domino that moves touches it, as
dominowave's held flag -- the PyRunner releases it in the step of the first real
interaction, before the NewtonIntegrator (dominowave starts a released body with a half
kick, YADE with a whole one: an O(dt) difference of its first velocity).

Contact law: YADE's Ip2_FrictMat_FrictMat_FrictPhys gives k_n = 2 E1 R1 E2 R2 /
(E1 R1 + E2 R2) and a wall takes the sphere's radius. With E = k_n / R for spheres of
radius R and 2 E for the base spheres of radius R/2, every sphere-sphere contact has the
same k_n as dominowave's (kn given per material); k_s = poisson * k_n with poisson =
kt_ratio. Friction angle atan(mu), min rule per contact (YADE's default).

Two details of YADE that the scene must get right (each alone moves the 2nd and 3rd
collision times by 0.07-0.8 %; benchmarks/README.md):

* The floor: a wall-sphere contact uses the wall's E with the *sphere's* radius, so a
  single wall of E = k_n / R would give the R/2 base spheres k_n = 2 (k_n/2) k_n /
  (3 k_n/2) = 2/3 k_n (a softer floor under every base; standing dominoes out of
  equilibrium at the sink computed for k_n). Hence one wall per sphere radius, both at
  z = 0, E_wall = k_n / r, and collision masks so that each sphere only meets the wall
  of its own radius (bit 0: all spheres, bit 1 + i: wall i). Every floor contact has
  k_n, as in dominowave.
* Blocked rotations (2D): YADE then integrates the clump with its spherical integrator,
  torque[i] / state.inertia[i] in world components, but a clump's state.inertia holds
  its principal moments in the body frame (here body z = world y): the domino would turn
  with I_xx instead of I_yy (7.3e-4 smaller). Hence state.inertia is set to the moments
  about the world axes (``probe_clump_blocked_inertia.py`` shows the YADE behaviour).

Modes: ``record`` -- a PyRunner after the InteractionLoop (every step) notes the step
time t_n at which each domino first has a real interaction with a lower-numbered one
(``arrival``) and the onset interpolated inside that step exactly as dominowave's event
log does, ``t_n - delta_n / |v_n|`` (overlap over approach speed of the member spheres
from the half-step velocities, clipped to one step; earliest of the new contacts;
``onset``); ``engines`` -- no Python callback, run a given number of steps and time it
(speed benchmark).
"""

import json
import math
import os
import time

from yade import utils

scene = json.load(open(os.environ["CHAIN_SCENE"]))
O.reset()
kn, R = scene["kn"], scene["radius"]
materials = {}


def material(radius, density, friction):
    key = (radius, density, friction)
    if key not in materials:
        materials[key] = O.materials.append(
            FrictMat(
                young=kn / radius,
                poisson=scene["kt_ratio"],
                frictionAngle=math.atan(friction),
                density=density,
            )
        )
    return materials[key]


# one floor wall per sphere radius (see the module docstring), masks 0b10, 0b100, ...
# (a single wall would give the R/2 base spheres a floor of 2/3 k_n)
radii_all = sorted({r for body in scene["bodies"] for r in body["radii"]})
wall_mask = {r: 1 << (1 + i) for i, r in enumerate(radii_all)}
for r in radii_all:
    O.bodies.append(
        utils.wall(
            0.0,
            axis=2,
            sense=0,
            material=material(r, scene["density"], scene["friction_floor"]),
            mask=wall_mask[r],
        )
    )
clumps, members = [], []
for body in scene["bodies"]:
    spheres = [
        utils.sphere(
            c,
            r,
            material=material(
                r, rho, scene["friction_floor"] if bottom else scene["friction_dominoes"]
            ),
            mask=1 | wall_mask[r],
        )
        for c, r, rho, bottom in zip(
            body["centres"], body["radii"], body["density"], body["bottom"], strict=True
        )
    ]
    cid, ids = O.bodies.appendClumped(spheres)
    b = O.bodies[cid]
    held = scene.get("held", False) and len(clumps) > 0
    b.state.blockedDOFs = "xyzXYZ" if held else scene["blocked"]
    b.state.vel = Vector3(*body["velocity"])
    w = Vector3(*body["angular_velocity"])
    b.state.angVel = w
    # YADE integrates the angular momentum of aspherical bodies: set it consistently,
    # L = R diag(I) R^T omega (principal inertia in the body frame, ori: body -> world)
    w_body = b.state.ori.conjugate() * w
    inertia = b.state.inertia
    b.state.angMom = b.state.ori * Vector3(*(inertia[i] * w_body[i] for i in range(3)))
    if any(axis in scene["blocked"] for axis in "XYZ"):
        # With a rotation blocked, NewtonIntegrator uses its *spherical* integrator,
        # angAccel[i] = torque[i] / inertia[i] with world components, while a clump's
        # state.inertia holds the principal moments of its *body* frame (here body z =
        # world y). Without this the 2D domino turns with I_xx instead of I_yy (7.3e-4
        # smaller). Give it the moments about the world axes: diag(R diag(I) R^T).
        rot = b.state.ori.toRotationMatrix()
        b.state.inertia = Vector3(
            *(sum(rot[i, j] ** 2 * inertia[j] for j in range(3)) for i in range(3))
        )
    clumps.append(cid)
    members.append(ids)

owner = {}
for k, ids in enumerate(members):
    for i in ids:
        owner[i] = k
n = len(clumps)
held = [scene.get("held", False) and k > 0 for k in range(n)]
arrival = [float("nan")] * n
arrival[0] = 0.0
onset = [float("nan")] * n  # interpolated inside the step, as dominowave's event log
onset[0] = 0.0
state = {"next": 1}


trace = []


def member_velocity(body):
    # velocity of a clump member over the last drift: clump v + omega x r (half-step values)
    c = O.bodies[body.clumpId].state
    return c.vel + c.angVel.cross(body.state.pos - c.pos)


def onset_time(it, t, dt):
    # dominowave's contact_rows.event_lag: overlap linear over the drift [t - dt, t], approach speed
    # from the half-step velocities: t - delta / |v_n|, clipped to [t - dt, t]
    speed = (member_velocity(O.bodies[it.id1]) - member_velocity(O.bodies[it.id2])).dot(
        it.geom.normal
    )
    depth = it.geom.penetrationDepth
    if speed <= 0.0:
        return t
    if depth >= speed * dt:
        return t - dt
    return t - depth / speed


def release():
    # free every held domino that has a real interaction with a free one (transitively)
    changed = True
    while changed:
        changed = False
        for m in range(n):
            if held[m] and touches_free(m):
                held[m] = False
                O.bodies[clumps[m]].state.blockedDOFs = scene["blocked"]
                changed = True


def touches_free(m):
    for i in members[m]:
        for it in O.bodies[i].intrs():
            other = owner.get(it.id1 if it.id2 == i else it.id2)
            if it.isReal and other is not None and not held[other]:
                return True
    return False


def record():
    # first real interaction of domino `next` with a lower-numbered domino: the step time
    # t_n (arrival) and the onset interpolated inside the step (onset)
    if any(held):
        release()
    if scene.get("trace_every") and O.iter % scene["trace_every"] == 0:
        trace.append(
            [O.time]
            + [O.bodies[c].state.angVel[1] for c in clumps[:3]]
            + [O.bodies[c].state.pos[0] for c in clumps[:3]]
        )
    while state["next"] < n:
        m = state["next"]
        hits = []
        for i in members[m]:
            for it in O.bodies[i].intrs():
                other = it.id1 if it.id2 == i else it.id2
                if it.isReal and owner.get(other, n) < m:
                    hits.append(it)
        if not hits:
            return
        arrival[m] = O.time
        onset[m] = min(onset_time(it, O.time, O.dt) for it in hits)
        state["next"] = m + 1
        if m + 1 == n and scene["mode"] == "record":
            O.pause()


# Collider settings (a helper's scan of verletDist, targetInterv, minSweepDistFactor,
# updatingDispFactor and the Newton flags; every setting gave bitwise identical
# trajectories; collider_scan.py re-measures the main ones). targetInterv=0: every bound is
# enlarged by the full verletDist (the default 100 shrinks the sweep of slow bodies, so the
# standing dominoes re-trigger the collider): 1.43x faster at N = 300, while YADE's
# defaults are 9 % faster at N = 30; verletDist=-1: one smallest radius.
# scene["collider"] overrides them (bench_chain.py times both and takes the faster).
collider = InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()])
for name, value in {"targetInterv": 0, "verletDist": -1, **scene.get("collider", {})}.items():
    setattr(collider, name, value)
engines = [
    ForceResetter(),
    collider,
    InteractionLoop(
        [Ig2_Sphere_Sphere_ScGeom(), Ig2_Wall_Sphere_ScGeom()],
        [Ip2_FrictMat_FrictMat_FrictPhys()],
        [Law2_ScGeom_FrictPhys_CundallStrack()],
    ),
]
if scene["mode"] == "record":
    engines.append(PyRunner(iterPeriod=1, command="record()"))
engines.append(NewtonIntegrator(gravity=(0.0, 0.0, -scene["g"]), damping=scene["damping"]))
O.engines = engines
O.dt = scene["dt"]

# O.run(n, True) waits in 40 ms sleeps, so it reports whole multiples of 40 ms (measured:
# 1000 steps of a small scene "0.0403 s", with fine polling 0.0307 s); poll every 0.1 ms
# instead (from the main thread, while YADE's one worker thread runs the engines).
start = time.perf_counter()
O.run(int(scene["max_steps"] if scene["mode"] == "record" else scene["n_steps"]))
while O.running:
    time.sleep(1e-4)
wall = time.perf_counter() - start
json.dump(
    {
        "arrival": arrival,
        "onset": onset,
        "wall_time": wall,
        "n_steps": O.iter,
        "time": O.time,
        "trace": trace,
        "collider_runs": collider.numAction,
        "final_positions": [list(O.bodies[b].state.pos) for b in clumps],
    },
    open(os.environ["CHAIN_OUT"], "w"),
)
