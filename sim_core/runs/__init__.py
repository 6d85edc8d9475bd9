# the backends `reproduce --backend` offers; here (no imports) so that building the CLI
# parser loads no MuJoCo: sim_core.runs.backends implements them
BACKENDS = ("local", "dask", "ray", "inline")
