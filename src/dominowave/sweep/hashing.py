"""The key of a run: a hash of its full resolved config and the package version.

Two runs with the same key would produce the same result files, so a sweep
skips a point whose key is already stored. Changing any field -- or upgrading
the package -- gives a new key and a new run.
"""

from __future__ import annotations

import hashlib
import json

import dominowave

__all__ = ["KEY_LENGTH", "config_dict", "point_key"]

KEY_LENGTH = 16
"""Hex digits kept from the SHA-256 (64 bits: collisions are not a practical concern)."""


def config_dict(model) -> dict:
    """The resolved config of a scenario model as plain Python (every field present)."""
    return model.model_dump(mode="python")


def point_key(model) -> str:
    """Hex key of ``model``'s full resolved config and ``dominowave.__version__``.

    The JSON is canonical (sorted keys, ``repr`` floats, ``Infinity`` for inf), so
    the key is the same in every process and on every machine.
    """
    text = json.dumps(
        {"config": config_dict(model), "version": dominowave.__version__},
        sort_keys=True,
        separators=(",", ":"),
        allow_nan=True,
    )
    return hashlib.sha256(text.encode()).hexdigest()[:KEY_LENGTH]
