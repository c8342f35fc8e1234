"""Parameter sweeps on dask.distributed: cached by config hash, resumable, nothing lost.

Heavy libraries (dask, xarray) are imported inside the functions that use them.
"""
