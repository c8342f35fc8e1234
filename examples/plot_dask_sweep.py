"""
A resumable sweep on Dask, collected into xarray
================================================

A study is a base scenario plus a grid of swept fields. ``run_sweep`` runs its points
on a Dask cluster and stores each point's result folder as soon as it finishes, keyed
by a hash of its configuration: re-running the same study runs only the points not
yet stored, so a crash or Ctrl-C loses nothing. ``collect`` gathers the stored points
into one ``xarray.Dataset`` on the swept grid.

The points here are the closed-form theory (milliseconds each) on a Dask cluster of
one worker thread in this process, so the example shows the machinery in a few seconds
(``dominowave sweep`` starts a LocalCluster of worker processes, or joins the cluster
at ``--scheduler``).
"""

# %%
import shutil
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
from distributed import Client

from dominowave.io.config import parse_study
from dominowave.sweep.collect import collect
from dominowave.sweep.runner import run_sweep

study = parse_study(
    {
        "scenario": {"kind": "theory", "height": 1.0, "mass": 1.0, "n_dominoes": 20},
        "sweep": {"grid": {"d_over_l": [0.1, 0.2, 0.4, 0.6, 0.8], "stiffness_ratio": [1e2, 1e4]}},
    }
)
out = Path(tempfile.mkdtemp()) / "sweep"


# %%
# One client for both runs; leaving the ``with`` block shuts the cluster down.
def counts(report) -> str:
    return f"{report.total} points: {report.skipped} already stored, {report.ran} run now"


# (threads in this process: a script that starts worker processes must guard its code
# with ``if __name__ == "__main__":``, which a gallery page would hide)
with Client(processes=False, n_workers=1, threads_per_worker=1, dashboard_address=":0") as client:
    print(counts(run_sweep(study, out, client=client, quiet=True)))
    # a crash that lost one point: remove its folder, run the same study again
    lost = sorted((out / "points").iterdir())[0]
    shutil.rmtree(lost)
    print(counts(run_sweep(study, out, client=client, quiet=True)))

# %%
# The stored points as one dataset: every summary value (SI units) on the
# (d_over_l, stiffness_ratio) grid.
ds = collect(out)
print(ds["speed"])

# %%
fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
for ratio in ds["stiffness_ratio"].values:
    ds["speed"].sel(stiffness_ratio=ratio).plot(ax=ax, marker="o", label=f"k/k* = {ratio:g}")
ax.set(xlabel="spacing d / l", ylabel="speed [m/s]", title="")
ax.legend()
shutil.rmtree(out.parent)
