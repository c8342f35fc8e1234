"""A saved state as an older version of dominowave wrote it (dem.simulation.STATE_FORMAT).

:func:`older_state` takes a state of the current format and gives it the layout of an
older one: the keys that format lacked dropped, and those it had in another form written
back in that form.  The tests of the readers of older files build their inputs with it,
so each format is described once, here.
"""

from __future__ import annotations

import numpy as np

from dominowave.dem.material_pairs import RULE_GIVEN, RULE_PAPER

FORMAT_2_KEYS = (
    "state_format",
    "settings.planar",
    "planar_kernels",
    "mats.shear_kinematics",
    "mats.pair_friction",
    "mats.pair_restitution",
    "mats.poisson",
    "mats.hertz_damping",
)
"""The keys a format-1 state lacks (with :data:`FORMAT_3_KEYS`)."""
FORMAT_3_KEYS = ("settings.sleep_speed", "settings.sleep_time", "bodies.calm_since")
"""The keys a format-2 state lacks (and those of the rows of resting boxes,
``boxes.dormant.*``)."""
FORMAT_5_KEYS = ("contacts.point", "contacts.normal", "contacts.mult")
"""The keys a format-4 state lacks: the sphere contacts' points, normals and
multiplicities (their rows' fields, contact_rows.py)."""
FORMAT_6_KEYS = ("contacts.key",)
"""The key a format-5 state lacks: the sphere contacts' feature keys (state.Contacts);
it had their flag ``contacts.active`` instead (1 while the overlap is positive)."""
FORMAT_1_BOX_KEYS = (
    "boxes.held_at_build",
    "boxes.sphere_cand",
    "boxes.n_sphere_cand",
    "boxes.sphere_cand_start",
)
"""Box keys a format-1 state may lack."""


def older_state(state: dict, version: int) -> dict:
    """``state`` (current format) in the layout of format ``version`` (1 to 6):

    * 1 to 6: the box-sphere rows in a table of their own (:func:`_split_sphere_rows`);
    * 1 to 5: sphere contacts without :data:`FORMAT_6_KEYS`, with ``contacts.active``;
    * 1 to 4: sphere contacts without :data:`FORMAT_5_KEYS`;
    * 1 to 3: one column ``mats.stiffness`` holding E, or k_n under RULE_GIVEN, instead
      of ``mats.young`` and ``mats.kn``;
    * 1 and 2: no sleep settings, no rows of resting boxes;
    * 1: no version key, none of :data:`FORMAT_2_KEYS` and :data:`FORMAT_1_BOX_KEYS`,
      and materials giving k_n flagged by ``mats.given_kn`` beside the paper's rule.
    """
    old = _split_sphere_rows(state)
    if version == 6:
        old["state_format"] = np.array(version)
        return old
    old = {k: v for k, v in old.items() if k not in FORMAT_6_KEYS}
    old["contacts.active"] = (np.asarray(state["contacts.overlap"]) > 0.0).astype(np.uint8)
    old["state_format"] = np.array(version)
    if version == 5:
        return old
    old = {k: v for k, v in old.items() if k not in FORMAT_5_KEYS}
    if version == 4:
        return old
    young, kn = old.pop("mats.young"), old.pop("mats.kn")
    given = int(old["mats.rule"][0]) == RULE_GIVEN
    old["mats.stiffness"] = kn if given else young
    if version <= 2:
        old = {k: v for k, v in old.items() if k not in FORMAT_3_KEYS}
        old = {k: v for k, v in old.items() if not k.startswith("boxes.dormant.")}
    if version == 1:
        old = {k: v for k, v in old.items() if k not in FORMAT_2_KEYS + FORMAT_1_BOX_KEYS}
        if given:
            old["mats.rule"] = np.array([RULE_PAPER], np.int64)
            old["mats.given_kn"] = np.ones(1, np.uint8)
    return old


def _split_sphere_rows(state: dict) -> dict:
    """``state`` with the box rows whose partner is a sphere (``j >= n_boxes``, after the
    others) moved to ``boxes.sphere_rows.*``, their partner the sphere's index, as
    formats 1 to 6 kept them."""
    old = dict(state)
    if "boxes.body" not in state:
        return old
    n_boxes = np.asarray(state["boxes.body"]).size
    sphere = np.asarray(state["boxes.rows.j"]) >= n_boxes
    for key in [k for k in state if k.startswith("boxes.rows.") and k != "boxes.rows.n"]:
        value = np.asarray(state[key])
        old[key] = value[~sphere]
        spheres = value[sphere]
        old["boxes.sphere_rows." + key[len("boxes.rows.") :]] = (
            spheres - n_boxes if key == "boxes.rows.j" else spheres
        )
    n = np.asarray(state["boxes.rows.n"])
    old["boxes.rows.n"] = n - sphere.sum()
    old["boxes.sphere_rows.n"] = np.full_like(n, sphere.sum())
    return old
