"""``python cli_with_helpers.py ARGS`` = ``dominowave ARGS`` with the test scenarios registered."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import workflow_helpers  # noqa: F401

from dominowave.cli import main

if __name__ == "__main__":
    main()
