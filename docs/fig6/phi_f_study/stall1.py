import pickle, numpy as np
np.set_printoptions(linewidth=250, precision=2, suppress=True)
res = pickle.load(open("ens_main.pkl", "rb"))
for key, ms in [((0.3, 0.7), [0, 5, 1]), ((0.6, 0.7), [0, 5])]:
    for m in ms:
        r = res[key][m]; e = r["ev"]
        print(f"== phi={key[0]} d/l={key[1]} member {m} speed {r['speed']:.2f} first {r['first']} last {r['last']} reached {r['reached']}")
        print("local  ", r["local"])
        print("arriv ms", r["arrival"]*1e3)
        print("slipfin cm", e["slip_final"]*100)
        print("slipmax cm", e["slip_max"]*100)
        print("mech     ", e["mechanism"])
        print("hits_prev", e["n_hits_from_prev"])
        print("inpass   ", e["n_hits_in_passage"])
        print("two_ahead", e["touched_two_ahead"].astype(int))
        print("maxback deg", np.degrees(e["max_backward"]))
        print("rebound deg", np.degrees(e["rebound_angle"]))
        print("topple ms", (e["topple_time"]-e["arrival"])*1e3)
