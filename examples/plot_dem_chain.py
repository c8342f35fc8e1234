"""
One DEM domino chain
====================

A chain of dominoes built from rigid clumps of spheres (the paper's Fig 6 model),
pushed at the first domino and integrated by the compiled DEM engine. We look at
its per-domino table, compare the arrival times of the wave with the theory's
transient on the same dominoes, and draw one frame of the toppling chain.

The chain is short (12 dominoes) so this runs in a second once the numba kernels
are compiled (the first run of a fresh install compiles those of a 2D clump chain: about
30 s on 2 cores).
"""

# %%
# Parameters are SI units; ``d_over_l`` is the gap over the height and
# ``stiffness_ratio`` the paper's ``k / k*``.
import matplotlib.pyplot as plt
import numpy as np

from dominowave.chain import ChainParams, DominoChain, Push, unsettled_reason

params = ChainParams(n_dominoes=12, height=0.05, thickness=0.005, d_over_l=0.4)
chain = DominoChain(params)
# the push: an angular velocity of domino 0 of 1 sqrt(g/l) [rad/s]
push = Push(omega=1.0 * np.sqrt(params.g / params.height))
run = chain.run(push, keep_record=True)  # keep_record: the frames, for drawing

# %%
# The per-domino table: first-contact (arrival) time, the theory's transient
# (eqs 8, 12, 19 from the measured push) and how often a domino hit the next one.
events = run.events.table()
print(" n   t_arr [ms]  t_theory [ms]  hits on n+1")
for k in range(params.n_dominoes):
    print(
        f"{k:2d}  {1e3 * run.arrival[k]:10.2f}  {1e3 * run.theory_arrival[k]:13.2f}"
        f"  {events['n_hits_on_next'][k]:11d}"
    )

# %%
# The wave speed. A 12-domino chain is often too short for the wave to settle
# (the local speed still changes at its end); then ``run.wave.settled`` is False and
# the speed is NaN: compare the arrival times with the theory's transient instead.
if run.wave.settled:
    print(f"steady speed: {run.wave.speed:.3f} ± {run.wave.speed_err:.2g} m/s")
else:  # the reason, read from the same arrival times
    print(f"steady speed: not settled: {unsettled_reason(run.arrival, run.positions)}")
print(f"theory, limit speed (eq 34): {run.theory_speed:.3f} m/s")

# %%
# Arrival times against the theory's transient.
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
n = np.arange(params.n_dominoes)
ax.plot(n, 1e3 * run.arrival, "o", label="DEM")
ax.plot(n, 1e3 * run.theory_arrival, "k--", label="theory transient")
ax.set(xlabel="domino n", ylabel="first-contact time [ms]")
ax.legend()

# %%
# One frame of the animation (``dominowave animate`` writes the whole movie from the
# same drawing code), half-way through the run; colour = angular velocity.
from dominowave.io.animation import render_frames  # noqa: E402
from dominowave.sweep.run_chain import chain_trajectory  # noqa: E402

traj = chain_trajectory(run.record, params.thickness / 2, params.height, params.thickness)
t_mid = 0.5 * float(run.arrival[-1])
image = next(render_frames(traj, np.array([t_mid]), width_px=800))
fig, ax = plt.subplots(figsize=(8, 8 * image.shape[0] / image.shape[1]))
ax.imshow(image)
ax.set_axis_off()
