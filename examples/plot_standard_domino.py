"""
Real dominoes: the standard preset and a small prediction
=========================================================

``standard_domino`` builds a chain of the common 48 x 24 x 7.5 mm toppling domino from
the material data the package ships (every value with its range and source), and
``predict`` runs a Saltelli design over those ranges: the front speed with the band the
material data allow and the Sobol' index of each value. Here a deliberately small and
soft version (2D, 8 dominoes, ``k/k* = 3e3`` instead of the plastic's stiffness, one
base sample: 8 chains) so that it runs in seconds; the user guide's page on real
dominoes gives the full-size numbers.
"""

# %%
# One chain of the preset at the 9.38 mm gap of the high-speed films, on felt.
import tempfile

import matplotlib.pyplot as plt
import numpy as np
from distributed import Client

from dominowave.chain import DominoChain, Push
from dominowave.chain.presets import standard_domino
from dominowave.chain.reconcile import reconcile_lines
from dominowave.sweep.predict import predict

cheap = {"n_dominoes": 8, "model": "2d", "stiffness_ratio": 3e3}
params = standard_domino(gap=0.00938, floor="felt", **cheap)
chain = DominoChain(params)
run = chain.run(Push(omega=np.sqrt(params.g / params.height)))
fit = chain.speed_from(run, 3)
print(f"front speed from domino 3 on: {fit.speed:.3f} ± {fit.speed_err:.2g} m/s")

# %%
# What it rests on: the films at this gap and floor, and the friction between the
# dominoes at which the leaning train and the box DEM would meet them (inferred). An
# 8-domino chain fitted from domino 3 is far from its steady speed: this comparison is
# the command line's, shown on a toy chain; the real-domino page has the long chains.
for line in reconcile_lines(
    fit.speed, gap=0.00938, floor="felt", friction=params.friction_dominoes
):
    print(line)

# %%
# The prediction over the material ranges (a resumable sweep: re-running the same
# call in the same folder runs nothing again).
with (
    tempfile.TemporaryDirectory() as folder,
    Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=":0") as client,
):  # one worker thread in this process (dominowave predict starts worker processes)
    pred = predict(0.00938, "felt", folder, 1, fit_from=3, client=client, **cheap)
lo, mid, hi = pred.band
print(f"DEM: median {mid:.3f} m/s, 90 % band [{lo:.3f}, {hi:.3f}] over {pred.speed.size} chains")
print(
    "leaning train over the same samples: median {1:.3f}, band [{0:.3f}, {2:.3f}]".format(
        *pred.leaning_band
    )
)
for name, effect in zip(pred.names, pred.effect, strict=True):
    print(f"  effect of {name:20s} over its range: {effect:+.3f} m/s")

# %%
# Each sample's speed against its friction between dominoes, the value that matters
# (the leaning train's is its steady speed, the toy chains' a short transient's).
j = pred.names.index("friction_dominoes")
fig, ax = plt.subplots(figsize=(6.0, 3.8), layout="constrained")
ax.plot(pred.samples[:, j], pred.speed, "o", label="DEM (8 dominoes, soft)")
ax.plot(pred.samples[:, j], pred.leaning_speed, "k^", label="leaning train")
ax.set(xlabel="friction between dominoes", ylabel="front speed [m/s]")
ax.legend()
plt.show()
