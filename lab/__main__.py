"""`python -m lab ...` from a checkout (the lab is not installed with the package)."""

import sys

from lab.cli import main

sys.exit(main())
