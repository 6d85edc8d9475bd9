"""Live browser viewer for the walking hexapod: a viser app over `sim_core.Simulation`.

Only `web.app` and `web.scene` import viser and MuJoCo; the request queue, slider mapping,
readers of the simulation's record (web/record.py) and SVG diagrams are pure so that they can
be tested without a browser.
"""
