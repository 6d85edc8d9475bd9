# insect-gait: the REST API (default command) and, with another command, the viewer.
# Same install steps as the Makefile's `make install` (`python -m venv .venv && .venv/bin/pip
# install -e .` with the same warning filter, then `python -m sim_core.model.ground_build`, the
# penalty ground's MuJoCo plugin), without the dev, cluster and lab extras (no optuna). They run
# in a build stage with a C compiler; the image gets /app without it.
# INSTALL_EXTRAS=cluster (a build argument) adds the cluster extra (dask.distributed): the image
# of docker-compose.yml's `cluster` profile (its scheduler and workers, and the API that sends
# them its jobs); empty by default, so the plain image stays `make install`'s.
FROM python:3.11-slim AS build
ARG INSTALL_EXTRAS=""

ENV PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1

# hadolint ignore=DL3008
RUN apt-get update \
    && apt-get install -y --no-install-recommends gcc libc6-dev \
    && rm -rf /var/lib/apt/lists/*

WORKDIR /app
COPY pyproject.toml README.md ./
COPY sim_core ./sim_core
COPY server ./server
COPY web ./web
RUN python -m venv .venv \
    && PYTHONWARNINGS="ignore:Editable installation" .venv/bin/pip install --quiet -e . \
    && if [ -n "$INSTALL_EXTRAS" ]; then \
        PYTHONWARNINGS="ignore:Editable installation" .venv/bin/pip install --quiet \
            -e ".[$INSTALL_EXTRAS]"; fi \
    && .venv/bin/python -m sim_core.model.ground_build

FROM python:3.11-slim

ENV PYTHONUNBUFFERED=1 \
    PYTHONDONTWRITEBYTECODE=1 \
    PIP_NO_CACHE_DIR=1 \
    PIP_DISABLE_PIP_VERSION_CHECK=1 \
    MPLBACKEND=Agg \
    PATH="/app/.venv/bin:${PATH}" \
    INSECT_GAIT_HOST=0.0.0.0 \
    INSECT_GAIT_PORT=8000 \
    INSECT_GAIT_DB_PATH=/data/insect-gait.sqlite3 \
    INSECT_GAIT_CACHE_DIR=/cache

RUN groupadd --system --gid 10001 app \
    && useradd --system --uid 10001 --gid app --home-dir /app --shell /usr/sbin/nologin app \
    && mkdir -p /app /data /cache \
    && chown app:app /app /data /cache

WORKDIR /app
USER 10001:10001

# the same base image as the build stage, so the venv's interpreter paths and libc match
COPY --from=build --chown=10001:10001 /app /app
# the results the viewer's panels read (the core's results folder: the checkout's docs/figures,
# here /app/docs/figures); only the JSON files reach the build context (.dockerignore)
COPY --chown=10001:10001 docs/figures ./docs/figures

# the jobs' database, and the result cache the API's jobs and `insect-gait` commands run in
# the container share (INSECT_GAIT_CACHE_DIR)
VOLUME ["/data", "/cache"]
EXPOSE 8000 8080

# The API's own health endpoint; python instead of curl, which the slim image lacks.
HEALTHCHECK --interval=30s --timeout=5s --start-period=30s --retries=3 \
    CMD ["python", "-c", "import os, urllib.request; urllib.request.urlopen('http://127.0.0.1:%s/healthz' % os.environ.get('INSECT_GAIT_PORT', '8000'), timeout=4)"]

CMD ["insect-gait", "api"]
