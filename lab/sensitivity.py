"""Robustness of the defaults: each open parameter moved by +-10%, and where the runs end.

`python -m lab sensitivity` runs it and writes a tornado chart (how many runs at each beta end
in the expected gait, per parameter and sign) and the JSON behind it.
"""

from __future__ import annotations

import json
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from lab.objectives import evaluate
from lab.space import SEARCH_SPACE
from sim_core import ModelParams
from sim_core.contract import circular_mean, classify_gait
from sim_core.research import BETA_FAST, BETA_SLOW


@dataclass(frozen=True)
class Outcome:
    """Where the runs from many initial values ended at one beta: a branch census."""

    beta: float
    finals: list[float | None]

    def branch(self, name: str) -> tuple[int, float | None]:
        """(how many runs settled in the gait `name`, their circular-mean Delta31)."""
        hits = [f for f in self.finals if f is not None and classify_gait(f, self.beta) == name]
        return len(hits), (circular_mean(hits) if hits else None)


def sensitivity(
    params: ModelParams,
    names: Sequence[str] | None = None,
    *,
    rel: float = 0.10,
    betas: Sequence[float] = (BETA_FAST, BETA_SLOW),
    n_init: int = 8,
    duration_s: float = 6.0,
    dt_s: float | None = None,
) -> dict[str, dict[str, list[Outcome]]]:
    """Outcomes for each parameter moved by -rel and +rel (and the base, under 'base').

    Every perturbed set runs in one batch call; a perturbation that leaves the model's own
    bounds is skipped (reported as missing).
    """
    names = list(names or SEARCH_SPACE)
    variants: list[tuple[str, str, ModelParams]] = [("base", "0", params)]
    for name in names:
        v = params.leaf(name)
        for sign, label in ((-1, "-"), (1, "+")):
            try:
                variants.append((name, label, params.replace(**{name: v * (1 + sign * rel)})))
            except ValueError:
                continue
    out: dict[str, dict[str, list[Outcome]]] = {}
    for name, label, p in variants:
        ev = evaluate(p, betas=betas, n_init=n_init, duration_s=duration_s, dt_s=dt_s)
        out.setdefault(name, {})[label] = [Outcome(b, ev.finals[b]) for b in betas]
    return out


def run_sensitivity(
    out: Path,
    params: ModelParams | None = None,
    *,
    names: Sequence[str] | None = None,
    betas: Sequence[float] = (BETA_FAST, BETA_SLOW),
    n_init: int = 8,
    duration_s: float = 6.0,
    log: Callable[[str], None] = print,
) -> dict[str, Any]:
    """+-10% of each parameter in `names` (default: all of SEARCH_SPACE): writes
    sensitivity_tornado.png and sensitivity.json into `out` and returns the report."""
    p = params or ModelParams()
    out.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    sens = sensitivity(p, names, betas=betas, n_init=n_init, duration_s=duration_s)
    plot_sensitivity(sens, out / "sensitivity_tornado.png")
    report: dict[str, Any] = {
        "params": p.model_dump(),
        "sensitivity": {
            name: {label: [_census(o) for o in outs] for label, outs in d.items()}
            for name, d in sens.items()
        },
        "wall_s": time.perf_counter() - t0,
    }
    (out / "sensitivity.json").write_text(json.dumps(report, indent=1, default=float))
    log(f"[{report['wall_s']:5.0f} s] sensitivity done")
    return report


def _census(o: Outcome) -> dict[str, Any]:
    tri = o.branch("tripod")
    meta = o.branch("metachronal")
    return {
        "beta": o.beta,
        "finals": o.finals,
        "tripod": {"n": tri[0], "d31": tri[1]},
        "metachronal": {"n": meta[0], "d31": meta[1]},
    }


def plot_sensitivity(
    sens: dict[str, dict[str, list[Outcome]]], path: Path, rel: float = 0.10
) -> None:
    """Tornado chart: how +-rel of each parameter moves the branch census at each beta."""
    names = [n for n in sens if n != "base"]
    base = sens["base"]["0"]
    betas = [o.beta for o in base]
    gaits = {b: ("tripod" if b < 0.66 else "metachronal") for b in betas}
    fig, axes = plt.subplots(1, len(betas), figsize=(5.5 * len(betas), 0.35 * len(names) + 1.5))
    axes = [axes] if len(betas) == 1 else list(axes)
    for ax, (k, beta) in zip(axes, enumerate(betas), strict=True):
        g = gaits[beta]
        n0 = base[k].branch(g)[0]
        for row, name in enumerate(names):
            for label, color in (("-", "tab:blue"), ("+", "tab:red")):
                if label in sens[name]:
                    n = sens[name][label][k].branch(g)[0]
                    ax.barh(row, n - n0, left=n0, color=color, alpha=0.6, height=0.35)
        ax.axvline(n0, color="k", lw=0.8)
        ax.set_yticks(range(len(names)), names, fontsize=8)
        total = len(base[k].finals)
        ax.set_xlim(0, total)
        ax.set_xlabel(f"runs (of {total}) ending {g}, beta = {beta}")
    axes[0].set_title(f"blue: parameter -{rel:.0%}, red: +{rel:.0%}", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)
