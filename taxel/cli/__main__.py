"""`python -m taxel.cli`: the `taxel` command."""

import sys

from taxel.cli import main

if __name__ == "__main__":
    sys.exit(main())
