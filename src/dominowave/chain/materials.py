"""Material data of a real toppling domino, each value with its range, unit and source.

The data file ``chain/data/materials.toml`` (shipped with the package) holds, for the
common 48 x 24 x 7.5 mm plastic domino, its size and mass, the density, Young's modulus
and Poisson ratio of the plastic, the domino-domino friction, the domino-floor friction of
named floors and the restitution of domino-domino and domino-floor impacts. Every entry
carries a nominal value, a plausible range ``[lo, hi]``, a unit, the kind of its source
(manufacturer, handbook, derived, assumption) and the source itself. Nothing is fitted to
wave-speed measurements. Where the numbers come from: ``docs/real_dominoes.md``.

::

    from dominowave.chain.materials import load_materials, floor_friction

    mat = load_materials()
    mat.plastic.youngs_modulus.value      # 2.39e9 [Pa]
    floor_friction("felt").range          # (0.5, 1.0)
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Iterator
from dataclasses import dataclass
from importlib import resources
from pathlib import Path

__all__ = [
    "KINDS",
    "Domino",
    "Entry",
    "Materials",
    "MaterialsError",
    "Plastic",
    "floor_friction",
    "load_materials",
]

#: Where an entry's number comes from.
KINDS = ("manufacturer", "handbook", "derived", "assumption")

# Each entry of the file: its unit and the physically admissible interval of its value
# (a bound of the physics, not of the data: the data's own range is the entry's lo, hi).
_ENTRY_SPECS: dict[str, tuple[str, float, float]] = {
    "domino.height": ("m", 0.0, math.inf),
    "domino.width": ("m", 0.0, math.inf),
    "domino.thickness": ("m", 0.0, math.inf),
    "domino.mass": ("kg", 0.0, math.inf),
    "plastic.density": ("kg/m^3", 0.0, math.inf),
    "plastic.youngs_modulus": ("Pa", 0.0, math.inf),
    "plastic.poisson_ratio": ("1", -1.0, 0.5),
    "friction.domino_domino": ("1", 0.0, math.inf),
    "restitution.domino_domino": ("1", 0.0, 1.0),
    "restitution.domino_floor": ("1", 0.0, 1.0),
}
_FLOOR_SPEC = ("1", 0.0, math.inf)  # every friction.floor.<name>
_ENTRY_KEYS = ("value", "lo", "hi", "unit", "kind", "source")
_MIN_SOURCE_CHARS = 20  # a citation, not a word


class MaterialsError(ValueError):
    """A materials file that is not well formed: names the file, the entry and the fault."""


@dataclass(frozen=True)
class Entry:
    """One material value: ``value`` (nominal) in ``[lo, hi]`` [``unit``], with its source."""

    value: float
    lo: float
    hi: float
    unit: str
    kind: str
    source: str

    @property
    def range(self) -> tuple[float, float]:
        """The plausible range ``(lo, hi)`` [unit]."""
        return (self.lo, self.hi)


@dataclass(frozen=True)
class Domino:
    """Size [m] and mass [kg] of the domino: height ``l``, width, thickness ``s``."""

    height: Entry
    width: Entry
    thickness: Entry
    mass: Entry


@dataclass(frozen=True)
class Plastic:
    """The plastic: density [kg/m^3], Young's modulus [Pa], Poisson ratio [1]."""

    density: Entry
    youngs_modulus: Entry
    poisson_ratio: Entry


@dataclass(frozen=True)
class Materials:
    """Everything in a materials file; ``floors`` maps a floor name to its friction."""

    domino: Domino
    plastic: Plastic
    friction_domino_domino: Entry
    floors: dict[str, Entry]
    restitution_domino_domino: Entry
    restitution_domino_floor: Entry
    path: str

    @property
    def floor_names(self) -> tuple[str, ...]:
        """The named floors, sorted."""
        return tuple(sorted(self.floors))

    def floor_friction(self, name: str) -> Entry:
        """Domino-floor friction coefficient [1] of the floor ``name`` (e.g. ``"felt"``)."""
        try:
            return self.floors[name]
        except (KeyError, TypeError):
            known = ", ".join(self.floor_names)
            raise ValueError(
                f"floor = {name!r} is not a known floor; known floors: {known}"
            ) from None

    def entries(self) -> Iterator[tuple[str, Entry]]:
        """Every entry as ``(dotted name, Entry)``, in the file's order of topics."""
        for field in ("height", "width", "thickness", "mass"):
            yield f"domino.{field}", getattr(self.domino, field)
        for field in ("density", "youngs_modulus", "poisson_ratio"):
            yield f"plastic.{field}", getattr(self.plastic, field)
        yield "friction.domino_domino", self.friction_domino_domino
        for name in self.floor_names:
            yield f"friction.floor.{name}", self.floors[name]
        yield "restitution.domino_domino", self.restitution_domino_domino
        yield "restitution.domino_floor", self.restitution_domino_floor


def _default_path():
    return resources.files("dominowave.chain").joinpath("data", "materials.toml")


def _number(where: str, key: str, raw) -> float:
    if isinstance(raw, bool) or not isinstance(raw, int | float):
        raise MaterialsError(f"{where}: {key} = {raw!r} is not a number")
    x = float(raw)
    if not math.isfinite(x):
        raise MaterialsError(f"{where}: {key} = {raw!r} is not a finite number")
    return x


def _entry(where: str, raw, spec: tuple[str, float, float]) -> Entry:
    """Validate one table of the file against ``spec = (unit, lo bound, hi bound)``."""
    if not isinstance(raw, dict):
        raise MaterialsError(f"{where}: expected a table with keys {', '.join(_ENTRY_KEYS)}")
    missing = [k for k in _ENTRY_KEYS if k not in raw]
    if missing:
        raise MaterialsError(f"{where}: missing {', '.join(missing)}")
    unknown = sorted(set(raw) - set(_ENTRY_KEYS))
    if unknown:
        raise MaterialsError(
            f"{where}: unknown key(s) {', '.join(unknown)}; allowed: {', '.join(_ENTRY_KEYS)}"
        )
    value, lo, hi = (_number(where, k, raw[k]) for k in ("value", "lo", "hi"))
    unit, bound_lo, bound_hi = spec
    if raw["unit"] != unit:
        raise MaterialsError(f"{where}: unit = {raw['unit']!r}, expected {unit!r}")
    if raw["kind"] not in KINDS:
        raise MaterialsError(f"{where}: kind = {raw['kind']!r} is not one of {', '.join(KINDS)}")
    source = raw["source"]
    if not isinstance(source, str) or len(source.strip()) < _MIN_SOURCE_CHARS:
        raise MaterialsError(
            f"{where}: source = {source!r} is not a citation "
            f"(at least {_MIN_SOURCE_CHARS} characters naming where the value comes from)"
        )
    if not lo <= value <= hi:
        raise MaterialsError(
            f"{where}: value = {value:g} is outside its range [lo, hi] = [{lo:g}, {hi:g}]"
        )
    # the admissible interval is open at 0 for positive quantities, closed otherwise
    strictly_positive = bound_lo == 0.0 and unit not in ("1",)
    if lo < bound_lo or hi > bound_hi or (strictly_positive and lo <= 0.0):
        interval = f"{'(' if strictly_positive else '['}{bound_lo:g}, {bound_hi:g}]"
        raise MaterialsError(
            f"{where}: range [lo, hi] = [{lo:g}, {hi:g}] leaves the physical interval {interval}"
        )
    return Entry(value=value, lo=lo, hi=hi, unit=unit, kind=raw["kind"], source=source.strip())


def _table(where: str, raw, name: str) -> dict:
    sub = raw.get(name)
    if not isinstance(sub, dict):
        raise MaterialsError(f"{where}: missing table [{name}]")
    return sub


def load_materials(path: str | Path | None = None) -> Materials:
    """Read and validate a materials file (default: the shipped ``materials.toml``).

    Every entry must have a finite ``value`` inside its range ``[lo, hi]``, the unit its
    quantity needs, a ``kind`` from :data:`KINDS` and a ``source``; unknown entries or keys
    are errors. Raises :class:`MaterialsError` naming the file, the entry and the fault.
    """
    source = _default_path() if path is None else Path(path)
    where = str(source)
    try:
        raw = tomllib.loads(source.read_text(encoding="utf-8"))
    except FileNotFoundError:
        raise MaterialsError(f"{where}: no such file") from None
    except tomllib.TOMLDecodeError as exc:
        raise MaterialsError(f"{where}: not valid TOML ({exc})") from None
    if raw.get("schema") != 1:
        raise MaterialsError(f"{where}: schema = {raw.get('schema')!r}, expected 1")
    allowed_top = {"schema", "domino", "plastic", "friction", "restitution"}
    unknown = sorted(set(raw) - allowed_top)
    if unknown:
        raise MaterialsError(f"{where}: unknown table(s) {', '.join(unknown)}")

    entries: dict[str, Entry] = {}
    for dotted, spec in _ENTRY_SPECS.items():
        topic, name = dotted.split(".")
        table = _table(where, raw, topic)
        if name not in table:
            raise MaterialsError(f"{where}: missing entry [{dotted}]")
        entries[dotted] = _entry(f"{where} [{dotted}]", table[name], spec)
    for topic in ("domino", "plastic", "friction", "restitution"):
        known = {d.split(".")[1] for d in _ENTRY_SPECS if d.startswith(topic + ".")}
        if topic == "friction":
            known.add("floor")
        extra = sorted(set(raw[topic]) - known)
        if extra:
            raise MaterialsError(
                f"{where}: unknown entry(ies) {', '.join(f'[{topic}.{e}]' for e in extra)}"
            )

    floors_raw = _table(where, raw["friction"], "floor")
    if not floors_raw:
        raise MaterialsError(f"{where}: [friction.floor] names no floor")
    floors = {
        name: _entry(f"{where} [friction.floor.{name}]", table, _FLOOR_SPEC)
        for name, table in floors_raw.items()
    }
    return Materials(
        domino=Domino(*(entries[f"domino.{f}"] for f in ("height", "width", "thickness", "mass"))),
        plastic=Plastic(
            *(entries[f"plastic.{f}"] for f in ("density", "youngs_modulus", "poisson_ratio"))
        ),
        friction_domino_domino=entries["friction.domino_domino"],
        floors=floors,
        restitution_domino_domino=entries["restitution.domino_domino"],
        restitution_domino_floor=entries["restitution.domino_floor"],
        path=where,
    )


def floor_friction(name: str, materials: Materials | None = None) -> Entry:
    """Domino-floor friction [1] of the named floor, from ``materials`` (default: shipped)."""
    return (materials or load_materials()).floor_friction(name)
