"""Routes per resource: `jobs` (the job queue and its results) and `meta` (health, model,
integrators, the offline API docs)."""
