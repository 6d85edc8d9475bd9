"""Fixtures for the REST service tests; the harness itself lives in api_harness.py."""

from api_harness import make_server

__all__ = ["make_server"]
