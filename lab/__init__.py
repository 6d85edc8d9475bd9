"""The lab: the studies and campaigns behind docs/REPRODUCTION.md, outside the product.

Not installed with the package (pyproject installs sim_core, server and web only): run from a
checkout as `python -m lab <command>` (lab/cli.py) or `python -m lab.campaigns.<name>`. The
product never imports it (an import-linter contract); it uses the core.
"""
