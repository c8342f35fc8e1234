"""Speed against pitch for the standard domino: the data of docs/real_dominoes.md, section 8.

For the standard 48 x 24 x 7.5 mm domino (``dominowave.chain.presets.standard_domino``) on
one named floor, at several clear gaps ``d``, every model measured the same way -- the
front speed fitted from domino ``fit_from`` to the last of ``n`` dominoes on the nominal
positions ``x_n = n (d + s)`` (pitch-based, as a camera study reports it;
``dominowave.chain.wave.speed_from``), domino 0 pushed with ``omega = sqrt(g/l)``:

* ``band``: ``dominowave.sweep.predict.predict`` (Saltelli design over the material
  ranges, ``samples (D + 2)`` chains): the 5 %, 50 %, 95 % quantiles and the mean;
* ``dem3d``, ``dem2d``: the DEM box chain (3D; 2D, one column) at the nominal values of
  ``materials.toml``;
* ``dem3d_long`` (part ``long``): the 3D chain at the nominal values with ``--long-n``
  dominoes, fitted from domino 10 on as the films of long rows in the measurements are
  (``--long-gaps``);
* ``rods``: the hinged compliant-rod model (``dominowave.rods``) with the box's mass,
  inertia (a uniform block about its front bottom edge), its pair spring, the domino-
  domino friction, a dashpot of the domino-domino restitution and the floor restitution;
* ``rods_ideal``: the same rods with the theory's assumptions (no friction between
  dominoes, elastic contacts): where the rods part from the theory and why;
* ``transient``: the theory's transient for the same push (eqs 8, 12, 19; box mapping of
  ``dominowave.chain.compare``, with the box's collision time) fitted over the same
  dominoes;
* every DEM chain at the plastic's contact stiffness (``fidelity = "exact"``,
  ``chain.fidelity``), as section 8 was measured, unless ``--stiffness-ratio`` replaces it;
* ``eq34_rigid``, ``eq34_tc``: the limit speed eq 34 (box mapping) in the rigid limit and
  with the box's collision time, at the gaps and on a fine grid (``*_theory.csv``).

Every chain is a point of the sweep engine (``--runs``, default ``speed_vs_pitch_runs``
in the current folder, not committed): a re-run resumes where a killed one stopped. One
process, no pool (the machine is shared). The measurements of
``chain/data/measurements.csv`` are compared with the band by
``dominowave.plots.real_dominoes.compare_measurements`` (``--report``).

    S=docs/real_dominoes/speed_vs_pitch.py
    nice -n 15 python $S --floor hardwood --samples 1 --n 12 --fit-from 3
    python $S --report --update-doc  # CSVs -> figure, tables (into docs/real_dominoes.md)
    python $S --quick --out quick --runs quick/runs  # a cheap check of the pipeline

Output (``--out``, default next to this script): ``speed_vs_pitch_band.csv``,
``speed_vs_pitch_models.csv``, ``speed_vs_pitch_theory.csv``, ``speed_vs_pitch.png`` and
``speed_vs_pitch_measurements.csv``.
"""

from __future__ import annotations

import argparse
import csv
import math
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).parent
GAPS_MM = (9.38, 18.0, 30.0, 5.0, 12.0, 24.0)
"""Clear gaps d [mm] in the order they are run (d/l = 0.10 .. 0.63): the spread first."""
BAND_COLUMNS = ("gap_m", "pitch_m", "d_over_l", "q05_m_s", "q50_m_s", "q95_m_s", "mean_m_s")
BAND_COLUMNS += ("runs", "waves_died", "runs_failed", "floor", "n_dominoes", "fit_from")
MODEL_COLUMNS = ("model", "gap_m", "pitch_m", "d_over_l", "speed_m_s", "speed_err_m_s")
MODEL_COLUMNS += ("toppled", "n_dominoes", "fit_from", "note")
THEORY_COLUMNS = ("gap_m", "pitch_m", "d_over_l", "eq34_rigid_m_s", "eq34_tc_m_s")


def _params(gap, floor, n, **overrides):
    from dominowave.chain.presets import standard_domino

    return standard_domino(gap=gap, floor=floor, n_dominoes=n, **overrides)


def push_omega(p) -> float:
    """The push of domino 0 [rad/s]: ``sqrt(g / l)``, ``DominoChain``'s default."""
    return math.sqrt(p.g / p.height)


def theory_rows(gap, floor, n, fit_from, stiffness_ratio=None) -> list[dict]:
    """eq 34 (rigid, with T_c) and the transient fitted over the chain's dominoes."""
    from dominowave.chain.build import chain_positions
    from dominowave.chain.compare import theory_first_contacts, theory_speed
    from dominowave.chain.wave import speed_from

    extra = {} if stiffness_ratio is None else {"stiffness_ratio": stiffness_ratio}
    p = _params(gap, floor, n, **extra)
    t = theory_first_contacts(p, push_omega(p), "clump")
    fit = speed_from(t, chain_positions(p), fit_from)
    common = {"gap_m": gap, "pitch_m": p.pitch, "d_over_l": p.d_over_l}
    common |= {"n_dominoes": n, "fit_from": fit_from, "toppled": n}
    return [
        common
        | {"model": "transient", "speed_m_s": fit.speed, "speed_err_m_s": fit.speed_err}
        | {"note": "eqs 8, 12, 19 with T_c, box mapping, push sqrt(g/l)"},
        common
        | {"model": "eq34_rigid", "speed_m_s": theory_speed(p, "clump", rigid=True)}
        | {"speed_err_m_s": 0.0, "note": "limit, T_c = 0, box mapping"},
        common
        | {"model": "eq34_tc", "speed_m_s": theory_speed(p, "clump")}
        | {"speed_err_m_s": 0.0, "note": "limit with the box's T_c (eq 31), box mapping"},
    ]


def theory_curve(floor, gaps) -> list[dict]:
    """eq 34 (rigid and with T_c, box mapping) at the gaps ``gaps`` [m]."""
    from dominowave.chain.compare import theory_speed

    rows = []
    for gap in gaps:
        p = _params(float(gap), floor, 3)
        rows.append(
            {
                "gap_m": float(gap),
                "pitch_m": p.pitch,
                "d_over_l": p.d_over_l,
                "eq34_rigid_m_s": theory_speed(p, "clump", rigid=True),
                "eq34_tc_m_s": theory_speed(p, "clump"),
            }
        )
    return rows


def restitution_damping_ratio(e: float | None) -> float:
    """Dashpot ratio ``zeta`` of a linear contact with restitution ``e`` (None: elastic),
    the DEM's rule ``e = exp(-zeta pi / sqrt(1 - zeta^2))``: ``c = 2 zeta sqrt(m k)``
    of ``dem.laws.linear.viscous_coefficient`` at ``m = k = 1``."""
    from dominowave.dem.laws.linear import viscous_coefficient

    return 0.0 if e is None else float(viscous_coefficient(e, 1.0, 1.0)) / 2.0


def rod_chain(p, ideal: bool = False):
    """The rod model of the box chain ``p`` (``ChainParams``): see the module docstring.
    ``ideal``: the theory's assumptions instead, no friction between dominoes and elastic
    contacts (the floor restitution stays)."""
    from dominowave.rods import RodChain, block

    e_dd, e_floor = p.restitution_pairs
    if ideal:
        e_dd = None
    return RodChain(
        n=p.n_dominoes,
        l=p.height,
        d=p.d_over_l * p.height,
        s=p.thickness,
        mass=block(p.mass, p.height, p.thickness),
        k=p.pair_stiffness,
        damping_ratio=restitution_damping_ratio(e_dd),
        mu=0.0 if ideal else p.friction_dominoes,
        floor_restitution=0.0 if e_floor is None else e_floor,
        g=p.g,
    )


def rod_row(gap, floor, n, fit_from, stiffness_ratio=None, ideal=False) -> dict:
    """The rod model's front speed, measured like the DEM chains (``ideal``: model
    ``rods_ideal``, frictionless and elastic, :func:`rod_chain`)."""
    from dominowave.chain.wave import speed_from
    from dominowave.rods import simulate

    extra = {} if stiffness_ratio is None else {"stiffness_ratio": stiffness_ratio}
    p = _params(gap, floor, n, **extra)
    run = simulate(rod_chain(p, ideal), push_omega(p))
    fit = speed_from(run.arrival, run.positions, fit_from)
    reached = int(np.sum(np.isfinite(run.arrival)))
    ok = reached == n
    return {
        "model": "rods_ideal" if ideal else "rods",
        "gap_m": gap,
        "pitch_m": p.pitch,
        "d_over_l": p.d_over_l,
        "speed_m_s": fit.speed if ok else math.nan,
        "speed_err_m_s": fit.speed_err if ok else math.nan,
        "toppled": reached,
        "n_dominoes": n,
        "fit_from": fit_from,
        "note": f"hinged rods, block inertia{', mu = 0, elastic' if ideal else ''}, {run.status}",
    }


def _fidelity(stiffness_ratio):
    """The plastic's own contact (``fidelity = "exact"``, as section 8 was measured),
    unless a stiffness ratio replaces the modulus."""
    return "exact" if stiffness_ratio is None else None


def nominal_points(gaps, floor, n, fit_from, models, stiffness_ratio=None):
    """``PredictSample`` points at the nominal material values, one per (model, gap)."""
    from dominowave.chain.presets import standard_entries
    from dominowave.sweep.predict import PredictSample

    nominal = {name: e.value for name, e in standard_entries(floor).items()}
    points = []
    for model in models:
        for gap in gaps:
            points.append(
                PredictSample(
                    sample=len(points),
                    gap=gap,
                    floor=floor,
                    n_dominoes=n,
                    fit_from=fit_from,
                    model=model,
                    stiffness_ratio=stiffness_ratio,
                    fidelity=_fidelity(stiffness_ratio),
                    **nominal,
                )
            )
    return points


def dem_rows(points, runs: Path, suffix: str = "", folder: str = "nominal") -> list[dict]:
    """Run (or resume) the nominal DEM chains on the sweep engine in ``runs / folder``;
    one row each, model ``dem<model><suffix>``."""
    from dominowave.sweep.presets import run_preset

    done = run_preset(points, runs / folder, workers=1)  # one study per folder
    rows = []
    for point, summary in zip(points, done.summaries, strict=True):
        p = point.params()
        failed = summary is None
        rows.append(
            {
                "model": f"dem{point.model}{suffix}",
                "gap_m": point.gap,
                "pitch_m": p.pitch,
                "d_over_l": p.d_over_l,
                "speed_m_s": math.nan if failed else float(summary["speed"]),
                "speed_err_m_s": math.nan if failed else float(summary["speed_err"]),
                "toppled": -1 if failed else int(summary["dominoes_toppled"]),
                "n_dominoes": point.n_dominoes,
                "fit_from": point.fit_from,
                "note": "run failed (failure.json)" if failed else "box, nominal values",
            }
        )
    return rows


def band_row(gap, floor, n, fit_from, samples, runs: Path, **options) -> dict:
    """Run (or resume) the prediction at ``gap``; its band as one row."""
    from dominowave.sweep.predict import predict

    pred = predict(
        gap,
        floor,
        runs / f"band_{1e3 * gap:g}mm",
        samples,
        n_dominoes=n,
        fit_from=fit_from,
        workers=1,
        **options,
    )
    p = _params(gap, floor, n)
    lo, mid, hi = pred.band
    return {
        "gap_m": gap,
        "pitch_m": p.pitch,
        "d_over_l": p.d_over_l,
        "q05_m_s": lo,
        "q50_m_s": mid,
        "q95_m_s": hi,
        "mean_m_s": pred.mean,
        "runs": int(pred.speed.size),
        "waves_died": pred.n_died,
        "runs_failed": pred.n_failed,
        "floor": floor,
        "n_dominoes": n,
        "fit_from": fit_from,
    }


def write_csv(path: Path, columns, rows) -> Path:
    with path.open("w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(columns))
        writer.writeheader()
        for row in rows:
            writer.writerow(
                {k: (f"{v:.6g}" if isinstance(v, float) else v) for k, v in row.items()}
            )
    return path


def _merge(path: Path, columns, new_rows, key) -> list[dict]:
    """Rows of ``path`` (if any) with ``new_rows`` replacing those of equal ``key``."""
    old = list(csv.DictReader(path.open(encoding="utf-8"))) if path.exists() else []
    fresh = {key(r) for r in new_rows}
    kept = [r for r in old if key(r) not in fresh]
    rows = [*kept, *new_rows]
    return sorted(rows, key=lambda r: (str(r.get("model", "")), float(r["gap_m"])))


def run_study(args) -> None:
    out, runs = Path(args.out), Path(args.runs)
    out.mkdir(parents=True, exist_ok=True)
    runs.mkdir(parents=True, exist_ok=True)
    gaps = [1e-3 * g for g in args.gaps]
    sr = args.stiffness_ratio
    models_csv = out / "speed_vs_pitch_models.csv"
    band_csv = out / "speed_vs_pitch_band.csv"

    def model_key(r):
        return (str(r["model"]), round(float(r["gap_m"]), 9))

    def save_models(rows):
        write_csv(models_csv, MODEL_COLUMNS, _merge(models_csv, MODEL_COLUMNS, rows, model_key))

    grid = np.linspace(0.003, 0.045, 85)  # to d/l = 0.94: the widest measured gap
    write_csv(out / "speed_vs_pitch_theory.csv", THEORY_COLUMNS, theory_curve(args.floor, grid))
    theory = [r for g in gaps for r in theory_rows(g, args.floor, args.n, args.fit_from, sr)]
    save_models(theory)
    if "rods" in args.parts:
        for g in gaps:
            for ideal in (False, True):
                start = time.process_time()
                row = rod_row(g, args.floor, args.n, args.fit_from, sr, ideal)
                save_models([row])
                print(f"{row['model']} {1e3 * g:g} mm: {row['speed_m_s']:.4g} m/s", end="")
                print(f" ({time.process_time() - start:.1f} s CPU)", flush=True)
    if "dem" in args.parts:
        points = nominal_points(gaps, args.floor, args.n, args.fit_from, args.models, sr)
        save_models(dem_rows(points, runs))
        print(f"nominal DEM chains ({', '.join(args.models)}) done", flush=True)
    if "long" in args.parts:  # measured as the films of long rows are: from domino 10 on
        for gap in args.long_gaps:  # one sweep folder a gap: gaps can be added later
            points = nominal_points([1e-3 * gap], args.floor, args.long_n, 10, ["3d"], sr)
            save_models(dem_rows(points, runs, suffix="_long", folder=f"long_{gap:g}mm"))
        print(f"long nominal 3D chains ({args.long_n} dominoes) done", flush=True)
    if "band" in args.parts:
        for g in gaps:
            options = {"model": args.band_model, "stiffness_ratio": sr, "fidelity": _fidelity(sr)}
            row = band_row(g, args.floor, args.n, args.fit_from, args.samples, runs, **options)
            rows = _merge(band_csv, BAND_COLUMNS, [row], lambda r: round(float(r["gap_m"]), 9))
            write_csv(band_csv, BAND_COLUMNS, rows)
            print(f"band {1e3 * g:g} mm: {row['q05_m_s']:.4g} .. {row['q95_m_s']:.4g} m/s")


def report(args) -> None:
    from dominowave.plots.real_dominoes import (
        compare_measurements,
        comparison_markdown,
        plot_speed_vs_pitch,
        read_study,
        speeds_markdown,
    )

    out = Path(args.out)
    study = read_study(out)
    plot_speed_vs_pitch(study, out / "speed_vs_pitch.png", measurements=args.measurements)
    table = compare_measurements(study, measurements=args.measurements)
    with (out / "speed_vs_pitch_measurements.csv").open("w", encoding="utf-8", newline="") as fh:
        writer = csv.DictWriter(fh, fieldnames=list(table[0]) if table else ["key"])
        writer.writeheader()
        writer.writerows(table)
    speeds, comparison = speeds_markdown(study), comparison_markdown(table)
    print(speeds)
    print()
    print(comparison)
    if args.update_doc:
        doc = HERE.parent / "real_dominoes.md"
        text = doc.read_text(encoding="utf-8")
        for name, block in (("speeds", speeds), ("comparison", comparison)):
            text = replace_between(text, name, block)
        doc.write_text(text, encoding="utf-8")
        print(f"updated the tables of {doc.name}")


def replace_between(text: str, name: str, block: str) -> str:
    """``text`` with the lines between ``<!-- name:begin -->`` and ``<!-- name:end -->``
    replaced by ``block``; a ``ValueError`` if the markers are missing."""
    begin, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    if text.count(begin) != 1 or text.count(end) != 1 or text.index(begin) > text.index(end):
        raise ValueError(f"the doc must hold the markers {begin} and {end} once, in order")
    head, rest = text.split(begin)
    _, tail = rest.split(end)
    return f"{head}{begin}\n{block}\n{end}{tail}"


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--floor", default="hardwood", help="named floor (default hardwood)")
    parser.add_argument("--gaps", type=float, nargs="+", default=list(GAPS_MM), help="[mm]")
    parser.add_argument("--n", type=int, default=12, help="dominoes in each chain")
    parser.add_argument("--fit-from", type=int, default=3, help="fit from this domino on")
    parser.add_argument("--samples", type=int, default=1, help="Saltelli base size N")
    parser.add_argument("--parts", default="rods,dem,band", help="parts to run (comma list)")
    parser.add_argument("--long-gaps", type=float, nargs="+", default=[9.38], help="[mm]")
    parser.add_argument("--long-n", type=int, default=30, help="dominoes of the long chains")
    parser.add_argument("--models", default="2d,3d", help="nominal DEM models (comma list)")
    parser.add_argument("--band-model", default="3d", help="DEM model of the band")
    parser.add_argument("--stiffness-ratio", type=float, default=None, help="cheap test runs")
    parser.add_argument("--out", default=str(HERE), help="folder of the CSVs and the figure")
    parser.add_argument("--runs", default="speed_vs_pitch_runs", help="sweep folders")
    parser.add_argument("--measurements", default=None, help="a measurements CSV")
    parser.add_argument("--report", action="store_true", help="figure and table from the CSVs")
    parser.add_argument(
        "--update-doc", action="store_true", help="write the tables into real_dominoes.md"
    )
    parser.add_argument("--quick", action="store_true", help="tiny 2D chains, two gaps")
    args = parser.parse_args(argv)
    args.parts = args.parts.split(",")
    args.models = args.models.split(",")
    if args.quick:  # the whole pipeline on cheap chains: k/k* = 1e3, 5 dominoes, 2D
        args.gaps, args.n, args.fit_from = [12.0, 24.0], 5, 1
        args.models, args.band_model, args.stiffness_ratio = ["2d"], "2d", 1e3
    if not args.report:
        run_study(args)
    report(args)
    return 0


if __name__ == "__main__":
    sys.exit(main())
