"""The gait campaigns' scripts, kept as code (linted, type-checked, importable): each module is
one study whose numbers and commands are in docs/studies/*.md, run as
`python -m lab.campaigns.<name> ...`. They predate `sim_core.runs` and keep their
own process pools; the newer studies (`python -m lab readings`, `timing-lines`, `slope-heading`)
run through the result cache."""
