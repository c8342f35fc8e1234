"""
An ensemble: wave speed with its uncertainty
============================================

One DEM run's speed depends on chaotic details of its many small collisions, so the
quantity to quote is the mean over an ensemble of runs whose pushes differ by a tiny
random factor (``jitter``, relative), with its standard error. Members whose wave
did not settle within the chain are named and left out of the mean, never hidden.
"""

# %%
import matplotlib.pyplot as plt
import numpy as np

from dominowave.chain import ChainParams, DominoChain

params = ChainParams(n_dominoes=20, d_over_l=0.5, damping=0.02)
chain = DominoChain(params)
ens = chain.ensemble(None, members=4, seed=0, jitter=1e-3)  # None: the default push

# %%
# ``ens.speed`` holds the mean, standard deviation and standard error over the
# members that settled, and the number of those that did not.
s = ens.speed
print(f"ensemble speed: {s.mean:.3f} ± {s.stderr:.2g} m/s (standard error, {s.n} members)")
if s.n_failed:
    print(f"{s.n_failed} member(s) did not settle within {params.n_dominoes} dominoes")
print(f"theory, limit speed (eq 34): {ens.theory_speed:.3f} m/s")

# %%
# The sphere-clump domino is not the theory's point mass on a massless rod, and a
# 20-domino chain is compared with a limit for an infinite one: the guide to domino
# chains says how far the two differ over the Fig 6 parameters, and why.

# %%
# Each member's local speed along the chain: solid where the member settled (its
# speed is in the mean), dashed where it did not.
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
for i, run in enumerate(ens.runs):
    v = np.diff(run.positions) / np.diff(run.arrival)
    style = "-" if run.wave.settled else "--"
    state = f"{run.wave.speed:.3f} m/s" if run.wave.settled else "not settled"
    ax.plot(np.arange(1, v.size + 1), v, style, color=f"C{i}", label=f"member {i}: {state}")
ax.axhline(ens.theory_speed, color="k", lw=0.8, label="theory limit, eq 34")
ax.set(xlabel="domino n", ylabel="local speed [m/s]")
ax.legend(fontsize=8)
