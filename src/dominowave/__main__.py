"""``python -m dominowave`` runs the command line."""

from dominowave.cli import main

main()
