"""The ``dominowave`` command line.

Each instrument registers its commands from a module of this package
(``cli/theory.py``, ...). Errors from bad input surface as a one-line message
on stderr and exit code 2, never as a traceback.
"""

from __future__ import annotations

import functools
import importlib
import sys

import typer

from dominowave import signals
from dominowave.io.atomic import os_error_line, remove_empty_created

app = typer.Typer(
    name="dominowave",
    help="How fast are elastic domino waves? Theory, reduced rod model and DEM.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
    # plain help text: rich markup would read the units "[m]", "[s]" of the options as
    # tags and drop them
    rich_markup_mode=None,
)


def version_line() -> str:
    """``dominowave X.Y.Z`` and, when imported from a git checkout, its commit."""
    from dominowave import __version__
    from dominowave.io.provenance import git_commit

    commit = git_commit()
    return f"dominowave {__version__}" + (f" (git {commit})" if commit else "")


def _print_version(value: bool) -> None:
    if value:
        typer.echo(version_line())
        raise typer.Exit()


@app.callback()
def _options(
    version: bool = typer.Option(
        False,
        "--version",
        help="Print the version and exit.",
        callback=_print_version,
        is_eager=True,
    ),
) -> None:
    """How fast are elastic domino waves? Theory, reduced rod model and DEM."""


# Command modules of this package, each exposing ``register(app)``.
_COMMAND_MODULES: tuple[str, ...] = ("theory", "leaning", "rods", "chain", "predict", "workflow")


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


def _stop_on_signals(callback):
    """Wrap a command: SIGINT/SIGTERM end it with one line and exit code 130/143.

    (Click would turn the KeyboardInterrupt into an ``Abort``: exit code 1, and
    SIGTERM would be indistinguishable from Ctrl-C.) A command that keeps partial
    results catches the interrupt itself first and says so.
    """

    @functools.wraps(callback)
    def wrapper(*args, **kwargs):
        try:
            return callback(*args, **kwargs)
        except KeyboardInterrupt as exc:
            typer.echo("dominowave: interrupted", err=True)
            sys.exit(signals.exit_code(exc))

    return wrapper


_register_all()
for _command in app.registered_commands:
    _command.callback = _stop_on_signals(_command.callback)


RENAMED_OPTIONS = {
    "--k-ratio": "--stiffness-ratio",
    "--mu": "--friction-floor (theory) or --friction-dominoes (rods)",
    "--damping": "--damping-ratio (rods)",
    "--mass": "--mass-model (rods)",
}
"""Options of earlier versions -> their names in the one vocabulary (ChainParams')."""


def main() -> None:
    """Entry point of the ``dominowave`` console script (see :func:`_main`); a command that
    fails or is interrupted leaves no empty output folder behind."""
    try:
        _main()
    except SystemExit as exc:
        if exc.code not in (0, None):
            remove_empty_created()
        raise
    except BaseException:
        remove_empty_created()
        raise


def _main() -> None:
    """The command line, every error one line.

    Every error a user can cause is one line on stderr with exit code 2: usage
    errors (unknown option, missing argument) and bad physical input, which raises
    ``ValueError`` deep inside the package. No traceback. SIGINT and SIGTERM stop
    any command with one line and exit code 130 and 143 (:mod:`dominowave.signals`).
    """
    signals.install()
    try:
        result = app(standalone_mode=False)
    except typer.TyperException as exc:  # click usage errors
        message = exc.format_message().strip()
        renamed = RENAMED_OPTIONS.get(getattr(exc, "option_name", None))
        if renamed:
            message = f"no such option: {exc.option_name} (renamed: use {renamed})"
        if "\n" in message:  # called without arguments: the message is the help text
            typer.echo(message, err=True)
        elif message:  # (an empty message: typer has already shown the help)
            typer.echo(f"dominowave: error: {message}", err=True)
        sys.exit(getattr(exc, "exit_code", 2))
    except (ValueError, FileNotFoundError, PermissionError, NotADirectoryError) as exc:
        typer.echo(f"dominowave: error: {exc}", err=True)
        sys.exit(2)
    except (FileExistsError, IsADirectoryError) as exc:  # a path given by the user
        typer.echo(f"dominowave: error: {exc.strerror}: {exc.filename}", err=True)
        sys.exit(2)
    except OSError as exc:  # the machine, not the input: exit code 1
        typer.echo(f"dominowave: error: {os_error_line(exc)}", err=True)
        sys.exit(1)
    except typer.Abort:
        typer.echo("dominowave: aborted", err=True)
        sys.exit(1)
    # In non-standalone mode typer returns the code of an explicit typer.Exit
    # (130 after Ctrl-C); a command's own return value is never an int here.
    if isinstance(result, int):
        sys.exit(result)
