"""Commands ``dominowave theory`` (table of the analytic theory) and ``dominowave figures``.

All numbers are dimensionless (``l = g = m = 1``): angular velocities in ``sqrt(g/l)``,
times in ``sqrt(l/g)``, speeds in ``sqrt(g l)``, the stiffness as ``k / k*`` with
``k* = m g / l``. Bad input raises ``ValueError`` (one line, exit code 2).
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from dominowave import theory as th
from dominowave.checks import check_in_range, check_memory, check_nonnegative, check_positive
from dominowave.cli import tables
from dominowave.io.atomic import ensure_writable_dir
from dominowave.units import beta_from_spacing

__all__ = ["register", "theory_table"]

COLUMNS = (
    ("d_over_l", "d/l"),
    ("k_ratio", "k/k*"),
    ("beta", "beta[rad]"),
    ("omega", "Omega"),
    ("fall_time", "T"),
    ("collision_time", "T_c"),
    ("v", "v"),
    ("v_s", "v^s"),
    ("v_w", "v_w"),
    ("v_w_s", "v_w^s"),
    ("fm_over_mg", "F_m/mg"),
    ("regime", "regime"),
    ("pair_regime", "pair(T>T_c/2)"),
)


BYTES_PER_ROW = 2000
"""One row of the table: a dict of about 15 numbers and its formatted line [bytes]."""


def parse_values(text: str, name: str, geometric: bool = False) -> np.ndarray:
    """Parse ``"0.1,0.4"`` (a list) or ``"start:stop:count"`` (a range) into floats.

    Ranges are linear, or geometric when ``geometric`` (used for ``k/k*``); the ends of
    a geometric range must be in (0, inf), else a range error naming ``name``.
    """
    try:
        if ":" in text:
            start, stop, count = text.split(":")
            start, stop, count = float(start), float(stop), int(count)
            if count < 1:
                raise ValueError
        else:
            return np.array([float(part) for part in text.split(",")])
    except ValueError:
        raise ValueError(
            f"{name} = {text!r} is not a list 'a,b,c' or a range 'start:stop:count' of numbers"
        ) from None
    if geometric:  # outside the try: the range error must not become a parse error
        check_in_range(name, [start, stop], 0.0, np.inf)
        return np.geomspace(start, stop, count)
    return np.linspace(start, stop, count)


def theory_table(d_over_l, k_ratio, s_over_l, mu, convention="paper") -> list[dict]:
    """One row per (d/l, k/k*) pair: every quantity of section 2, dimensionless.

    ``d_over_l`` and ``k_ratio`` are scalars or 1-D sequences; rows run over ``d/l``
    first, then ``k/k*``.
    """
    d_over_l, k_ratio = np.atleast_1d(d_over_l), np.atleast_1d(k_ratio)
    beta = beta_from_spacing(d_over_l)  # validated on the 1-D input, before the grid
    beta_grid, k_grid = np.meshgrid(beta, k_ratio, indexing="ij")
    d_grid = np.broadcast_to(np.asarray(d_over_l, dtype=float)[:, None], beta_grid.shape)
    one = 1.0  # l = g = m = 1, so k* = 1 and k = k/k*
    s = s_over_l * one
    fm = th.peak_contact_force(beta_grid, one, one, k_grid, one, convention)
    columns = {
        "d_over_l": d_grid,
        "k_ratio": k_grid,
        "beta": beta_grid,
        "omega": th.omega_limit(beta_grid, one, one),
        "fall_time": th.fall_time_limit(beta_grid, one, one),
        "collision_time": th.collision_time(k_grid, one, beta_grid, convention),
        "v": th.wave_speed(beta_grid, one, one, k_grid, one, convention),
        "v_s": th.wave_speed_thick(beta_grid, one, one, k_grid, s, one, convention),
        "v_w": th.p_wave_speed(beta_grid, one, one, k_grid, convention),
        "v_w_s": th.p_wave_speed_thick(beta_grid, one, one, k_grid, s, convention),
        "fm_over_mg": fm,
        "regime": th.classify_regime(beta_grid, fm, mu, s_over_l).name,
        "pair_regime": th.pair_regime_holds(beta_grid, one, one, k_grid, one, convention),
    }
    rows = []
    for index in np.ndindex(beta_grid.shape):
        row = {}
        for key, values in columns.items():
            value = values[index]
            if isinstance(value, np.bool_):
                value = bool(value)
            elif isinstance(value, np.floating):
                value = float(value)
            row[key] = value
        rows.append(row)
    return rows


NOTE = (
    "# dimensionless (l = g = m = 1): Omega in sqrt(g/l); T, T_c in sqrt(l/g); speeds in "
    "sqrt(g l); k per particle (k_r = k/2) unless --convention contact"
)
FORMATTERS = {
    "table": lambda rows: tables.as_table(rows, COLUMNS, NOTE),
    "csv": lambda rows: tables.as_csv(rows, COLUMNS),
    "json": tables.as_json,
}


def theory_cmd(
    d_over_l: Annotated[
        str,
        typer.Option("--d-over-l", help="Spacing d/l in (0, 1): '0.4', '0.1,0.4' or '0.1:0.9:9'."),
    ] = "0.1,0.4,0.8",
    stiffness_ratio: Annotated[
        str,
        typer.Option(
            "--stiffness-ratio",
            help="Stiffness k/k* in (0, inf] ('inf' = rigid): list, or geometric range '1:1e8:9'.",
        ),
    ] = "inf,1e8,1e4",
    s_over_l: Annotated[float, typer.Option("--s-over-l", help="Thickness s/l in [0, 1).")] = 0.1,
    friction_floor: Annotated[
        float, typer.Option(help="Friction coefficient with the floor, >= 0.")
    ] = 0.3,
    convention: Annotated[
        str, typer.Option(help="'paper': k per particle, k_r = k/2; 'contact': k_r = k (YADE).")
    ] = "paper",
    fmt: Annotated[str, typer.Option("--format", help="table, csv or json.")] = "table",
) -> None:
    """Print beta, Omega, T, T_c, v, v^s, v_w, F_m/mg, regime and pair-regime validity."""
    if fmt not in FORMATTERS:
        raise ValueError(f"format = {fmt!r} is not one of {', '.join(FORMATTERS)}")
    d_values = parse_values(d_over_l, "d_over_l")
    k_values = parse_values(stiffness_ratio, "stiffness_ratio", geometric=True)
    check_in_range("s_over_l", s_over_l, 0.0, 1.0, lo_inclusive=True)
    # validate before the (d/l, k/k*) grid is formed, so messages name the given values
    check_positive("stiffness_ratio", k_values)
    check_nonnegative("friction_floor", friction_floor)
    check_memory(
        BYTES_PER_ROW * d_values.size * k_values.size,
        f"a table of {d_values.size * k_values.size} rows",
        f"d_over_l ({d_values.size} values) x stiffness_ratio ({k_values.size} values)",
    )
    rows = theory_table(d_values, k_values, s_over_l, friction_floor, convention)
    typer.echo(FORMATTERS[fmt](rows))


def figures_cmd(
    out: Annotated[
        str, typer.Option("--out", help="Directory for the PNG and CSV files.")
    ] = "figures",
) -> None:
    """Write Fig 1D, 4A, 4B and 5B of the paper (PNG + CSV of the plotted data)."""
    ensure_writable_dir(Path(out))  # fail fast, before importing matplotlib
    from dominowave.plots.paper_theory import write_all  # matplotlib only when needed

    for path in write_all(out):
        typer.echo(str(path))


def register(app: typer.Typer) -> None:
    """Add ``theory`` and ``figures`` to the ``dominowave`` command line."""
    app.command("theory")(theory_cmd)
    app.command("figures")(figures_cmd)
