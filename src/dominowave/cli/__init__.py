"""The ``dominowave`` command line.

Each instrument registers its commands from a module of this package
(``cli/theory.py``, ...). Errors from bad input surface as a one-line message
on stderr and exit code 2, never as a traceback.
"""

from __future__ import annotations

import importlib
import sys

import typer

app = typer.Typer(
    name="dominowave",
    help="How fast are elastic domino waves? Theory, reduced rod model and DEM.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)

# Command modules of this package, each exposing ``register(app)``.
_COMMAND_MODULES: tuple[str, ...] = ("theory", "rods", "chain", "workflow")


def _register_all() -> None:
    for name in _COMMAND_MODULES:
        qualified = f"dominowave.cli.{name}"
        try:
            module = importlib.import_module(qualified)
        except ModuleNotFoundError as exc:
            if exc.name == qualified:  # instrument not built yet in this checkout
                continue
            raise
        module.register(app)


_register_all()


def main() -> None:
    """Entry point of the ``dominowave`` console script.

    Typer handles usage errors itself (exit code 2). Bad physical input raises
    ``ValueError`` deep inside the package; it is shown as one line, exit code 2.
    """
    try:
        app()
    except (ValueError, FileNotFoundError, PermissionError, NotADirectoryError) as exc:
        typer.echo(f"dominowave: error: {exc}", err=True)
        sys.exit(2)
