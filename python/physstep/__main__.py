"""``python -m physstep``: the command line."""

import sys

from physstep.cli import main

sys.exit(main())
