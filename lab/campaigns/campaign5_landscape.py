"""Fifth campaign, point 3 (issue 40): the search's landscape, read from its exported record.

    python -m lab.campaigns.campaign5_landscape [--trials FILE] [--figure PNG]

Prints (markdown, for docs/studies/journal.md) how many candidates were evaluated per ground, the
best ones with their folds and parts of the score, the Pareto front of metachronal-fold error
against tripod-fold error among candidates that walk properly, and which parameters matter
(optuna's PED-ANOVA importances over the parameters every candidate has); draws the folds of
every candidate against the paper's (`--figure`).
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path
from typing import Any

import numpy as np

from lab.surface_search import PAPER_METACHRONAL_FOLD, PAPER_TRIPOD_FOLD

SANE = 0.02  # a candidate "walks properly" when its sanity part of the score is below this


def evaluated(rows: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [r for r in rows if r["state"] == "COMPLETE" and "error" not in r["user_attrs"]]


def pareto(points: list[tuple[float, float, int]]) -> list[tuple[float, float, int]]:
    """The non-dominated (a, b, id) points, both errors minimised, in order of a."""
    front: list[tuple[float, float, int]] = []
    for a, b, i in sorted(points):
        if not front or b < front[-1][1]:
            front.append((a, b, i))
    return front


def importances(rows: list[dict[str, Any]]) -> dict[str, float]:
    """PED-ANOVA importances of the parameters every evaluated candidate has (empty if < 20)."""
    import optuna

    from lab.campaigns.campaign5_search import distributions

    rows = evaluated(rows)
    if len(rows) < 20:
        return {}
    shared = set.intersection(*(set(r["params"]) for r in rows))
    study = optuna.create_study()
    for r in rows:
        dist = distributions(r["params"]["ground"])
        study.add_trial(
            optuna.trial.create_trial(
                params={k: r["params"][k] for k in shared},
                distributions={k: dist[k] for k in shared},
                value=r["value"],
            )
        )
    optuna.logging.set_verbosity(optuna.logging.WARNING)
    ev = optuna.importance.PedAnovaImportanceEvaluator()  # needs no scikit-learn
    return dict(optuna.importance.get_param_importances(study, evaluator=ev))


def report(rows: list[dict[str, Any]], top: int = 8) -> str:
    ok = evaluated(rows)
    out = []
    by_ground = {
        g: [r for r in ok if r["params"]["ground"] == g] for g in ("constraint", "penalty")
    }
    n_err = sum(1 for r in rows if "error" in r["user_attrs"])
    out.append(
        f"{len(rows)} candidates: {len(ok)} evaluated (constraint ground "
        f"{len(by_ground['constraint'])}, paper's ground {len(by_ground['penalty'])}), {n_err} "
        "refused before simulating (a tip out of reach)."
    )
    wall = [r["user_attrs"].get("wall_s") for r in ok if r["user_attrs"].get("wall_s")]
    if wall:
        out.append(f"Wall time per evaluated candidate: median {np.median(wall):.1f} s.")
    out.append("\n| # | ground | score | metachronal fold | tripod fold | extra zeros | sanity |")
    out.append("|---|---|---|---|---|---|---|")
    for r in sorted(ok, key=lambda r: r["value"])[:top]:
        u = r["user_attrs"]
        out.append(
            f"| {r['number']} | {r['params']['ground']} | {r['value']:.4f} | "
            f"{u['metachronal_fold']:.3f} | {u['tripod_fold']:.3f} | {u['extra_zeros']} | "
            f"{u['part_sanity']:.3f} |"
        )
    sane = [r for r in ok if r["user_attrs"]["part_sanity"] < SANE]
    pts = [
        (
            abs(r["user_attrs"]["metachronal_fold"] - PAPER_METACHRONAL_FOLD),
            abs(r["user_attrs"]["tripod_fold"] - PAPER_TRIPOD_FOLD),
            r["number"],
        )
        for r in sane
    ]
    out.append(f"\nPareto front among the {len(sane)} that walk properly (sanity < {SANE}):")
    out.append("| # | metachronal fold error | tripod fold error | bistable (tripod fold above)? |")
    out.append("|---|---|---|---|")
    by_id = {r["number"]: r for r in ok}
    for a, b, i in pareto(pts):
        u = by_id[i]["user_attrs"]
        loop = "yes" if u["tripod_fold"] > u["metachronal_fold"] else "no"
        out.append(f"| {i} | {a:.3f} | {b:.3f} | {loop} |")
    imp = importances(rows)
    if imp:
        out.append(
            "\nWhat matters (PED-ANOVA importance of the score, parameters all candidates share):"
        )
        out.append(", ".join(f"{k} {v:.2f}" for k, v in list(imp.items())[:10]))
    return "\n".join(out)


def figure(rows: list[dict[str, Any]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = evaluated(rows)
    fig, ax = plt.subplots(figsize=(6.0, 5.0))
    for ground, colour in (("constraint", "#1f77b4"), ("penalty", "#d62728")):
        sel = [r for r in ok if r["params"]["ground"] == ground]
        sane = [r["user_attrs"]["part_sanity"] < SANE for r in sel]
        x = [r["user_attrs"]["metachronal_fold"] for r in sel]
        y = [r["user_attrs"]["tripod_fold"] for r in sel]
        ax.scatter(x, y, s=[18 if s else 5 for s in sane], c=colour, alpha=0.6,
                   label=f"{ground} ground ({len(sel)})")  # fmt: skip
    ax.plot([PAPER_METACHRONAL_FOLD], [PAPER_TRIPOD_FOLD], "k*", ms=14, label="the paper")
    lo, hi = 0.54, 0.81
    ax.plot([lo, hi], [lo, hi], "k:", lw=0.8)
    ax.text(0.56, 0.78, "bistable band\n(tripod fold above)", fontsize=8)
    ax.set(xlim=(lo, hi), ylim=(lo, hi), xlabel="metachronal fold (beta where it appears)",
           ylabel="tripod fold (beta where it dies)",
           title="Fifth campaign: every candidate's folds (coarse surfaces)")  # fmt: skip
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", default="docs/data/campaign5_trials.json")
    ap.add_argument("--figure", default="docs/figures/campaign5_landscape.png")
    a = ap.parse_args()
    rows = json.loads(Path(a.trials).read_text())["trials"]
    print(report(rows))
    figure(rows, Path(a.figure))
    print(f"\nwrote {a.figure}")


if __name__ == "__main__":
    main()
