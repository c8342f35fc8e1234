"""
Theory: the wave speed of Fig 4A
================================

The closed forms of the paper give the speed of a domino wave for thin dominoes as a
function of the collision angle ``beta = arcsin(d/l)``: the rigid
(Efthimiou-Johnson) limit, eq 14, and with a finite collision time, eq 20, for a
stiffness ``k`` given in units of ``k* = m g / l``. Everything here is dimensionless
(``l = g = m = 1``), so speeds are in ``sqrt(g l)``.
"""

# %%
# The theory is plain NumPy: every function takes arrays and returns arrays.
import matplotlib.pyplot as plt
import numpy as np

from dominowave import theory

beta = np.geomspace(1e-3, np.pi / 2 - 1e-3, 300)  # collision angle [rad]
l, g, m = 1.0, 1.0, 1.0  # height, gravity, mass: speeds come out in sqrt(g l)

v_rigid = theory.wave_speed_rigid(beta, l, g)  # eq 14, k -> infinity

# %%
# With a finite stiffness the collision takes the time ``T_c`` (eq 31) and the wave
# speed is ``v = d / (T + T_c / 2)`` (eq 20). That formula assumes that only one pair
# of dominoes is in contact at a time (``T > T_c / 2``); outside that pair regime the
# curve is drawn dotted.
fig, ax = plt.subplots(figsize=(6.4, 4.4), layout="constrained")
ax.plot(beta, v_rigid, color="k", lw=2, label=r"$k=\infty$ (eq 14)")
for ratio, colour in [(1e8, "C0"), (1e4, "C1"), (1.0, "C2")]:
    v = theory.wave_speed(beta, l, m, ratio, g)  # eq 20; k* = m g / l = 1
    pair = theory.pair_regime_holds(beta, l, m, ratio, g)
    ax.plot(beta, np.where(pair, v, np.nan), color=colour, label=f"k = {ratio:g} k*")
    ax.plot(beta, np.where(pair, np.nan, v), color=colour, ls=":")
ax.set(xscale="log", yscale="log", xlabel=r"$\beta$ [rad]", ylabel=r"$v/\sqrt{gl}$")
ax.legend()

# %%
# The numbers quoted in the README, at d/l = 0.4:
beta_04 = np.arcsin(0.4)
print(f"rigid limit (eq 14):  v = {theory.wave_speed_rigid(beta_04, l, g):.4g} sqrt(gl)")
print(f"k = 1e4 k* (eq 20):   v = {theory.wave_speed(beta_04, l, m, 1e4, g):.4g} sqrt(gl)")
