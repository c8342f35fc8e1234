"""Domino chain scenarios: build, push, record events, measure the wave (paper section 3)."""
