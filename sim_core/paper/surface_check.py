"""The drift surface against the fixed-point finder: two independent readings of one model.

The finder (`finder`) reads stable states from settled free runs and borders by
bisecting starts; the surface (`paper.surface`) reads zeros of the drift at held Delta31. They
agree when:
- every resolved stable zero of the surface has a stable state of the finder within
  `STABLE_TOL` rad, and every stable state of the finder inside the window has a stable zero
  within `STABLE_TOL`, unless the surface marks that place unresolved (an unresolved zero or a
  near-zero band reaching within `STABLE_TOL`);
- every resolved border of the finder has an unstable zero within `BORDER_TOL` rad (or an
  unresolved mark there).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from sim_core.contract.finder import CellResult, FinderOutput
from sim_core.contract.surface import SurfaceConfig
from sim_core.model.params import ModelParams
from sim_core.paper.surface import DriftSurface
from sim_core.runs.backends import Backend
from sim_core.runs.cache import ResultCache

STABLE_TOL = 0.03  # rad
BORDER_TOL = 0.05  # rad
WINDOW = (1.4, 3.4)  # the finder's window (FinderConfig.window)


@dataclass
class BetaCheck:
    """One beta's comparison; `misses` says every disagreement in words."""

    beta: float
    surface_stable: list[float]
    surface_unstable: list[float]
    surface_unresolved: list[tuple[float, float]]  # brackets of unresolved zeros and bands
    finder_stable: list[float]
    finder_borders: list[float]
    misses: list[str] = field(default_factory=list)

    @property
    def ok(self) -> bool:
        return not self.misses


def _near(x: float, xs: list[float], tol: float) -> bool:
    return any(abs(x - y) <= tol for y in xs)


def _covered(x: float, bands: list[tuple[float, float]], tol: float) -> bool:
    return any(lo - tol <= x <= hi + tol for lo, hi in bands)


def check_beta(surface: DriftSurface, cell: CellResult) -> BetaCheck:
    """Compare the surface's zeros at `cell.beta` with the finder's states there."""
    lo, hi = WINDOW
    zs = [z for z in surface.zeros_at(cell.beta) if lo <= z.d31 <= hi]
    stable = [z.d31 for z in zs if z.stable and z.resolved]
    unstable = [z.d31 for z in zs if not z.stable and z.resolved]
    unresolved = [(z.lo, z.hi) for z in zs if not z.resolved]
    unresolved += [(n.lo, n.hi) for n in surface.near_zeros if abs(n.beta - cell.beta) < 1e-9]
    f_stable = [a.d31 for a in cell.stable() if lo <= a.d31 <= hi]
    f_borders = [
        b.d31 for b in cell.borders if b.resolved and b.d31 is not None and lo <= b.d31 <= hi
    ]
    out = BetaCheck(cell.beta, stable, unstable, unresolved, f_stable, f_borders)
    for x in stable:
        if not _near(x, f_stable, STABLE_TOL):
            out.misses.append(
                f"surface stable zero {x:.3f} has no finder state within {STABLE_TOL}"
            )
    for x in f_stable:
        if not _near(x, stable, STABLE_TOL) and not _covered(x, unresolved, STABLE_TOL):
            out.misses.append(f"finder state {x:.3f} has no stable zero within {STABLE_TOL}")
    for x in f_borders:
        if not _near(x, unstable, BORDER_TOL) and not _covered(x, unresolved, BORDER_TOL):
            out.misses.append(f"finder border {x:.3f} has no unstable zero within {BORDER_TOL}")
    return out


def check(surface: DriftSurface, finder: FinderOutput) -> list[BetaCheck]:
    """Every beta the surface and the finder (at the surface's mass and slope) share."""
    cells = {
        round(c.beta, 6): c
        for c in finder.cells
        if c.body_mass_g == surface.body_mass_g and c.slope_deg == surface.slope_deg
    }
    return [check_beta(surface, cells[round(b, 6)]) for b in surface.betas if round(b, 6) in cells]


def table(rows: list[BetaCheck]) -> str:
    """The comparison as a markdown table (docs/REPRODUCTION.md)."""

    def xs(v: list[float]) -> str:
        return ", ".join(f"{x:.3f}" for x in v) or "none"

    lines = [
        "| β | surface: stable | unstable | unresolved | finder: stable | borders | agree? |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        unres = ", ".join(f"{a:.2f}-{b:.2f}" for a, b in r.surface_unresolved) or "none"
        verdict = "yes" if r.ok else "**no**: " + "; ".join(r.misses)
        lines.append(
            f"| {r.beta:g} | {xs(r.surface_stable)} | {xs(r.surface_unstable)} | "
            f"{unres} | {xs(r.finder_stable)} | {xs(r.finder_borders)} | {verdict} |"
        )
    return "\n".join(lines)


# --- the protocol's own checks: the pin's gain and the step ---------------------------------------
# a sample of the surface re-measured with the pin at a third of its gain and at half the step
SAMPLE_BETAS = (0.64, 0.675)
SAMPLE_D31 = (1.7, 1.8, 2.3, 2.6, 2.9)  # on the first pass's grid (variant_rows pairs by D)


@dataclass
class VariantRow:
    """One sampled probe measured by the surface's protocol and by a variant of it."""

    variant: str
    beta: float
    d31: float
    drift: float | None  # rad per cycle, the surface's protocol
    other: float | None  # the variant's

    @property
    def diff(self) -> float | None:
        return None if self.drift is None or self.other is None else self.other - self.drift


def variant_rows(
    base: DriftSurface, variants: dict[str, DriftSurface], floor_rad: float
) -> tuple[list[VariantRow], bool]:
    """Each variant's probes beside the same (beta, D) of `base`; ok when every difference is
    within `floor_rad` (the noise floor the surface claims)."""
    rows: list[VariantRow] = []
    for name, s in variants.items():
        for p in s.points:
            q = next((x for x in base.points_at(p.beta) if abs(x.pin_d31 - p.pin_d31) < 1e-9), None)
            rows.append(
                VariantRow(name, p.beta, p.pin_d31, None if q is None else q.drift, p.drift)
            )
    ok = all(r.diff is not None and abs(r.diff) <= floor_rad for r in rows)
    return rows, ok


def variant_table(rows: list[VariantRow]) -> str:
    lines = [
        "| variant | β | D | drift (mrad/cycle) | variant's | difference |",
        "|---|---|---|---|---|---|",
    ]
    for r in rows:

        def m(x: float | None) -> str:
            return "n/a" if x is None else f"{1e3 * x:+.2f}"

        lines.append(
            f"| {r.variant} | {r.beta:g} | {r.d31:.2f} | {m(r.drift)} | {m(r.other)} | "
            f"{m(r.diff)} |"
        )
    return "\n".join(lines)


# --- the fourth check: +-10% of each calibrated parameter ---------------------------------------
# the mechanism's betas: the fast end (tripod and metachronal side), the bistable middle, the
# slow end
ROBUST_BETAS = (0.62, 0.655, 0.70)


def robust_surfaces(
    betas: Sequence[float],
    *,
    cache: ResultCache,
    backend: Backend,
    config: SurfaceConfig | None = None,
    params: ModelParams | None = None,
    progress: bool = True,
    **conditions: Any,
) -> dict[str, DriftSurface]:
    """The surface over `betas` on the default and at 0.9 and 1.1 of each calibrated parameter
    (`claims.CALIBRATED`, the finder's robustness check's list), by name; `conditions`: what
    `drift_surface` takes of the probes' conditions (body_mass_g, slope_deg, numerics)."""
    from sim_core.paper.claims import CALIBRATED, SCALES, scaled_values
    from sim_core.paper.surface import drift_surface

    base = params or ModelParams()
    variants = [("default", base)] + [
        (name, base.replace(**u)) for name, u in scaled_values(base, CALIBRATED, SCALES)
    ]
    return {
        name: drift_surface(
            betas,
            cache=cache,
            backend=backend,
            config=config,
            params=p,
            progress=progress,
            **conditions,
        )
        for name, p in variants
    }


def robust_table(surfaces: dict[str, DriftSurface]) -> str:
    """Per variant and beta the stable zeros in the window (unresolved with '?'), and how far
    the default's stable zeros moved (the nearest stable zero of the variant; 'gone' if none
    within 0.15 rad)."""
    base = surfaces["default"]
    betas = sorted(base.betas)
    lines = ["| variant | " + " | ".join(f"β {b:g}" for b in betas) + " | largest move |",
             "|---|" + "---|" * (len(betas) + 1)]  # fmt: skip
    for name, s in surfaces.items():
        cells, moves = [], []
        for b in betas:
            zs = [z for z in s.zeros_at(b) if z.stable and WINDOW[0] <= z.d31 <= WINDOW[1]]
            cells.append(", ".join(f"{z.d31:.2f}{'' if z.resolved else '?'}" for z in zs) or "none")
            for z0 in (z for z in base.zeros_at(b) if z.stable and WINDOW[0] <= z.d31 <= WINDOW[1]):
                near = [abs(z.d31 - z0.d31) for z in zs]
                moves.append(min(near) if near and min(near) <= 0.15 else None)
        gone = sum(m is None for m in moves)
        worst = max((m for m in moves if m is not None), default=0.0)
        move = f"{worst:.3f} rad" + (f"; {gone} gone" if gone else "")
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {move} |")
    return "\n".join(lines)
