"""
Real dominoes: the leaning train
================================

Real dominoes do not bounce off each other: each one keeps leaning on the domino it
struck, and the corner slides down that domino's face against friction. The leaning
train (Shaw 1978, van Leeuwen 2010; ``dominowave.theory.leaning``) is that model for
rigid dominoes: perfectly inelastic collisions, Coulomb friction ``mu`` between the
dominoes, no slip on the floor. Its steady speed takes milliseconds. Here: the standard
48 x 7.5 mm domino.
"""

# %%
# The steady speed against the friction between the dominoes, at the 9.38 mm gap of
# the high-speed films; every function broadcasts its arguments.
import matplotlib.pyplot as plt
import numpy as np

from dominowave.chain.reconcile import compare_with_measurements, leaning_friction_for_speed
from dominowave.theory import leaning

l, s, gap = 0.048, 0.0075, 0.00938  # height, thickness, clear gap [m]
friction = np.linspace(0.0, 0.75, 31)
speed = leaning.limit_speed(height=l, thickness=s, gap=gap, friction=friction)
films = {floor: compare_with_measurements(gap, floor) for floor in ("hardwood", "felt")}

fig, ax = plt.subplots(figsize=(6.4, 4.2), layout="constrained")
ax.plot(friction, speed, color="k", label="leaning train, 9.38 mm")
for (floor, f), colour in zip(films.items(), ("tab:brown", "tab:purple"), strict=True):
    ax.axhspan(f.mean - f.spread, f.mean + f.spread, color=colour, alpha=0.3)
    ax.axhline(f.mean, color=colour, label=f"films on {floor} (mean ± sd)")
ax.axvspan(0.2, 0.75, color="grey", alpha=0.1, label="handbook range of the plastic")
ax.set(xlabel=r"friction between dominoes $\mu$", ylabel="front speed [m/s]")
ax.legend(fontsize=8)

# %%
# The friction at which the train meets the films: inferred from the measurement, far
# below the handbook's 0.2-0.75 for polystyrene and ABS (the real-domino page of the
# user guide discusses what that can and cannot mean).
for floor, f in films.items():
    mu, _ = leaning_friction_for_speed(f.mean, height=l, thickness=s, gap=gap)
    print(f"{floor}: films {f.mean:.3f} m/s -> leaning train at friction {mu:.3f}")

# %%
# Where the energy goes: per domino the train releases the height a fallen domino lost;
# the collision and the friction dissipate it (to round-off in the steady state).
mus = np.array([0.0, 0.3, 0.525])
st = leaning.steady_state(l, s, gap, friction=mus)
mass = 0.008  # [kg]
budget = zip(mus, st.released, st.collision_loss, st.friction_loss, strict=True)
for mu, e, c, fr in budget:
    print(
        f"mu = {mu:5.3f}: released {1e3 * mass * e:.3f} mJ = collision"
        f" {1e3 * mass * c:.3f} + friction {1e3 * mass * fr:.3f} mJ"
    )

# %%
# From a push to the steady wave: the struck domino's angular velocity after each
# collision settles within about ten dominoes, whatever the push.
fig, ax = plt.subplots(figsize=(6.4, 4.0), layout="constrained")
for omega0, style in [(8.0, ":"), (np.sqrt(9.81 / l), "-"), (40.0, "--")]:
    tr = leaning.transient(l, s, gap, 0.3, n_dominoes=25, omega0=omega0)
    ax.plot(np.arange(1, 25), tr.omega_after, "k" + style, label=f"push {omega0:.3g} rad/s")
ax.axhline(leaning.steady_state(l, s, gap, 0.3).omega_after, color="tab:green", lw=0.8)
ax.set(xlabel="struck domino", ylabel=r"$\omega$ after its collision [rad/s]")
ax.set_title(r"$\mu$ = 0.3; green: the steady state")
ax.legend(fontsize=8)
plt.show()
