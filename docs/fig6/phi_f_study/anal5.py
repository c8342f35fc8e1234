"""Summary of the friction-switch runs (switch07.pkl, switch08.pkl)."""
import pickle, numpy as np
for f in ("switch07.pkl", "switch08.pkl"):
    res = pickle.load(open(f, "rb"))
    print(f)
    for m, r in res.items():
        j = r["trigger"]; v = r["variants"]
        ref_after = [k for k in v["ref"]["back"] if k > j + 3]
        line = f"  member {m:2d} trigger {j:2d}: ref backward after j+3: {len(ref_after):2d}"
        for name in ("at hit on striker j-1", "1 ms before hit on j", "after j+3 hit"):
            if name not in v: continue
            x = v[name]; a = x["arrival"]
            nreach = int(np.isfinite(a).sum())
            line += f" | {name}: j back {int(j in x['back'])}, backward after j+3 {len([k for k in x['back'] if k > j+3])}, touched {nreach}/30, in order {x['reached']}"
        print(line)
