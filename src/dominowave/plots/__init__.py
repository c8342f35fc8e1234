"""Figures of the paper and theory-vs-simulation overlays (PNG + CSV of the plotted data)."""
