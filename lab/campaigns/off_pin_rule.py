"""The drift surface's off-pin rule read against leg 1's reset jump (issue 52, point 1), on the
committed surfaces of both regimes, without simulating.

Usage: python -m lab.campaigns.off_pin_rule

Why: a pinned walk's Delta31 is sampled at leg 1's touchdown, after eq. 4 has reset leg 1, so
it sits off its pin by leg 1's own jump (per probe, offset against jump: r = -0.99 soft, -0.97
stiff; docs/studies/soft_legs.md). Soft legs jump leg 1 by ~+0.10 rad, onto the 0.1 rad
rule (`SurfaceConfig.off_pin_tol_rad`), which then discards 15% of their probes. Here every
periodic probe is re-read with the rule applied to (offset + leg 1's jump) and the surface
re-assembled from the same probes (`assemble`: zeros, bands, branches, folds), then compared
with the rule as it stands: which probes change, which zeros and folds appear or go.
"""

from __future__ import annotations

from pathlib import Path

from sim_core.contract import DriftSurface, SurfaceConfig
from sim_core.research import angle_diff, assemble

SURFACES = {
    "stiff (defaults), docs/figures/surface.json": Path("docs/figures/surface.json"),
    "soft legs, docs/studies/surface_soft_legs.json": Path("docs/studies/surface_soft_legs.json"),
}
WINDOW = (1.4, 3.4)  # the paper's window of Delta31


def config_of(s: DriftSurface) -> SurfaceConfig:
    """The protocol the surface was made with (its recorded config)."""
    return s.config


def corrected(s: DriftSurface, cfg: SurfaceConfig) -> tuple[DriftSurface, int, int]:
    """The surface re-assembled with the rule on (offset + leg 1's jump); how many probes
    became usable and how many unusable."""
    points, gained, lost = [], 0, 0
    for p in s.points:
        periodic = p.spread is not None and p.spread <= cfg.periodic_tol_rad
        if p.d31 is None or p.jumps[0] is None or p.drift is None or not periodic:
            points.append(p)
            continue
        offset = float(angle_diff(p.d31, p.pin_d31)) + float(p.jumps[0])
        ok = abs(offset) <= cfg.off_pin_tol_rad
        gained += ok and not p.usable
        lost += p.usable and not ok
        why = "" if ok else f"off its pin by {offset:.3f} rad after leg 1's jump"
        points.append(p.model_copy(update={"usable": ok, "why": why}))
    out = assemble(s.betas, points, cfg, sim_s=s.sim_s, body_mass_g=s.body_mass_g,
                   slope_deg=s.slope_deg, ground=s.ground)  # fmt: skip
    return out, gained, lost


def zeros(s: DriftSurface) -> set[tuple[float, float, str]]:
    """(beta, Delta31, S/U) of every zero in the window, rounded as the table writes them."""
    lo, hi = WINDOW
    return {(round(z.beta, 3), round(z.d31, 2), "S" if z.stable else "U")
            for z in s.zeros if lo <= z.d31 <= hi}  # fmt: skip


def main() -> None:
    for name, path in SURFACES.items():
        s = DriftSurface.model_validate_json(path.read_text())
        new, gained, lost = corrected(s, config_of(s))
        before, after = zeros(s), zeros(new)
        print(f"{name}: {len(s.points)} probes; with the jump-corrected rule {gained} more "
              f"usable, {lost} fewer")  # fmt: skip
        print(f"  zeros only with the rule as it stands: {sorted(before - after)}")
        print(f"  zeros only with the corrected rule:    {sorted(after - before)}")
        folds = sorted((f.beta_lo, f.beta_hi, round(f.d31, 2)) for f in new.folds)
        print(f"  folds with the corrected rule: {folds}\n")


if __name__ == "__main__":
    main()
