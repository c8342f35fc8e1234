"""The layering of the package (docs/architecture.md), checked on the source: no import
circles, and the three
instruments (theory, rods, dem) import neither each other nor anything above them.

Every import counts, also those inside functions (a lazy import that closes a circle is
still a circle a reader must untangle).
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

SRC = Path(__file__).parents[1] / "src"
INSTRUMENTS = ("theory", "rods", "dem")
SHARED = (
    "dominowave.checks",
    "dominowave.units",
    "dominowave.kernel_cache",
    "dominowave.compile_ahead",
)


def _modules() -> dict[str, Path]:
    out = {}
    for path in SRC.rglob("*.py"):
        parts = path.relative_to(SRC).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        out[name] = path
    return out


def _imports(path: Path, known: set[str]) -> set[str]:
    """The package modules that ``path`` imports (``from a import b`` counts ``a.b``
    when ``b`` is a module)."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            names = [node.module, *(f"{node.module}.{a.name}" for a in node.names)]
        elif isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        else:
            continue
        found.update(n for n in names if n in known)
    return found


MODULES = _modules()
GRAPH = {
    name: {t for t in _imports(path, set(MODULES)) if not name.startswith(t) and t != name}
    for name, path in MODULES.items()
}


def test_no_import_circles():
    def visit(node, trail):
        if node in trail:
            return [*trail[trail.index(node) :], node]
        for nxt in sorted(GRAPH[node]):
            circle = visit(nxt, [*trail, node])
            if circle:
                return circle
        return None

    for start in sorted(GRAPH):
        circle = visit(start, [])
        assert circle is None, " -> ".join(circle)


@pytest.mark.parametrize("layer", INSTRUMENTS)
def test_instruments_import_only_below_them(layer):
    prefix = f"dominowave.{layer}"
    for name in (n for n in GRAPH if n == prefix or n.startswith(prefix + ".")):
        foreign = {
            t
            for t in GRAPH[name]
            if t != prefix and not t.startswith(prefix + ".") and t not in SHARED
        }
        assert not foreign, f"{name} imports {sorted(foreign)}"
