"""The drift surface: the drift of Delta31 per gait cycle, d(Delta31; beta), read from walks
held at each Delta31.

Why. The model's stability story is this one function: its zeros are the gaits (a negative
slope: stable), its near-zeros the ghosts, and where two zeros meet as beta moves is a fold.
Free walking (the fixed-point finder, `finder`) sees only where runs end; a walk
held at Delta31 = D shows d at every D, stable and unstable zeros alike, for a fixed price.

How. Resets stay on (eq. 4); a weak pin (`RunSpec.pin_d31`, `cpg.pin`) on the fore and hind
oscillators holds Delta31 = Delta53 near D. S = (phi5 + phi6 - phi1 - phi2) / 4 moves only by
the resets and the pin, so on a periodic pinned walk the resets' drift per cycle,
`gait.drift_per_cycle` of the mean jumps e1..e6, is the free drift at D to first order in the
pin's small push (shared/notes/drift-surface.md). The abscissa is Delta31 sampled after leg-1
touchdowns, as free runs are sampled, not D: where the fore legs land late (D <= 1.5) the
sample leaves D, and such probes are kept in the data but not used for zeros.

What is claimed. A drift counts as nonzero only outside the noise floor
(`SurfaceConfig.floor_rad`, the pin's own bias, or 3 standard errors). A zero lies between two
such probes of opposite sign; it is `resolved` when they are at most `resolve_width_rad` apart
and the raw drift crosses zero once between them (placed there by linear interpolation), else
it is reported with its bracket and `resolved=False`. A band inside the floor that returns to
the same sign is a `NearZero` (a tangency, a ghost or a narrow pair of zeros: the surface cannot
tell, the finder's free runs can). Bisection (`bisection_probes`) halves the spacing near every
zero and dip of |d|; a last pass (`refinement_probes`) probes every unresolved
bracket and band finer and longer. Nothing is guessed.
"""

from __future__ import annotations

import itertools
import math
import tempfile
from collections.abc import Callable, Mapping, Sequence
from typing import Any, NamedTuple

import numpy as np

from sim_core.contract.choice import changed_leaves
from sim_core.contract.surface import (
    Branch,
    DriftSurface,
    Fold,
    NearZero,
    SurfaceConfig,
    SurfacePoint,
    SurfaceZero,
    grid,
)
from sim_core.contract.template import RunTemplate
from sim_core.model.gait import angle_diff, circular_mean, drift_per_cycle, phase_jumps
from sim_core.model.params import ModelParams, phi_aep
from sim_core.model.spec import RunSpec
from sim_core.runs.backends import Backend, Executor, InlineBackend, RunStats, run_tasks
from sim_core.runs.cache import ResultCache
from sim_core.runs.tasks import execute_chunk, run_task


# --- the probes ---------------------------------------------------------------------------------
class Probe(NamedTuple):
    """One pinned walk: at duty factor beta, held at D (rad), averaged over average_s (s)."""

    beta: float
    d: float
    average_s: float


def probe_spec(probe: Probe, cfg: SurfaceConfig, template: RunTemplate | None = None) -> RunSpec:
    """The pinned run of `probe` on `template` (every field of the run but the per-run ones;
    None: RunSpec's defaults): it starts on the gait family member D (eqs. 5-6) and walks
    `cfg.settle_s` plus its averaging time."""
    return (template or RunTemplate()).spec(
        beta=probe.beta,
        d31_init=probe.d,
        pin_d31=probe.d,
        pin_gain_per_s=cfg.gain_per_s,
        duration_s=cfg.settle_s + probe.average_s,
    )


def grid_probes(betas: Sequence[float], cfg: SurfaceConfig) -> list[Probe]:
    """The first pass: every beta x `cfg.d31_grid`, beta outer."""
    return [Probe(b, d, cfg.average_s) for b in betas for d in cfg.d31_grid]


def refinement_probes(
    surface: DriftSurface, cfg: SurfaceConfig, only: Sequence[float] | None = None
) -> list[Probe]:
    """The last pass: probes every `cfg.refine_step` inside each unresolved zero's bracket
    and near-zero band (from a little below it: the sample sits above D), averaged over
    `cfg.refine_average_s`; D values already probed at that beta are skipped; only at the
    betas `only` where that is given."""
    out: list[Probe] = []
    for b in surface.betas:
        if only is not None and not any(abs(b - x) < 1e-9 for x in only):
            continue
        done = {round(p.pin_d31, 6) for p in surface.points_at(b)}
        spans = [(z.lo, z.hi) for z in surface.zeros_at(b) if not z.resolved]
        spans += [(n.lo, n.hi) for n in surface.near_zeros if abs(n.beta - b) < 1e-9]
        for lo, hi in spans:
            for d in grid(lo - 2 * cfg.refine_step, hi, cfg.refine_step):
                if round(d, 6) not in done:
                    done.add(round(d, 6))
                    out.append(Probe(b, round(d, 6), cfg.refine_average_s))
    return out


def bisection_probes(surface: DriftSurface, cfg: SurfaceConfig) -> list[Probe]:
    """One round of bisection, averaged `cfg.average_s` as the first pass: a probe in the
    middle of every gap wider than `cfg.resolve_width_rad` between neighbouring probed D
    inside every zero's bracket, and on either side of every dip of |d| (a probe whose |d| is
    no larger than its neighbours', all three of one sign), where a narrow pair of zeros may
    hide. A coarse first
    pass so pays a finer spacing only where the drift changes sign or dips."""
    out: list[Probe] = []
    wide = cfg.resolve_width_rad + 1e-9
    for b in surface.betas:
        pts = sorted(
            (p for p in surface.points_at(b) if p.usable and p.drift is not None),
            key=lambda p: p.pin_d31,
        )
        pins = [round(p.pin_d31, 6) for p in pts]
        by_d31 = {p.d31: p.pin_d31 for p in pts}
        gaps: list[tuple[float, float]] = []
        for z in surface.zeros_at(b):
            lo, hi = by_d31.get(z.lo, z.lo), by_d31.get(z.hi, z.hi)
            inside = [d for d in pins if lo - 1e-9 <= d <= hi + 1e-9]
            gaps += list(itertools.pairwise(inside))
        d = [float(p.drift or 0.0) for p in pts]
        for k in range(1, len(pts) - 1):
            one_sign = (d[k - 1] > 0) == (d[k] > 0) == (d[k + 1] > 0)  # no zero beside it
            if one_sign and abs(d[k]) <= min(abs(d[k - 1]), abs(d[k + 1])):
                gaps += [(pins[k - 1], pins[k]), (pins[k], pins[k + 1])]
        for lo, hi in gaps:
            if hi - lo > wide:
                out.append(Probe(b, round(0.5 * (lo + hi), 6), cfg.average_s))
    return list(dict.fromkeys(out))


def _jumps(
    tds: Sequence[Sequence[float]],
    phases: Sequence[Sequence[float]],
    aep: float,
    a: float,
    b: float,
) -> np.ndarray:
    """(6,) mean jump of each leg's touchdowns after `a` and before `b` (`gait.phase_jumps`
    on the touchdowns before `b`)."""
    keep = [np.asarray(t, dtype=float) < b for t in tds]
    times = [np.asarray(t, dtype=float)[k] for t, k in zip(tds, keep, strict=True)]
    phis = [np.asarray(ph, dtype=float)[k] for ph, k in zip(phases, keep, strict=True)]
    return phase_jumps(times, phis, aep, a)


def read_probe(probe: Probe, result: dict[str, Any], cfg: SurfaceConfig) -> SurfacePoint:
    """A probe's numbers from its task result (`execute_chunk`: touchdowns and phases)."""
    beta, d = probe.beta, probe.d
    failed = result.get("failure")
    if failed or "touchdowns_s" not in result:
        why = f"run failed: {failed}" if failed else "no events recorded"
        return SurfacePoint(
            beta=beta,
            pin_d31=d,
            d31=None,
            spread=None,
            drift=None,
            drift_se=None,
            jumps=[None] * 6,
            cycles=0,
            usable=False,
            why=why,
        )
    tds, phases = result["touchdowns_s"], result["touchdown_phases"]
    aep, t0, t1 = phi_aep(beta), cfg.settle_s, cfg.settle_s + probe.average_s + 1e-9
    jumps = _jumps(tds, phases, aep, t0, t1)
    drift = float(drift_per_cycle(jumps))
    nblocks = max(1, round(probe.average_s / cfg.block_s))
    edges = np.linspace(t0, t1, nblocks + 1)
    blocks = np.array(
        [drift_per_cycle(_jumps(tds, phases, aep, a, b)) for a, b in itertools.pairwise(edges)]
    )
    blocks = blocks[np.isfinite(blocks)]
    se = float(np.std(blocks, ddof=1) / math.sqrt(blocks.size)) if blocks.size > 1 else None
    times = np.asarray(result.get("d31_times_s", []), dtype=float)
    values = np.asarray(result.get("d31", []), dtype=float)[times >= t0]
    if values.size == 0 or not math.isfinite(drift):
        return SurfacePoint(
            beta=beta,
            pin_d31=d,
            d31=None,
            spread=None,
            drift=None,
            drift_se=se,
            jumps=_opt(jumps),
            cycles=int(values.size),
            usable=False,
            why="no touchdowns of a fore or hind leg after settling",
        )
    mean = circular_mean(values)
    spread = float(np.max(np.abs(angle_diff(values, mean))))
    why = ""
    if spread > cfg.periodic_tol_rad:
        why = f"not periodic: Delta31 spreads {spread:.3f} rad (> {cfg.periodic_tol_rad:g})"
    elif abs(float(angle_diff(mean, d))) > cfg.off_pin_tol_rad:
        why = f"walks {mean:.3f}, off its pin {d:.3f} by more than {cfg.off_pin_tol_rad:g} rad"
    return SurfacePoint(
        beta=beta,
        pin_d31=d,
        d31=mean,
        spread=spread,
        drift=drift,
        drift_se=se,
        jumps=_opt(jumps),
        cycles=int(values.size),
        usable=not why,
        why=why,
    )


def _opt(x: np.ndarray) -> list[float | None]:
    return [float(v) if math.isfinite(v) else None for v in x]


# --- what the curve says ------------------------------------------------------------------------
def _floor(p: SurfacePoint, cfg: SurfaceConfig) -> float:
    return max(cfg.floor_rad, 3.0 * (p.drift_se or 0.0))


def zeros_of(
    points: Sequence[SurfacePoint], cfg: SurfaceConfig
) -> tuple[list[SurfaceZero], list[NearZero]]:
    """The zeros and near-zero bands of one beta's curve (usable probes, by sampled Delta31)."""
    pts = sorted((p for p in points if p.usable), key=lambda p: float(p.d31 or 0.0))
    zeros: list[SurfaceZero] = []
    near: list[NearZero] = []
    last: int | None = None  # the last probe whose drift cleared the floor
    for j, p in enumerate(pts):
        d = float(p.drift or 0.0)
        if abs(d) <= _floor(p, cfg):
            continue
        if last is not None:
            q = pts[last]
            dq, xq, xp = float(q.drift or 0.0), float(q.d31 or 0.0), float(p.d31 or 0.0)
            if (dq > 0) != (d > 0):
                # the raw drift's crossing between the two floor-clearing probes: resolved
                # when it crosses once and the bracket is narrow (`resolve_width_rad`)
                cross = _single_crossing(pts[last : j + 1])
                zeros.append(
                    SurfaceZero(
                        beta=p.beta,
                        d31=0.5 * (xq + xp) if cross is None else cross,
                        lo=xq,
                        hi=xp,
                        stable=dq > 0 > d,
                        slope=(d - dq) / (xp - xq) if xp > xq else None,
                        resolved=cross is not None and xp - xq <= cfg.resolve_width_rad + 1e-9,
                    )
                )
            elif j > last + 1:
                band = pts[last + 1 : j]
                near.append(
                    NearZero(
                        beta=p.beta,
                        lo=xq,
                        hi=xp,
                        sign=1 if d > 0 else -1,
                        min_abs_drift=min(abs(float(b.drift or 0.0)) for b in band),
                    )
                )
        last = j
    return zeros, near


def _single_crossing(pts: Sequence[SurfacePoint]) -> float | None:
    """Where the raw drift crosses zero, interpolated, if it crosses exactly once in `pts`."""
    xs = [float(p.d31 or 0.0) for p in pts]
    ds = [float(p.drift or 0.0) for p in pts]
    hits = [k for k in range(len(ds) - 1) if (ds[k] >= 0) != (ds[k + 1] >= 0)]
    if len(hits) != 1:
        return None
    k = hits[0]
    return xs[k] + (xs[k + 1] - xs[k]) * ds[k] / (ds[k] - ds[k + 1])


def branches_of(
    zeros: Sequence[SurfaceZero], betas: Sequence[float], cfg: SurfaceConfig
) -> tuple[list[Branch], list[Fold]]:
    """Stable zeros linked across the grid's neighbouring betas, and where each branch ends
    inside the grid (a fold, to within the grid's beta spacing)."""
    bs = sorted(betas)
    stable = {
        b: sorted((z for z in zeros if z.stable and abs(z.beta - b) < 1e-9), key=lambda z: z.d31)
        for b in bs
    }
    used: set[tuple[float, int]] = set()
    branches: list[Branch] = []
    folds: list[Fold] = []
    for k, b in enumerate(bs):
        for i, z in enumerate(stable[b]):
            if (b, i) in used:
                continue
            chain = [z]
            used.add((b, i))
            for b2 in bs[k + 1 :]:
                prev = chain[-1]
                cand = [
                    (abs(z2.d31 - prev.d31), m)
                    for m, z2 in enumerate(stable[b2])
                    if (b2, m) not in used and abs(z2.d31 - prev.d31) <= cfg.link_tol_rad
                ]
                if not cand:
                    break
                m = min(cand)[1]
                used.add((b2, m))
                chain.append(stable[b2][m])
            branches.append(
                Branch(
                    betas=[c.beta for c in chain],
                    d31=[c.d31 for c in chain],
                    resolved=[c.resolved for c in chain],
                )
            )
            first, last = bs.index(chain[0].beta), bs.index(chain[-1].beta)
            if first > 0:
                folds.append(
                    Fold(
                        beta_lo=bs[first - 1],
                        beta_hi=chain[0].beta,
                        d31=chain[0].d31,
                        side="ends as beta falls",
                        resolution=chain[0].beta - bs[first - 1],
                        resolved=chain[0].resolved,
                    )
                )
            if last < len(bs) - 1:
                folds.append(
                    Fold(
                        beta_lo=chain[-1].beta,
                        beta_hi=bs[last + 1],
                        d31=chain[-1].d31,
                        side="ends as beta rises",
                        resolution=bs[last + 1] - chain[-1].beta,
                        resolved=chain[-1].resolved,
                    )
                )
    return branches, folds


def assemble(
    betas: Sequence[float],
    points: Sequence[SurfacePoint],
    cfg: SurfaceConfig,
    *,
    sim_s: float,
    body_mass_g: float = 3.0,
    slope_deg: float = 0.0,
    ground: str = "constraint",
    params: Mapping[str, Any] | None = None,
) -> DriftSurface:
    """The surface's zeros, bands, branches and folds from its probes; `params`: the model's
    leaves off their defaults it records (`changed_leaves`; None: the defaults)."""
    zeros: list[SurfaceZero] = []
    near: list[NearZero] = []
    for b in betas:
        z, n = zeros_of([p for p in points if abs(p.beta - b) < 1e-9], cfg)
        zeros += z
        near += n
    branches, folds = branches_of(zeros, betas, cfg)
    return DriftSurface(
        config=cfg,
        betas=list(betas),
        points=list(points),
        zeros=zeros,
        near_zeros=near,
        branches=branches,
        folds=folds,
        sim_s=sim_s,
        body_mass_g=body_mass_g,
        slope_deg=slope_deg,
        ground=ground,
        params=dict(params or {}),
    )


def drift_surface(
    betas: Sequence[float],
    *,
    cache: ResultCache | None = None,
    backend: Backend | None = None,
    config: SurfaceConfig | None = None,
    params: ModelParams | None = None,
    template: RunTemplate | None = None,
    refine: bool = True,
    last_pass_betas: Sequence[float] | None = None,
    progress: bool | str = True,
    stats: RunStats | None = None,
    on_progress: Callable[[float], None] | None = None,
    executor: Executor = execute_chunk,
) -> DriftSurface:
    """The drift surface over `betas` x `config.d31_grid`: every probe run through
    `sim_core.runs` (cached by content, so an interrupted surface resumes; local pool or Dask).

    Args:
        betas: duty factors (nb,).
        cache, backend: where results are kept (None: a private temporary folder) and where
            probes run (None: in this process, one batch after another).
        config: the probes' protocol (`SurfaceConfig()` if None).
        params: model parameters (defaults if None); its ground names the surface's.
        template: every field of the probes' runs but the per-run ones (`RunTemplate`: the
            body mass, slope, numerics, phase resetting ...; RunSpec's defaults if None); a
            probe adds its beta, start, pin and length (`probe_spec`).
        refine: bisect every zero's bracket and every dip of |d| down to
            `resolve_width_rad` (`bisection_probes`, at most `bisect_rounds` rounds), then
            (`band_pass`) probe finer and longer inside every zero still unresolved and every
            near-zero band (`refinement_probes`).
        last_pass_betas: where that last pass runs (None: at every beta); `reproduce` runs it
            only where a row reads the zeros themselves, and walks decide the other cells.
        progress: a tqdm bar on stderr (a str: its label); stats: accumulates what was
            computed and read back.
        on_progress: called with the share of probes done (0..1) as chunks finish.
        executor: what runs a chunk of tasks (`execute_chunk`; tests pass a stand-in).

    Returns:
        The `DriftSurface`: per probe the sampled Delta31, drift per cycle (rad) with its
        standard error and the mean jumps e1..e6; per beta the zeros and near-zero bands;
        over beta the stable branches and their folds.
    """
    (surface,) = drift_surfaces(
        betas, [template or RunTemplate()], cache=cache, backend=backend, config=config,
        params=params, refine=refine, last_pass_betas=last_pass_betas, progress=progress,
        stats=stats, on_progress=on_progress, executor=executor,
    )  # fmt: skip
    return surface


def drift_surfaces(
    betas: Sequence[float],
    templates: Sequence[RunTemplate],
    *,
    cache: ResultCache | None = None,
    backend: Backend | None = None,
    config: SurfaceConfig | None = None,
    params: ModelParams | None = None,
    refine: bool = True,
    last_pass_betas: Sequence[float] | None = None,
    progress: bool | str = True,
    stats: RunStats | None = None,
    on_progress: Callable[[float], None] | None = None,
    executor: Executor = execute_chunk,
) -> list[DriftSurface]:
    """`drift_surface` on each of `templates` (an atlas's rows: a mass or slope each), every
    pass of all of them handed to the backend at once: one pool or cluster stays busy across
    an atlas's rows."""
    if cache is None:
        with tempfile.TemporaryDirectory(prefix="surface-") as tmp:
            return drift_surfaces(
                betas, templates, cache=ResultCache(tmp), backend=backend, config=config,
                params=params, refine=refine, last_pass_betas=last_pass_betas,
                progress=progress, stats=stats, on_progress=on_progress, executor=executor,
            )  # fmt: skip
    backend = backend or InlineBackend()
    cfg = config or SurfaceConfig()
    p = params or ModelParams()
    conds = list(templates)

    def run(probes: list[list[Probe]], share: tuple[float, float]) -> list[list[SurfacePoint]]:
        tasks = [
            [run_task(probe_spec(q, cfg, c), p) for q in qs]
            for c, qs in zip(conds, probes, strict=True)
        ]
        flat = [t for ts in tasks for t in ts]
        a, b = share
        report = None if on_progress is None else (lambda x: on_progress(a + (b - a) * x))
        results, st = run_tasks(
            flat, cache, backend, cfg.chunk_size, progress, executor, on_progress=report
        )
        if stats is not None:
            for name in ("tasks", "computed", "cached", "compute_s"):
                setattr(stats, name, getattr(stats, name) + getattr(st, name))
        return [
            [read_probe(q, results[t.key], cfg) for q, t in zip(qs, ts, strict=True)]
            for qs, ts in zip(probes, tasks, strict=True)
        ]

    def surfaces() -> list[DriftSurface]:
        held = [c.spec() for c in conds]  # each template's fields, typed
        return [
            assemble(betas, pts, cfg, sim_s=_sim_s(qs, cfg), ground=p.contact.ground,
                     body_mass_g=h.body_mass_g, slope_deg=h.slope_deg, params=leaves)
            for h, pts, qs in zip(held, points, probes, strict=True)
        ]  # fmt: skip

    leaves = changed_leaves(p)  # what each surface records of the model
    probes = [grid_probes(betas, cfg) for _ in conds]
    points = run(probes, (0.0, 0.6 if refine else 1.0))
    out = surfaces()
    if not refine:
        return out

    def last_pass(sf: DriftSurface, c: SurfaceConfig) -> list[Probe]:
        return refinement_probes(sf, c, last_pass_betas)

    passes = [bisection_probes] * cfg.bisect_rounds + [last_pass] * cfg.band_pass
    for k, step in enumerate(passes):
        extra = [step(sf, cfg) for sf in out]
        if not any(extra):
            continue
        a = 0.6 + 0.4 * k / len(passes)
        for pts, new in zip(points, run(extra, (a, a + 0.4 / len(passes))), strict=True):
            pts += new
        for qs, e in zip(probes, extra, strict=True):
            qs += e
        out = surfaces()
    return out


def _sim_s(probes: Sequence[Probe], cfg: SurfaceConfig) -> float:
    return sum(cfg.settle_s + q.average_s for q in probes)
