"""``python -m neurov``: the ``neurov`` command."""

import sys

from neurov.cli import main

if __name__ == "__main__":  # importing the module (a documentation tool's walk) runs nothing
    sys.exit(main())
