"""
Rods vs theory at one point
===========================

The reduced model (``dominowave.rods``) simulates the paper's own hinged dominoes
with Newton's laws and compliant contacts; it tests the assumptions of the theory.
Here one point, d/l = 0.4 and k/k* = 1e4, with the paper's head-on contact, the
contact the theory's collision rule assumes. Dimensionless: ``l = g = 1``.
"""

# %%
from dominowave.chain import theory_vs_rods as tvr

c = tvr.compare_point(0.4, 1e4, n=30, normal="head-on", g=1.0)

# %%
# The first collision against the theory: its duration against eq 31, its peak
# force against eq 37, and the fraction of angular velocity passed on against f+ (eq 3).
print(f"collision time  / eq 31: {c.tc_first / c.tc_theory:.4f}")
print(f"peak force      / eq 37: {c.f_first / c.fm_theory:.4f}")
print(f"transfer Omega+/Omega_f: {c.transfer_first:.4f}   (f+ = {c.f_plus:.4f})")

# %%
# The wave speed: simulated (steady fit) against eq 20, in sqrt(g l). The
# simulation keeps gravity on during contacts, which the theory neglects.
if c.speed == c.speed:  # not NaN: the wave settled within the chain
    print(f"rods: v = {c.speed:.4f} ± {c.speed_err:.2g}   eq 20: {c.speed_theory:.4f}")
else:
    print(f"rods: not settled within {c.n} dominoes; eq 20: {c.speed_theory:.4f}")
print(f"status: {c.status}")

# %%
# The same four checks as ratios of simulation to theory: 1 where the theory's
# assumptions hold (head-on contact, a single pair in contact at a time).
import matplotlib.pyplot as plt  # noqa: E402

ratios = {
    "T_c / eq 31": c.tc_first / c.tc_theory,
    "F_m / eq 37": c.f_first / c.fm_theory,
    "transfer / f+": c.transfer_first / c.f_plus,
    "v / eq 20": c.speed / c.speed_theory,
}
fig, ax = plt.subplots(figsize=(6.0, 3.2), layout="constrained")
ax.bar(list(ratios), list(ratios.values()), color="tab:blue")
ax.axhline(1.0, color="k", lw=0.8)
ax.set(ylabel="rods / theory", ylim=(0.8, 1.2), title="d/l = 0.4, k/k* = 1e4, head-on")
plt.show()
