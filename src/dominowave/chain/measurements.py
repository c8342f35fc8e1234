"""Published measurements of domino toppling-wave speeds, as printed by their authors.

The data file ``chain/data/measurements.csv`` (shipped with the package) has one row per
measured speed: who measured it (a full citation), how (high-speed camera, sound, stopwatch,
...), the dominoes (height, width, thickness [m], mass [kg], material), the floor, the
spacing and its basis, the speed [m/s] with its uncertainty if given, whether it is an
asymptotic (steady) speed or an average over the row, the number of dominoes, and where in
the source the number is printed (a figure read-off says so, with its error). Where a
source prints only the raw observations (e.g. the frame of each domino's impact), the
speed is computed from them: ``where_printed`` says that the speed is not printed, and
``note`` gives the arithmetic.

The spacing basis matters: some authors give the *gap* ``d`` between the faces of
neighbours, others the *pitch* ``d + s`` (distance between equivalent points). Both are
kept as printed; :attr:`Measurement.gap` converts where the thickness is known.
Empty cells mean "not published". What the package compares them with:
``docs/real_dominoes.md``.
"""

from __future__ import annotations

import csv
import math
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

from dominowave.theory import wave_speed_rigid
from dominowave.units import G_STANDARD

__all__ = [
    "BASES",
    "COLUMNS",
    "SPEED_KINDS",
    "Measurement",
    "MeasurementsError",
    "eq34_rigid_speed",
    "load_measurements",
]

#: The columns of the file, in order.
COLUMNS = (
    "key",
    "source",
    "method",
    "height_m",
    "width_m",
    "thickness_m",
    "mass_kg",
    "material",
    "floor",
    "spacing_m",
    "spacing_basis",
    "speed_m_s",
    "speed_unc_m_s",
    "speed_kind",
    "n_dominoes",
    "where_printed",
    "note",
)
#: ``gap``: face-to-face distance d; ``pitch``: d + s, between equivalent points.
BASES = ("gap", "pitch")
#: ``asymptotic``: the steady speed far from the push; ``average``: over the whole row,
#: start included.
SPEED_KINDS = ("asymptotic", "average")
_OPTIONAL_POSITIVE = ("height_m", "width_m", "thickness_m", "mass_kg")
_TEXT = ("key", "source", "method", "material", "floor", "where_printed")
_MIN_SOURCE_CHARS = 20


class MeasurementsError(ValueError):
    """A measurements file that is not well formed: names the file, line, column and fault."""


@dataclass(frozen=True)
class Measurement:
    """One published wave-speed measurement; lengths [m], mass [kg], speeds [m/s].

    Optional quantities the source does not publish are ``None``.
    """

    key: str
    source: str
    method: str
    height: float | None
    width: float | None
    thickness: float | None
    mass: float | None
    material: str
    floor: str
    spacing: float
    spacing_basis: str
    speed: float
    speed_unc: float | None
    speed_kind: str
    n_dominoes: int | None
    where_printed: str
    note: str

    @property
    def gap(self) -> float | None:
        """Face-to-face gap ``d`` [m]: the spacing itself, or pitch minus thickness."""
        if self.spacing_basis == "gap":
            return self.spacing
        return None if self.thickness is None else self.spacing - self.thickness

    @property
    def pitch(self) -> float | None:
        """Pitch ``d + s`` [m]: the spacing itself, or gap plus thickness."""
        if self.spacing_basis == "pitch":
            return self.spacing
        return None if self.thickness is None else self.spacing + self.thickness


def _default_path():
    return resources.files("dominowave.chain").joinpath("data", "measurements.csv")


def _float(where: str, column: str, text: str, *, optional: bool) -> float | None:
    """A positive number from a cell (an uncertainty may be 0); ``None`` if empty and optional."""
    text = text.strip()
    if not text:
        if optional:
            return None
        raise MeasurementsError(f"{where}: {column} is empty but required")
    try:
        x = float(text)
    except ValueError:
        raise MeasurementsError(f"{where}: {column} = {text!r} is not a number") from None
    if not math.isfinite(x):
        raise MeasurementsError(f"{where}: {column} = {text!r} is not a finite number")
    if column == "speed_unc_m_s":
        if x < 0.0:
            raise MeasurementsError(f"{where}: {column} = {x:g} is outside [0, inf)")
    elif x <= 0.0:
        raise MeasurementsError(f"{where}: {column} = {x:g} is outside (0, inf)")
    return x


def _row(where: str, row: dict[str, str]) -> Measurement:
    for column in _TEXT:
        if not row[column].strip():
            raise MeasurementsError(f"{where}: {column} is empty but required")
    source = row["source"].strip()
    if len(source) < _MIN_SOURCE_CHARS:
        raise MeasurementsError(
            f"{where}: source = {source!r} is not a citation "
            f"(at least {_MIN_SOURCE_CHARS} characters: authors, year, journal or address)"
        )
    basis = row["spacing_basis"].strip()
    if basis not in BASES:
        raise MeasurementsError(f"{where}: spacing_basis = {basis!r} is not one of {BASES}")
    kind = row["speed_kind"].strip()
    if kind not in SPEED_KINDS:
        raise MeasurementsError(f"{where}: speed_kind = {kind!r} is not one of {SPEED_KINDS}")
    n_text = row["n_dominoes"].strip()
    n = None
    if n_text:
        if not n_text.isdigit() or int(n_text) < 2:
            raise MeasurementsError(f"{where}: n_dominoes = {n_text!r} is not an integer >= 2")
        n = int(n_text)
    opt = {c: _float(where, c, row[c], optional=True) for c in _OPTIONAL_POSITIVE}
    m = Measurement(
        key=row["key"].strip(),
        source=source,
        method=row["method"].strip(),
        height=opt["height_m"],
        width=opt["width_m"],
        thickness=opt["thickness_m"],
        mass=opt["mass_kg"],
        material=row["material"].strip(),
        floor=row["floor"].strip(),
        spacing=_float(where, "spacing_m", row["spacing_m"], optional=False),
        spacing_basis=basis,
        speed=_float(where, "speed_m_s", row["speed_m_s"], optional=False),
        speed_unc=_float(where, "speed_unc_m_s", row["speed_unc_m_s"], optional=True),
        speed_kind=kind,
        n_dominoes=n,
        where_printed=row["where_printed"].strip(),
        note=row["note"].strip(),
    )
    if m.gap is not None and m.gap <= 0.0:
        raise MeasurementsError(
            f"{where}: pitch {m.spacing:g} m minus thickness {m.thickness:g} m leaves no gap"
        )
    return m


def load_measurements(path: str | Path | None = None) -> list[Measurement]:
    """Read and validate a measurements file (default: the shipped ``measurements.csv``).

    The header must be exactly :data:`COLUMNS`; every row needs a citation, a method, the
    spacing with its basis (:data:`BASES`), a positive speed and its kind
    (:data:`SPEED_KINDS`), and says where the number is printed. Keys are unique. Raises
    :class:`MeasurementsError` naming the file, the line, the column and the fault.
    """
    source = _default_path() if path is None else Path(path)
    name = str(source)
    try:
        text = source.read_text(encoding="utf-8")
    except FileNotFoundError:
        raise MeasurementsError(f"{name}: no such file") from None
    reader = csv.DictReader(text.splitlines(), strict=True)
    header = tuple(reader.fieldnames or ())
    if header != COLUMNS:
        missing = [c for c in COLUMNS if c not in header]
        extra = [c for c in header if c not in COLUMNS]
        raise MeasurementsError(
            f"{name}: header must be {', '.join(COLUMNS)}"
            + (f"; missing {', '.join(missing)}" if missing else "")
            + (f"; unknown {', '.join(extra)}" if extra else "")
            + ("; columns out of order" if not missing and not extra else "")
        )
    rows: list[Measurement] = []
    seen: set[str] = set()
    try:
        for row in reader:
            where = f"{name} line {reader.line_num}"
            if None in row or any(v is None for v in row.values()):
                raise MeasurementsError(
                    f"{where}: expected {len(COLUMNS)} cells, got a different number"
                )
            m = _row(where, row)
            if m.key in seen:
                raise MeasurementsError(f"{where}: key = {m.key!r} appears twice")
            seen.add(m.key)
            rows.append(m)
    except csv.Error as exc:
        raise MeasurementsError(f"{name} line {reader.line_num}: not valid CSV ({exc})") from None
    if not rows:
        raise MeasurementsError(f"{name}: no measurements")
    return rows


def eq34_rigid_speed(m: Measurement, g: float = G_STANDARD) -> float | None:
    """The paper's speed for this measurement's dominoes in the rigid limit [m/s].

    Eq 34 with ``T_c = 0``: ``v^s = (d + s) / T``, ``T`` the Efthimiou-Johnson limit fall
    time (eq 13) of thin dominoes of height ``l`` at ``sin(beta) = d / l``, ``d`` the gap
    and ``s`` the thickness (the paper's thin-domino free fall, point mass at the top).
    ``None`` where the source does not publish ``l`` or ``s``, or where ``d >= l`` (no
    collision).
    """
    if m.height is None or m.thickness is None:
        return None
    d = m.gap
    if d is None or d >= m.height:
        return None
    beta = math.asin(d / m.height)
    return float(wave_speed_rigid(beta, m.height, g)) * (d + m.thickness) / d  # eq. 34
