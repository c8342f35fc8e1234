"""Causal test: run a stalling phi_f = 0.3 member and switch the floor/base friction to
phi_new at a chosen time (materials and the per-contact mu of every contact that had 0.3).
Usage: python switch.py OUT.pkl d/l members(comma) phi_new"""
import sys, pickle, math
import numpy as np
from dominowave.chain.build import ChainParams
from dominowave.chain.scenario import DominoChain

out, d = sys.argv[1], float(sys.argv[2])
members = [int(x) for x in sys.argv[3].split(",")]
phi_new = float(sys.argv[4])
OLD = 0.3
chain = DominoChain(ChainParams(n_dominoes=30, d_over_l=d, friction_floor=OLD))
vs = math.sqrt(chain.params.g * chain.params.height)
base = chain.resolve(None)

def back(e, j):
    return e["mechanism"][j] == 3 and math.radians(60) < e["max_backward"][j] < math.radians(150)

def summary(run):
    e = run.events.table()
    nb = [j for j in range(1, 30) if back(e, j)]
    return dict(speed=run.wave.speed / vs, reached=run.wave.reached, back=nb,
                arrival=run.arrival.copy(), slip=e["slip_final"].copy(), mech=e["mechanism"].copy())

def run_switch(push, t_switch):
    st = chain.stepper(push)
    if t_switch is not None:
        st.advance(int(round(t_switch / st.sim.dt)))
        mats, con = st.sim.mats, st.sim.contacts
        mats.friction[np.isclose(mats.friction, OLD)] = phi_new
        con.mu[np.isclose(con.mu, OLD)] = phi_new
    st.advance(np.iinfo(np.int64).max)
    return summary(st.result())

res = {}
for m in members:
    push = base.scaled(1.0 + 1e-3 * np.random.default_rng([0, m]).standard_normal())
    ref = run_switch(push, None)
    if not ref["back"]:
        print(f"member {m}: no backward fall (speed {ref['speed']:.2f})"); continue
    j = ref["back"][0]
    a = ref["arrival"]
    variants = {"ref": ref}
    for name, t in [("at hit on striker j-1", a[j - 1] - 1e-3),
                    ("1 ms before hit on j", a[j] - 1e-3),
                    ("after j+3 hit", a[j + 3] + 1e-3 if j + 3 < 30 and np.isfinite(a[j + 3]) else None)]:
        if t is None:
            continue
        variants[name] = run_switch(push, t)
    res[m] = dict(trigger=j, variants=variants)
    print(f"member {m}: trigger domino {j} (first backward fall), ref speed {ref['speed']:.2f}, "
          f"backward {ref['back'][:12]}", flush=True)
    for name, v in variants.items():
        if name == "ref": continue
        print(f"   switch to {phi_new} {name:24s}: domino {j} falls back: {j in v['back']}; "
              f"n backward {len(v['back'])} (ref {len(ref['back'])}); speed {v['speed']:.2f}; reached {v['reached']}", flush=True)
    with open(out, "wb") as fh:
        pickle.dump(res, fh)
