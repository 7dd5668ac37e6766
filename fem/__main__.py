"""``python -m fem``: see fem.cli."""
import sys

from fem.cli import main

if __name__ == "__main__":
    sys.exit(main())
