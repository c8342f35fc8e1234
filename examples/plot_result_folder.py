"""
Reading a result folder and its netCDF
======================================

``dominowave run study.toml --out DIR`` (or ``run_one`` from Python) writes one
folder per run: the resolved ``config.toml``, ``provenance.json`` (versions, git
commit, machine, wall time), ``summary.json`` (scalars, SI units), ``events.csv``
(one row per domino) and ``timeseries.nc`` (netCDF, read with xarray). This is how to
read them back in a notebook.
"""

# %%
# First make a folder to read: a 15-domino run of the rod model.
import json
import shutil
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import xarray as xr

from dominowave.io.config import parse_study
from dominowave.io.results import read_events, read_summary
from dominowave.sweep.runner import run_one

study = parse_study({"scenario": {"kind": "rods", "n_dominoes": 15, "d_over_l": 0.4}})
folder = Path(tempfile.mkdtemp()) / "run"
print(run_one(study, folder))
print(sorted(p.name for p in folder.iterdir()))

# %%
# The summary: scalar results in SI units. A speed that did not settle is NaN here
# (``null`` in the JSON file), and ``speed_note`` says why (this rod chain has the
# face-normal contact without damping: its wave keeps accelerating).
summary = read_summary(folder)
for name in ("d_over_l", "stiffness_over_kstar", "dominoes_toppled"):
    print(f"{name:22s} {summary[name]}")
speed = summary["speed"]
if speed == speed:  # not NaN
    print(f"{'speed':22s} {speed:.4g} m/s")
else:
    print(f"{'speed':22s} not settled: {summary['speed_note']}")
provenance = json.loads((folder / "provenance.json").read_text())
print("package version", provenance.get("version"), "commit", provenance.get("git_commit"))

# %%
# Per-domino events: a dict of NumPy arrays, one entry per column of events.csv.
events = read_events(folder)
print(list(events))

# %%
# The time series: an xarray Dataset (here the rod model's energies).
with xr.open_dataset(folder / "timeseries.nc") as ts:
    print(ts)
    fig, ax = plt.subplots(figsize=(6.4, 3.6), layout="constrained")
    for name in list(ts.data_vars)[:4]:
        ts[name].plot(ax=ax, label=name)
    ax.set(title="")
    ax.legend(fontsize=8)
shutil.rmtree(folder.parent)
