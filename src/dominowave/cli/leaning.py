"""Command ``dominowave leaning``: the leaning-train theory of real dominoes, in SI units.

One row per (gap, friction) pair of :func:`dominowave.theory.leaning.steady_state`:
the steady front speed, the front's angular velocity after each collision, the period and
the energy budget of one domino. Where no steady train runs the row says why.
"""

from __future__ import annotations

import math
from typing import Annotated

import numpy as np
import typer

from dominowave.checks import check_memory
from dominowave.cli import tables
from dominowave.cli.theory import parse_values
from dominowave.units import G_STANDARD

__all__ = ["leaning_table", "register"]

COLUMNS = (
    ("gap", "gap[m]"),
    ("pitch", "pitch[m]"),
    ("d_over_l", "d/l"),
    ("friction", "mu"),
    ("speed", "v[m/s]"),
    ("speed_scaled", "v/sqrt(gl)"),
    ("omega_after", "omega+[rad/s]"),
    ("period", "T[s]"),
    ("released", "E_rel[mJ]"),
    ("collision_loss", "E_coll[mJ]"),
    ("friction_loss", "E_fric[mJ]"),
    ("note", "note"),
)
BYTES_PER_ROW = 2000
"""One row: a dict of about 12 values and its formatted line [bytes]."""


def leaning_table(height, thickness, mass, gaps, frictions, g=G_STANDARD) -> list[dict]:
    """Rows over ``gaps`` [m] first, then ``frictions``; energies per domino [mJ]."""
    from dominowave.theory import leaning  # (scipy.fft: not at every command's start)

    gaps, frictions = np.atleast_1d(gaps), np.atleast_1d(frictions)
    st = leaning.steady_state(height, thickness, gaps[:, None], frictions[None, :], g)
    rows = []
    for i, j in np.ndindex(st.speed.shape):
        gap, mu = float(gaps[i]), float(frictions[j])
        rows.append(
            {
                "gap": gap,
                "pitch": gap + thickness,
                "d_over_l": gap / height,
                "friction": mu,
                "speed": float(st.speed[i, j]),
                "speed_scaled": float(st.speed[i, j]) / math.sqrt(g * height),
                "omega_after": float(st.omega_after[i, j]),
                "period": float(st.period[i, j]),
                "released": 1e3 * mass * float(st.released[i, j]),
                "collision_loss": 1e3 * mass * float(st.collision_loss[i, j]),
                "friction_loss": 1e3 * mass * float(st.friction_loss[i, j]),
                "note": str(st.reason[i, j]) or "steady train",
            }
        )
    return rows


FORMATTERS = {
    "table": lambda rows, note: tables.as_table(rows, COLUMNS, note, free_last=True),
    "csv": lambda rows, _note: tables.as_csv(rows, COLUMNS, header="title"),
    "json": lambda rows, _note: tables.as_json(rows),
}


def leaning_cmd(
    gap: Annotated[
        str,
        typer.Option(help="Clear gap d [m] in (0, height): '0.00938', list or 'start:stop:count'."),
    ] = "0.00938,0.01509,0.025",
    friction: Annotated[
        str, typer.Option(help="Friction between dominoes (>= 0): list or range.")
    ] = "0,0.1,0.3,0.525",
    height: Annotated[float, typer.Option(help="Domino height l [m].")] = 0.048,
    thickness: Annotated[float, typer.Option(help="Domino thickness s [m].")] = 0.0075,
    mass: Annotated[float, typer.Option(help="Domino mass [kg] (energies only).")] = 0.008,
    g: Annotated[float, typer.Option(help="Gravity [m/s^2].")] = G_STANDARD,
    fmt: Annotated[str, typer.Option("--format", help="table, csv or json.")] = "table",
) -> None:
    """Steady speed of the leaning train (inelastic collisions, friction between dominoes).

    Defaults: the standard 48 x 24 x 7.5 mm, 8 g domino. Energies are per domino.
    """
    if fmt not in FORMATTERS:
        raise ValueError(f"format = {fmt!r} is not one of {', '.join(FORMATTERS)}")
    gaps, frictions = parse_values(gap, "gap"), parse_values(friction, "friction")
    if not mass > 0 or not math.isfinite(mass):
        raise ValueError(f"mass = {mass:.6g} is outside the valid range (0, inf)")
    check_memory(
        BYTES_PER_ROW * gaps.size * frictions.size,
        f"a table of {gaps.size * frictions.size} rows",
        f"gap ({gaps.size} values) x friction ({frictions.size} values)",
    )
    rows = leaning_table(height, thickness, mass, gaps, frictions, g)
    note = (
        f"# leaning train (Shaw 1978, van Leeuwen 2010): l = {height:.6g} m, s ="
        f" {thickness:.6g} m, m = {mass:.6g} kg, g = {g:.6g} m/s^2; rigid dominoes, perfectly"
        " inelastic collisions, no slip on the floor; energies per domino and period"
    )
    typer.echo(FORMATTERS[fmt](rows, note))


def register(app: typer.Typer) -> None:
    """Add ``leaning`` to the ``dominowave`` command line."""
    app.command("leaning")(leaning_cmd)
