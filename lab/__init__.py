"""The lab: the studies and campaigns behind docs/REPRODUCTION.md, outside the product.

Not installed with the package (pyproject installs sim_core, server and web only): run from a
checkout as `python -m lab <command>` (lab/cli.py) or `python -m lab.campaigns.<name>`. The
product never imports it, and it uses only the core's public API, as the edges do: `sim_core`,
`sim_core.contract` and `sim_core.cli` (import-linter contracts in pyproject.toml; the names:
docs/CORE_API.md, "For research").
"""
