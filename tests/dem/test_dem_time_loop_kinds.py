"""The time loop is compiled for each kind of scene (engine.time_loop, SceneKind).

numba compiles a function with everything it calls; the loop of a kind must call only
the kernels of what that kind of scene holds (numba drops the branches of the other
kinds before typing, which these tests read from the loop's pruned IR, without compiling
it), and a kind may leave out only calls that would have done nothing: a scene run with
the loop with the box kernels follows the same trajectory to the bit.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba.core import analysis, compiler, ir

from dominowave.chain import ChainParams, DominoChain, Push
from dominowave.chain.presets import standard_domino
from dominowave.dem import SceneKind, Simulation, box_sphere, boxes, contact, engine, integrate
from dominowave.dem.engine import time_loop
from dominowave.dem.shapes import cuboid, rectangle

BOX_KERNELS = {"build_box_candidates", "box_power", "box_peak_force"}
# the kernels of one source compiled for each kind of scene (contact._sphere_driver,
# engine._body_pass, boxes._box_driver, boxes._box_sphere_pass), and the integrator's
GENERAL = {contact.compute_forces, engine._advance_general,
           integrate.kick_general, integrate.drift_general}  # fmt: skip
PLANAR = {contact.compute_forces_planar, engine._advance_planar,
          integrate.kick_planar, integrate.drift_planar}  # fmt: skip
# the box driver that a scene of boxes and spheres calls, with the box-sphere points, and
# every box driver of a kind
BOX_GENERAL = {boxes.box_forces_general_spheres}
BOX_PLANAR = {boxes.box_forces_planar_spheres}
BOX_DRIVERS = {
    False: {boxes.box_forces_general, boxes.box_forces_general_spheres},
    True: {boxes.box_forces_planar, boxes.box_forces_planar_spheres},
}
# what only spheres need: their list, contacts and records, and the box-sphere contacts
SPHERE_KERNELS = GENERAL - {engine._advance_general, integrate.kick_general,
                            integrate.drift_general} | {
    contact.compute_forces_planar, contact.build_verlet_list, engine._record_contact_forces,
    integrate.update_listed_sphere_positions, integrate.update_sphere_positions,
    box_sphere.build_box_sphere_candidates, *BOX_GENERAL, *BOX_PLANAR,
    boxes._sphere_pass_general, boxes._sphere_pass_planar, cuboid.box_sphere,
    rectangle.rect_sphere,
}  # fmt: skip
# the geometry of the box pairs in 3D (shapes.cuboid) and in a plane (shapes.rectangle)
GEOMETRY_GENERAL = {cuboid.box_box, cuboid.box_plane, cuboid.box_sphere, cuboid.faces_separate}
GEOMETRY_PLANAR = {rectangle.rect_rect, rectangle.rect_plane, rectangle.rect_sphere,
                   rectangle.edges_separate}  # fmt: skip


def _called_kernels(kernel) -> set:
    """The compiled functions ``kernel`` calls once numba has pruned the branches of its
    constants (the untyped IR that numba types next)."""
    func_ir = compiler.run_frontend(kernel.py_func)
    # (the arguments unknown: a branch on an argument stays)
    analysis.dead_branch_prune(func_ir, (None,) * func_ir.arg_count)
    kernels = set()
    for block in func_ir.blocks.values():
        for stmt in block.body:
            if isinstance(stmt, ir.Assign) and isinstance(stmt.value, (ir.Global, ir.FreeVar)):
                if hasattr(stmt.value.value, "py_func"):
                    kernels.add(stmt.value.value)
    return kernels


def _compiled_with(kernel) -> set:
    """Every compiled function that compiling ``kernel`` compiles: those it calls, those
    they call, and so on."""
    seen, todo = set(), [kernel]
    while todo:
        for callee in _called_kernels(todo.pop()) - seen:
            seen.add(callee)
            todo.append(callee)
    return seen


@pytest.mark.parametrize("planar", [True, False])
@pytest.mark.parametrize("boxes", [False, True])
def test_a_kind_calls_only_its_own_kernels(planar, boxes):
    called = _called_kernels(time_loop(SceneKind(planar, boxes)))
    names = {kernel.py_func.__name__ for kernel in called}
    assert "needs_rebuild" in names and "energies" in names  # (the IR was read)
    own, other = (PLANAR, GENERAL) if planar else (GENERAL, PLANAR)
    assert own <= called and not called & other
    assert {"build_verlet_list", "_bookkeep"} <= names  # (in every kind with spheres)
    own_boxes, other_boxes = (BOX_PLANAR, BOX_GENERAL) if planar else (BOX_GENERAL, BOX_PLANAR)
    if boxes:
        assert BOX_KERNELS <= names and own_boxes <= called and not called & other_boxes
        assert not called & BOX_DRIVERS[not planar]
    else:
        assert not names & BOX_KERNELS and not called & (BOX_DRIVERS[True] | BOX_DRIVERS[False])


@pytest.mark.parametrize("planar", [True, False])
def test_a_box_scene_compiles_the_geometry_of_its_own_kind_only(planar):
    """A planar box chain compiles no 3D box geometry, a 3D one no planar geometry: the
    loop, and everything it calls, calls only its kind's."""
    compiled = _compiled_with(time_loop(SceneKind(planar, True)))
    own, other = (
        (GEOMETRY_PLANAR, GEOMETRY_GENERAL) if planar else (GEOMETRY_GENERAL, GEOMETRY_PLANAR)
    )
    assert own <= compiled and not compiled & other
    clumps = _compiled_with(time_loop(SceneKind(planar, False)))
    assert not clumps & (GEOMETRY_GENERAL | GEOMETRY_PLANAR)


@pytest.mark.parametrize("planar", [True, False])
def test_a_scene_of_boxes_alone_compiles_no_sphere_kernel(planar):
    """The loop of a scene of boxes without spheres (every box chain) compiles none of the
    sphere kernels, which the loop of boxes with spheres compiles (its kind's)."""
    alone = _compiled_with(time_loop(SceneKind(planar, True, spheres=False)))
    with_spheres = _compiled_with(time_loop(SceneKind(planar, True, spheres=True)))
    own_boxes = boxes.box_forces_planar if planar else boxes.box_forces_general
    own_points = boxes._sphere_pass_planar if planar else boxes._sphere_pass_general
    assert own_boxes in alone and own_points in with_spheres
    assert engine._bookkeep in alone  # (the events of the box contacts)
    assert not alone & SPHERE_KERNELS
    own_spheres = contact.compute_forces_planar if planar else contact.compute_forces
    assert {own_spheres, contact.build_verlet_list, box_sphere.build_box_sphere_candidates} <= (
        with_spheres & SPHERE_KERNELS
    )


@pytest.mark.parametrize(
    "params",
    [
        ChainParams(shape="box", n_dominoes=4, friction_dominoes=0.3),  # the paper's, 2D
        standard_domino(gap=0.00938, floor="felt", n_dominoes=5),  # 3D, asleep at the end
    ],
    ids=["2d", "3d standard"],
)
def test_validate_a_box_chain_runs_alike_with_the_sphere_kernels(params, monkeypatch):
    """A box chain run with its own loop (no sphere kernels) and with the loop that holds
    them ends in the same state to the bit, its records too: the paper's 2D chain for
    3000 steps, the standard 3D chain until it has fallen and every domino sleeps."""
    push = Push(omega=1.2 * math.sqrt(params.g / params.height))
    own_kind = Simulation.kind.fget
    with_spheres = property(lambda sim: own_kind(sim)._replace(spheres=True))
    runs = []
    for spheres in (False, True):
        if spheres:
            monkeypatch.setattr(Simulation, "kind", with_spheres)
        sim, _ = DominoChain(params).build(push, record=True, track_energy=True)
        assert sim.kind.spheres == spheres
        limit = {"n_steps": 3000} if params.model == "2d" else {"until": 1.5}
        res = sim.run(**limit, trajectory_every=97, energy_every=89, record_contact_forces=True)
        runs.append((sim.get_state(), res))
    (mine, mine_res), (every, every_res) = runs
    if params.model == "3d":
        assert np.all(sim.bodies.held == 1) and np.isfinite(sim.bodies.calm_since).all()
    assert mine.keys() == every.keys()
    for key in mine:
        np.testing.assert_array_equal(mine[key], every[key], err_msg=key)
    for key in ("positions", "quaternions", "energy_times"):
        np.testing.assert_array_equal(getattr(mine_res, key), getattr(every_res, key), key)
    for key, value in mine_res.energy.items():
        np.testing.assert_array_equal(value, every_res.energy[key], err_msg=key)
    for key in ("start", "first", "second", "point", "force"):
        np.testing.assert_array_equal(
            getattr(mine_res.contact_frames, key), getattr(every_res.contact_frames, key), key
        )


@pytest.mark.parametrize(
    "fields",
    [
        dict(n_dominoes=6),  # 2D clumps
        dict(n_dominoes=4, model="3d", lateral_asymmetry=0.01),  # 3D clumps
    ],
)
def test_validate_the_loop_of_every_kind_gives_the_same_trajectory(fields, monkeypatch):
    """A clump chain run with the loop of its own kind and with the loop that holds the
    box kernels too (the planar flag as the scene's) end in the same state to the bit:
    what a kind leaves out does nothing in a scene of that kind."""
    p = ChainParams(friction_dominoes=0.3, friction_floor=0.5, **fields)
    push = Push(omega=1.2 * math.sqrt(p.g / p.height))
    own_kind = Simulation.kind.fget
    every_kind = property(lambda sim: SceneKind(own_kind(sim).planar, True))
    states = []
    for everything in (False, True):
        if everything:
            monkeypatch.setattr(Simulation, "kind", every_kind)
        sim, _ = DominoChain(p).build(push, record=True, track_energy=True)
        if everything:
            # the box lists of a scene without boxes are complete and empty; left at
            # "never built" (-1), the loop with box kernels would build them at its first
            # step, and a list build places every sphere anew (round-off of the centres)
            sim.boxes.n_cand[0] = sim.boxes.n_sphere_cand[0] = 0
        sim.run(n_steps=1500, trajectory_every=97, energy_every=89, record_contact_forces=True)
        sim.run(n_steps=1500)
        states.append(sim.get_state())
    mine, every = states
    assert mine.keys() == every.keys()
    for key in mine:
        np.testing.assert_array_equal(mine[key], every[key], err_msg=key)
