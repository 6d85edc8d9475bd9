"""The one sentence the viewer says about the model: keep it true.

This is the only place the viewer describes what the model does. It must agree with
docs/REPRODUCTION.md (and README's "Status, honestly"): today the metachronal branch is
reproduced and the tripod branch is not, so there is no jump between the gaits and no hysteresis
loop. When the gait-selection work makes the tripod branch appear, change this text together
with REPRODUCTION.md (tests/web/test_web_units.py checks that the caption makes no promise
REPRODUCTION.md's summary table does not back).
"""

from __future__ import annotations

CAPTION = (
    "**Hexapod (Fujiki et al. 2013), today's model.** Δ31 settles on the *metachronal* branch "
    "(about 1.7-2.1 rad, lower at higher β); the tripod branch of the paper does not appear yet, "
    "so there is no jump to the tripod and no hysteresis loop. Starts near the tripod (π) drift "
    "slowly towards the metachronal gait. See docs/REPRODUCTION.md."
)
