"""REST service for insect-gait: queue simulation jobs, run them in worker processes, keep them.

Entry points: `server.app.create_app(settings)` for ASGI servers and tests, `insect-gait api`
(`server.cli`) for people. The service depends on `sim_core` only through its public names.
"""
