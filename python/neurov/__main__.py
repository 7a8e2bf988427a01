"""``python -m neurov``: the ``neurov`` command."""

import sys

from neurov.cli import main

sys.exit(main())
