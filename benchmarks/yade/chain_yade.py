# ruff: noqa: F821  (YADE injects O, FrictMat, engines, Vector3, ... into the namespace)
"""YADE side of the chain cross-check: build the scene described in a JSON file, run it.

Run as ``yade -n -j1 -x chain_yade.py`` with ``CHAIN_SCENE=<in.json> CHAIN_OUT=<out.json>``
(``compare_yade.py`` does this). The JSON is written by dominowave's ``DominoChain`` so
both codes get identical spheres, masses, stiffnesses, friction, damping, push, time
step and standing rule (a two-sphere base: YADE has no "held until touched" flag).

Contact law: YADE's Ip2_FrictMat_FrictMat_FrictPhys gives k_n = 2 E1 R1 E2 R2 /
(E1 R1 + E2 R2) and a wall takes the sphere's radius. With E = k_n / R for spheres of
radius R and 2 E for the base spheres of radius R/2, every contact has the same k_n as
dominowave's (kn given per material); k_s = poisson * k_n with poisson = kt_ratio.
Friction angle atan(mu), min rule per contact (YADE's default).

Modes: ``record`` -- a PyRunner after the InteractionLoop (every step) notes the step
time t_n at which each domino first has a real interaction with a lower-numbered one
(dominowave logs onsets at the same t_n); ``engines`` -- no Python callback, run a
given number of steps and time it (speed benchmark).
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


O.bodies.append(
    utils.wall(
        0.0, axis=2, sense=0, material=material(R, scene["density"], scene["friction_floor"])
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
        )
        for c, r, rho, bottom in zip(
            body["centres"], body["radii"], body["density"], body["bottom"], strict=True
        )
    ]
    cid, ids = O.bodies.appendClumped(spheres)
    b = O.bodies[cid]
    b.state.blockedDOFs = scene["blocked"]
    b.state.vel = Vector3(*body["velocity"])
    w = Vector3(*body["angular_velocity"])
    b.state.angVel = w
    # YADE integrates the angular momentum of aspherical bodies: set it consistently,
    # L = R diag(I) R^T omega (principal inertia in the body frame, ori: body -> world)
    w_body = b.state.ori.conjugate() * w
    inertia = b.state.inertia
    b.state.angMom = b.state.ori * Vector3(*(inertia[i] * w_body[i] for i in range(3)))
    clumps.append(cid)
    members.append(ids)

owner = {}
for k, ids in enumerate(members):
    for i in ids:
        owner[i] = k
n = len(clumps)
arrival = [float("nan")] * n
arrival[0] = 0.0
state = {"next": 1}


trace = []


def record():
    # first real interaction of domino `next` with a lower-numbered domino, at t_n
    if scene.get("trace_every") and O.iter % scene["trace_every"] == 0:
        trace.append(
            [O.time]
            + [O.bodies[c].state.angVel[1] for c in clumps[:3]]
            + [O.bodies[c].state.pos[0] for c in clumps[:3]]
        )
    while state["next"] < n:
        m = state["next"]
        hit = False
        for i in members[m]:
            for it in O.bodies[i].intrs():
                other = it.id1 if it.id2 == i else it.id2
                if it.isReal and owner.get(other, n) < m:
                    hit = True
                    break
            if hit:
                break
        if not hit:
            return
        arrival[m] = O.time
        state["next"] = m + 1
        if m + 1 == n and scene["mode"] == "record":
            O.pause()


engines = [
    ForceResetter(),
    InsertionSortCollider([Bo1_Sphere_Aabb(), Bo1_Wall_Aabb()]),
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

start = time.perf_counter()
if scene["mode"] == "record":
    O.run(int(scene["max_steps"]), True)
else:
    O.run(int(scene["n_steps"]), True)
wall = time.perf_counter() - start
json.dump(
    {"arrival": arrival, "wall_time": wall, "n_steps": O.iter, "time": O.time, "trace": trace},
    open(os.environ["CHAIN_OUT"], "w"),
)
