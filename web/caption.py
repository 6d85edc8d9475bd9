"""The one sentence the viewer says about the model: keep it true.

This is the only place the viewer describes what the model does. It must agree with
docs/REPRODUCTION.md (and README's "Status, honestly"): today both gaits exist at the paper's
values, the tripod's fold is at beta ~0.6475 (settled 40 s runs at the default step; at dt/2
it is gone by 0.6325; it lingers on a ghost to ~0.67),
but the metachronal gait lives at every
beta, so there is one jump (tripod -> metachronal) and no hysteresis loop. When the metachronal's
fold appears, change this text together with REPRODUCTION.md (tests/web/test_web_units.py checks
that the caption makes no promise REPRODUCTION.md's summary table does not back).
"""

from __future__ import annotations

CAPTION = (
    "**Hexapod (Fujiki et al. 2013), today's model.** Two gaits at the paper's values: *tripod* "
    "(Δ31 ≈ 2.95 rad) from a tripod start while β ≤ 0.645 (to ~0.62 at half the step), and "
    "*metachronal* (1.7-2.1 rad) at "
    "every β. Raise β past ~0.65 and the tripod is lost: Δ31 lingers 15-25 s near 2.95, then "
    "slides to the metachronal gait. The jump back to the tripod at high speed does not appear "
    "(the metachronal gait lives down to β 0.60), so there is no hysteresis loop yet. On a "
    "slope, walk on the penalty ground, the paper's (buttons 'ground'): the constraint ground "
    "turns the body downhill. See docs/REPRODUCTION.md."
)
