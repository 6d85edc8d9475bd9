"""The paper's Figs. 5-9 and the phase-reset ablation as task lists plus analyses.

For each figure, `figure_tasks` lists the simulations it needs (deterministic: the same config
and parameters give the same tasks, hence the same cache keys) and `analyse` turns their results
into the data behind the figure (JSON-able), its CSV tables, and a small summary the
reproduction table reads. Nothing here simulates or draws; `sim_core.paper.reproduce` runs the tasks
and `sim_core.paper.plots` draws.

Protocol choices the paper leaves open are fields of `ReproduceConfig`, each with the reason.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import asdict, dataclass, field, replace
from typing import Any

import numpy as np

from sim_core.contract.finder import Cell, FinderConfig, Probe
from sim_core.contract.surface import SHORT_PROBES, SurfaceConfig, WalkConfig, grid
from sim_core.contract.values import FIGURES, METACHRONAL_BRANCH, PAPER, TRIPOD_BRANCH
from sim_core.model.gait import (
    angle_diff,
    circular_mean,
    classify_gait,
    settling,
    stance_intervals,
)
from sim_core.model.params import ModelParams
from sim_core.model.spec import RunSpec, spec_grid
from sim_core.paper.analysis import (
    branch_census,
    max_drift,
    sweep_summary,
)
from sim_core.paper.returnmap import initial_values
from sim_core.paper.search import probe_task
from sim_core.runs.tasks import Ramp, Task, ramp_task, run_task

BRANCH_TOL = 0.2  # rad: a settled Delta31 this close to the paper's branch counts as on it
MAP_BETAS = (0.64, 0.655, 0.675)  # Fig. 7's return maps (the paper's panels)


@dataclass(frozen=True)
class ReproduceConfig:
    """Sizes and protocol of every experiment (the paper states few of them)."""

    # Fig. 5's runs are the finder's starts at these betas (`fig5_tasks`: the same tasks, run
    # once): `finder.starts` (8; the paper used 3) spread over the circle, `finder.duration_s`
    # (40 s, ~360 strides at 0.70: past the tripod fold a start near pi slides for 30-60 s
    # through the ghost, docs/studies/gait_campaign3.md)
    fig5_betas: tuple[float, ...] = (0.62, 0.70)
    map_betas: tuple[float, ...] = MAP_BETAS  # Fig. 7
    # Fig. 5's runs stop here if they have settled (`RunSpec.stop_if_settled_s`: bit for bit a
    # run this long), else run on to `finder.duration_s`: 10 of the 16 have settled by 20 s,
    # on the finals they reach at 40 s (docs/NUMERICS.md, "reproduce within 5 minutes").
    fig5_try_s: float | None = FinderConfig().bisect_duration_s  # the finder's try, 20 s
    # Fig. 7's free runs (its own check: they end on the surface's stable zeros) stop at
    # `map_try_s` if settled. Read from the same 40 s runs cut at 30 s, every run settled by
    # then is settled at 40 s on the same final within 0.002 rad; a 20 s or 25 s try reads a
    # ghost at 2.97 (beta 0.655) as settled. Every one of the finder's 8 starts is kept: every
    # other one drops the two runs per beta that end off the surface's zeros (near 1.5 rad)
    # and turns the check's "no" into a "yes" (docs/NUMERICS.md, "reproduce within 5
    # minutes"). None: every run whole
    map_try_s: float | None = 30.0
    # Figs. 7-8 are read from the drift surface (`paper.surface`, protocol in SurfaceConfig)
    # over these 15 betas, containing the Fig. 7 betas: 0.005 apart from 0.64 to 0.68 (both
    # of the paper's transitions, 0.645 and 0.67, and our tripod's end, 0.645), 0.01 below
    # and 0.02 above, where no range end of ours or the paper's lies (docs/NUMERICS.md,
    # "reproduce within 5 minutes")
    surface_betas: tuple[float, ...] = (
        0.60, 0.61, 0.62, 0.63, *(round(0.64 + 0.005 * k, 3) for k in range(9)), 0.70, 0.72,
    )  # fmt: skip
    # short probes (`contract.surface.SHORT_PROBES`: measured there against the longer ones)
    surface: SurfaceConfig = SHORT_PROBES
    # the surface's last pass only at these betas (None: every beta): the Fig. 7 betas, whose
    # zeros the rows read; elsewhere a cell's unresolved spans are decided by the walks
    # (`walks`), as an atlas decides its cells (docs/NUMERICS.md, "reproduce within 5 minutes")
    last_pass_betas: tuple[float, ...] | None = MAP_BETAS
    # the mechanism figure's surface on the paper's ground (`surface_repro.MECHANISM_BETAS`):
    # its first pass only, no bisection or last pass: the figure draws the drift's curves and
    # no row reads its zeros (the refinement was 3/4 of its cost, at twice a constraint-ground
    # probe's cost per simulated second)
    mechanism_refine: bool = False
    # Figs. 7-8 decided by settled free walks where the surface cannot tell (issue 52, point
    # 1): the atlas's walks (`surface_walks.WalkConfig`: a 20 s try, 40 s where unsettled) at
    # every cell whose unresolved zero or near-zero band could change its gaits, and walks off
    # the grid beside each range end (`surface_repro.off_grid_checks`). None: the surface alone
    walks: WalkConfig | None = field(default_factory=WalkConfig)
    # the settled fixed-point finder (`finder`), now the independent check of the
    # surface (`surface-check`, `finder-check`); its starts and durations, chosen from
    # measurement in `FinderConfig`, also make Fig. 5's and Fig. 7's free runs
    finder: FinderConfig = field(default_factory=FinderConfig)
    # the finder's Fig. 8 grid: 17 betas, 0.005 apart, containing the Fig. 7 betas
    bif_betas: tuple[float, ...] = tuple(round(0.62 + 0.005 * k, 3) for k in range(17))
    beta_high: float = 0.70
    beta_low: float = 0.62
    hold_s: float = 5.0  # settle on the starting gait before ramping, and again at the end
    ramp_s: float = 30.0  # each way: 0.08 in beta over ~ 300 strides (2.7e-4 per stride)
    rate_factor: float = 2.0  # the ramp-rate check runs the beta ramp this much slower
    # transitions may move by this much (in beta) when the rate is halved: the Fig. 8 spacing
    rate_tolerance: float = 0.005
    sweep_beta: float = 0.66  # Figs. 9a, 9b (paper)
    # Fig. 9 ranges are not stated in the text; ours span light to heavy, downhill to uphill
    mass_range_g: tuple[float, float] = (1.0, 6.0)
    slope_range_deg: tuple[float, float] = (-20.0, 20.0)
    start_d31: float = METACHRONAL_BRANCH  # every sweep starts on the metachronal side ...
    # ... except Fig. 6a's second protocol: "we reduced the locomotion speed by increasing beta
    # from 0.62 to 0.7" after a stable gait at 0.62, the paper's tripod; where both gaits live
    # at 0.62 the ideal tripod (pi, Sec. II B 5) is the start that walks the paper's
    tripod_start_d31: float = math.pi
    ablation_betas: tuple[float, ...] = (0.62, 0.70)
    ablation_inits: int = 8
    ablation_duration_s: float = 3.0
    footprint_window_s: float = 1.0  # Fig. 6b shows +- this around the transition
    chunk_size: int = 8
    name: str = field(default="full", compare=False)

    @classmethod
    def quick(cls) -> ReproduceConfig:
        """Tiny sizes for tests and smoke runs: the machinery, not the science."""
        return cls(
            finder=FinderConfig.quick(),
            bif_betas=(0.62, 0.64, 0.655, 0.675, 0.70), hold_s=0.3,
            surface_betas=(0.62, 0.64, 0.655, 0.675, 0.70),
            surface=SurfaceConfig(d31_grid=grid(1.5, 3.3, 0.2), settle_s=0.5, average_s=0.5,
                                  block_s=0.25, bisect_rounds=0),
            ramp_s=0.6, ablation_betas=(0.66,), ablation_inits=2, ablation_duration_s=0.5,
            footprint_window_s=0.3, fig5_try_s=None, walks=WalkConfig(try_s=0.5, duration_s=1.0),
            map_try_s=None, name="quick",
        )  # fmt: skip

    @classmethod
    def dense_protocol(cls) -> ReproduceConfig:
        """The protocol of 2026-12-02 (552-600 s on 2 cores from an empty cache): 19 surface
        betas, the last pass at every beta, Fig. 7's free runs 40 s each (no try). Kept to
        re-validate the default against (`benchmarks/reproduce_protocols.py`)."""
        return cls(
            surface_betas=(
                0.60, 0.61, *(round(0.62 + 0.005 * k, 3) for k in range(13)), 0.69, 0.70,
                0.71, 0.72,
            ),
            last_pass_betas=None, map_try_s=None, name="dense",
        )  # fmt: skip

    @classmethod
    def long_protocol(cls) -> ReproduceConfig:
        """The protocol before issue 54 (558-573 s on 2 cores from an empty cache): 25
        surface betas 0.005 apart, probes averaged 1 s and 2.5 s, the mechanism's surface
        refined, every free run 40 s. Kept to re-validate the faster default against
        (`benchmarks/reproduce_protocols.py`)."""
        return cls(
            surface_betas=tuple(round(0.60 + 0.005 * k, 3) for k in range(25)),
            surface=SurfaceConfig(), mechanism_refine=True, fig5_try_s=None, map_try_s=None,
            last_pass_betas=None, name="long",
        )  # fmt: skip

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    def with_(self, **kw: Any) -> ReproduceConfig:
        return replace(self, **kw)


# --- task lists ---------------------------------------------------------------------------------
def _runs(
    betas: tuple[float, ...], n: int, duration_s: float, p: ModelParams, **kw: Any
) -> list[Task]:
    return [
        run_task(s, p) for s in spec_grid(betas, initial_values(n), duration_s=duration_s, **kw)
    ]


def spread_tasks(
    betas: tuple[float, ...], cfg: ReproduceConfig, p: ModelParams, try_s: float | None = None
) -> list[Task]:
    """Free runs from the finder's spread starts at each of `betas` (beta outer), as the
    finder asks for them (`probe_task`); with `try_s`, each a try that stops there if it has
    settled."""
    return [probe_task(Cell(beta), Probe(float(x), cfg.finder.duration_s, try_s), p)
            for beta in betas for x in initial_values(cfg.finder.starts)]  # fmt: skip


def fig5_tasks(cfg: ReproduceConfig, p: ModelParams) -> list[Task]:
    """Fig. 5's runs: the spread starts at each of `fig5_betas`."""
    return spread_tasks(cfg.fig5_betas, cfg, p, cfg.fig5_try_s)


def beta_ramp(cfg: ReproduceConfig, slower: bool = False, up: bool = False) -> Ramp:
    """Fig. 6a's triangle: from 0.70 down and back (`up`: from 0.62 up and back)."""
    ramp_s = cfg.ramp_s * (cfg.rate_factor if slower else 1.0)
    ends = (cfg.beta_low, cfg.beta_high) if up else (cfg.beta_high, cfg.beta_low)
    return Ramp("beta", *ends, cfg.hold_s, ramp_s)


def sweep_ramps(cfg: ReproduceConfig) -> dict[str, Ramp]:
    m, s = cfg.mass_range_g, cfg.slope_range_deg
    return {
        "fig9a": Ramp("body_mass_g", m[0], m[1], cfg.hold_s, cfg.ramp_s),
        "fig9b": Ramp("slope_deg", s[0], s[1], cfg.hold_s, cfg.ramp_s),
    }


def _ramp_task(r: Ramp, cfg: ReproduceConfig, p: ModelParams) -> Task:
    beta = r.start if r.param == "beta" else cfg.sweep_beta
    up = r.param == "beta" and r.turn > r.start  # Fig. 6a's second protocol
    d31 = cfg.tripod_start_d31 if up else cfg.start_d31
    return ramp_task(r, RunSpec(beta=beta, d31_init=d31), p)


def figure_tasks(fig: str, cfg: ReproduceConfig, p: ModelParams) -> list[Task]:
    """Every simulation figure `fig` needs (Fig. 8 also needs the Fig. 6a sweep it overlays)."""
    if fig == "5":
        return fig5_tasks(cfg, p)
    if fig == "6":
        return [_ramp_task(beta_ramp(cfg, s, u), cfg, p) for u in (False, True)
                for s in (False, True)]  # fmt: skip
    if fig == "7":  # the free runs its return maps are checked against (the surface aside)
        return spread_tasks(cfg.map_betas, cfg, p, cfg.map_try_s)
    if fig == "8":
        return [_ramp_task(beta_ramp(cfg, up=u), cfg, p) for u in (False, True)]
    if fig == "9":
        return [_ramp_task(r, cfg, q) for _, r, q in _fig9_runs(cfg, p)]
    if fig == "ablation":
        return _runs(cfg.ablation_betas, cfg.ablation_inits, cfg.ablation_duration_s, p,
                     phase_reset=False)  # fmt: skip
    raise ValueError(f"unknown figure {fig!r}; choose from {FIGURES}")


# --- analyses -----------------------------------------------------------------------------------
Lookup = Callable[[Task], dict[str, Any]]
Csv = dict[str, tuple[list[str], list[list[Any]]]]


@dataclass
class FigureData:
    """One output figure: the data behind it, its CSV tables, the table's summary."""

    name: str  # file stem: fig5, fig6a, ...
    data: dict[str, Any]
    csv: Csv
    summary: dict[str, Any]


def _by_beta(tasks: list[Task], get: Lookup) -> dict[float, list[tuple[Task, dict[str, Any]]]]:
    out: dict[float, list[tuple[Task, dict[str, Any]]]] = {}
    for t in tasks:
        out.setdefault(t.run_spec().beta, []).append((t, get(t)))
    return out


def _fig5(cfg: ReproduceConfig, p: ModelParams, get: Lookup) -> list[FigureData]:
    runs = []
    rows: list[list[Any]] = []
    summary: dict[str, Any] = {}
    for beta, items in _by_beta(figure_tasks("5", cfg, p), get).items():
        finals: list[float | None] = []
        speeds = []
        for t, r in items:
            if r["error"] is None:  # THE settled rule (drift over a resolved last quarter)
                st = settling(r["d31"])
                final = st.final if st.settled else None
                gait = classify_gait(final, beta) if st.settled else "not settled"
            else:
                final, gait = None, "diverged"
            finals.append(final)
            if r["speed_cm_s"] is not None:
                speeds.append(r["speed_cm_s"])
            x0 = t.run_spec().d31_init
            runs.append({"beta": beta, "d31_init": x0, "final": final, "gait": gait, **r})
            rows += [[beta, x0, k, v] for k, v in enumerate(r["d31"])]
        target = TRIPOD_BRANCH if beta < 0.66 else METACHRONAL_BRANCH
        hit, n = branch_census(finals, target, BRANCH_TOL)
        near = [f for f in finals if f is not None and abs(angle_diff(f, target)) <= BRANCH_TOL]
        summary[str(beta)] = {
            "target_rad": target, "hits": hit, "runs": n,
            "branch_rad": circular_mean(near) if near else None,
            "finals": finals, "speed_cm_s": float(np.median(speeds)) if speeds else None,
        }  # fmt: skip
    csv: Csv = {"fig5": (["beta", "d31_init_rad", "cycle", "d31_rad"], rows)}
    return [FigureData("fig5", {"runs": runs, "summary": summary}, csv, summary)]


def _series_rows(tag: str, r: dict[str, Any]) -> list[list[Any]]:
    return [[tag, t, v, d] for t, v, d in zip(r["d31_times_s"], r["value"], r["d31"], strict=True)]


def _sweep(r: Ramp, res: dict[str, Any], cfg: ReproduceConfig) -> dict[str, Any]:
    beta = res["value"] if r.param == "beta" else cfg.sweep_beta  # as `_ramp_task` runs it
    s = sweep_summary(res["d31_times_s"], res["value"], res["d31"], r.start, r.turn, r.hold_s,
                      r.ramp_s, beta)  # fmt: skip
    return s | {"param": r.param, "ramp_s": r.ramp_s, "hold_s": r.hold_s, "error": res["error"]}


def _switch(leg: list[dict[str, Any]], after: str) -> float | None:
    """The swept value of the first transition into `after` on one leg of a sweep."""
    hits = [t["value"] for t in leg if t["after"] == after]
    return float(hits[0]) if hits else None


def _fig6(cfg: ReproduceConfig, p: ModelParams, get: Lookup) -> list[FigureData]:
    """The paper's two protocols: beta falls from 0.70 after a metachronal start, and rises
    from 0.62 after a tripod start (each ramp then returns to its start)."""
    ramps = {"full": beta_ramp(cfg), "half_rate": beta_ramp(cfg, slower=True)}
    ups = {"full": beta_ramp(cfg, up=True), "half_rate": beta_ramp(cfg, slower=True, up=True)}
    res = {k: get(_ramp_task(r, cfg, p)) for k, r in ramps.items()}
    res_up = {k: get(_ramp_task(r, cfg, p)) for k, r in ups.items()}
    sweeps = {k: _sweep(r, res[k], cfg) for k, r in ramps.items()}
    sweeps_up = {k: _sweep(r, res_up[k], cfg) for k, r in ups.items()}
    # the switch to the tripod as beta falls (first protocol's first leg) and back to the
    # metachronal as it rises (second protocol's first leg); keyed as the legs of a loop
    legs = {"first_leg": (sweeps, "tripod"), "second_leg": (sweeps_up, "metachronal")}
    at = {k: {leg: _switch(sw[k]["first_leg"], g) for leg, (sw, g) in legs.items()} for k in ramps}
    shift: dict[str, float | None] = {}
    at_zero: dict[str, float | None] = {}
    # slow passage through a saddle-node: the switch lags the fold by ~ rate^(2/3), so two
    # rates give the lag and the zero-rate limit (shown for information, never judged on)
    shrink = 1.0 - cfg.rate_factor ** (-2.0 / 3.0)
    for leg in legs:
        a, b = at["full"][leg], at["half_rate"][leg]
        shift[leg] = None if a is None or b is None else abs(a - b)
        at_zero[leg] = None if a is None or b is None else a - (a - b) / shrink
    moved = [s for s in shift.values() if s is not None]
    ok = bool(len(moved) == 2 and max(moved) < cfg.rate_tolerance)
    rate = {"shift": shift, "tolerance": cfg.rate_tolerance, "switch": at,
            "zero_rate": at_zero, "ok": ok}  # fmt: skip
    keys = ("d31_times_s", "value", "d31")
    series = {k: {key: res[k][key] for key in keys} for k in res}
    series |= {f"up_{k}": {key: res_up[k][key] for key in keys} for k in res_up}
    rows = [row for k in res for row in _series_rows(k, res[k])]
    rows += [row for k in res_up for row in _series_rows(f"up_{k}", res_up[k])]
    summary = {"sweep": sweeps["full"], "half_rate": sweeps["half_rate"],
               "sweep_up": sweeps_up["full"], "half_rate_up": sweeps_up["half_rate"],
               "rate_check": rate}  # fmt: skip
    fig6a = FigureData(
        "fig6a", {"series": series, **summary},
        {"fig6a": (["ramp", "time_s", "beta", "d31_rad"], rows)}, summary,
    )  # fmt: skip

    # Fig. 6b: footprints around the metachronal -> tripod switch of the decreasing-beta leg
    # (or, where there is none, the tripod -> metachronal switch of the increasing one)
    full, r = res["full"], ramps["full"]
    switch = [x for x in sweeps["full"]["first_leg"] if x["after"] == "tripod"]
    back = [x for x in sweeps_up["full"]["first_leg"] if x["after"] == "metachronal"]
    if switch:
        centre, how = switch[0]["time_s"], "detected metachronal-to-tripod transition"
    elif back:
        full, r = res_up["full"], ups["full"]
        centre, how = back[0]["time_s"], "detected tripod-to-metachronal transition (β rising)"
    else:  # no switch: where the ramp passes the paper's transition
        frac = (PAPER.transition_down - r.start) / (r.turn - r.start)
        centre = r.hold_s + frac * r.ramp_s
        how = f"no transition detected: the paper's beta {PAPER.transition_down}"
    w = cfg.footprint_window_s
    t0, t1 = max(0.0, centre - w), centre + w
    stance = stance_intervals(full["touchdowns_s"], full["liftoffs_s"], t0, t1)
    times = np.asarray(full["d31_times_s"])
    sel = (times >= t0) & (times <= t1)
    data = {"t0_s": t0, "t1_s": t1, "centre_s": centre, "centre": how, "stance": stance,
            "d31_times_s": times[sel].tolist(), "d31": np.asarray(full["d31"])[sel].tolist(),
            "beta": [float(r.schedule()(float(t))) for t in times[sel]]}  # fmt: skip
    rows = [[leg + 1, a, b] for leg, ivs in enumerate(stance) for a, b in ivs]
    fig6b = FigureData("fig6b", data, {"fig6b": (["leg", "touchdown_s", "liftoff_s"], rows)},
                       {"centre": how})  # fmt: skip
    return [fig6a, fig6b]


def _fig9_runs(cfg: ReproduceConfig, p: ModelParams) -> list[tuple[str, Ramp, ModelParams]]:
    """Fig. 9's sweeps (figure name, ramp, parameters), and Fig. 9b's again on the paper's
    ground: today's contact turns the body 90-100 deg downhill within 40-60 s, the paper's
    ground keeps it within 1 deg (docs/MODEL.md, "Slopes"), so only there does the sweep walk
    down and up the slope."""
    ramps = sweep_ramps(cfg)
    runs = [(name, r, p) for name, r in ramps.items()]
    if p.contact.ground != "penalty":
        runs.append(("fig9b", ramps["fig9b"], p.replace(**{"ground": "penalty"})))
    return runs


def _sweep_data(r: Ramp, res: dict[str, Any], cfg: ReproduceConfig) -> dict[str, Any]:
    """A Fig. 9 sweep's summary (with the largest heading the body reached) and series."""
    sweep = _sweep(r, res, cfg)
    heading = [abs(h) for h in res.get("heading_deg") or []]
    sweep["max_heading_deg"] = max(heading) if heading else None
    keys = ("d31_times_s", "value", "d31", "heading_deg")
    return {"sweep": sweep, "series": {k: res[k] for k in keys if k in res}}


def _fig9(cfg: ReproduceConfig, p: ModelParams, get: Lookup) -> list[FigureData]:
    figs: dict[str, FigureData] = {}
    for name, r, q in _fig9_runs(cfg, p):
        res = get(_ramp_task(r, cfg, q))
        data = _sweep_data(r, res, cfg)
        if name in figs:  # the same sweep on the paper's ground, beside it
            figs[name].data["paper_ground"] = data
            figs[name].summary["paper_ground"] = data["sweep"]
            continue
        data["beta"] = cfg.sweep_beta
        data["ground"] = q.contact.ground
        header = ["ramp", "time_s", r.param, "d31_rad"]
        rows = {name: (header, _series_rows(name, res))}
        figs[name] = FigureData(name, data, rows, dict(data["sweep"]))
    return list(figs.values())


def _ablation(cfg: ReproduceConfig, p: ModelParams, get: Lookup) -> list[FigureData]:
    runs = []
    rows: list[list[Any]] = []
    series = []
    for t in figure_tasks("ablation", cfg, p):
        r, s = get(t), t.run_spec()
        runs.append({"beta": s.beta, "d31_init": s.d31_init, "d31": r["d31"], "error": r["error"]})
        rows += [[s.beta, s.d31_init, k, v] for k, v in enumerate(r["d31"])]
        if r["error"] is None:
            series.append(r["d31"])
    errors = sum(1 for x in runs if x["error"] is not None)
    summary = {"max_drift_rad": max_drift(series) if series else None, "runs": len(runs),
               "diverged": errors}  # fmt: skip
    csv: Csv = {"ablation": (["beta", "d31_init_rad", "cycle", "d31_rad"], rows)}
    return [FigureData("ablation", {"runs": runs, "summary": summary}, csv, summary)]


def analyse(fig: str, cfg: ReproduceConfig, p: ModelParams, get: Lookup) -> list[FigureData]:
    """The figure data of `fig` (Figs. 5, 6, 9, the ablation) from its tasks' results
    (`get(task)` -> result dict)."""
    if fig in ("7", "8"):
        raise ValueError(f"Fig. {fig} is read from the drift surface (paper.surface_repro)")
    fn = {"5": _fig5, "6": _fig6, "9": _fig9, "ablation": _ablation}
    if fig not in fn:
        raise ValueError(f"unknown figure {fig!r}; choose from {FIGURES}")
    return fn[fig](cfg, p, get)
