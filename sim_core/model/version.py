"""The physics' version: what the result cache means by "the same simulated numbers".

A cached run is keyed by its spec, its non-default parameters and this version, not by the
bytes of the physics sources, so a comment, a rename or a regrouping keeps every cached run.
The price is a promise: a change that moves any simulated number bumps `PHYSICS_VERSION` in
the same commit. `tests/core/test_physics_version.py` holds the promise to account: it
re-simulates a dump of every way a number is made (both grounds, a failed run, a settled
stop, a pinned probe, a ramp, dt/2, the live walk) and fails when the numbers moved but the
version did not, or the version moved but the committed numbers did not.
"""

from __future__ import annotations

# 1: the physics at commit 1e3c8fb, when the key stopped hashing the sources
PHYSICS_VERSION = "1"
