"""`python -m sim_core.cli`: the `insect-gait` command without the installed script."""

import sys

from sim_core.cli.main import main

sys.exit(main())
