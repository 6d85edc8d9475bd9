"""The sixth campaign's landscape so far, from its exported trials (no simulation):

    python -m lab.campaigns.campaign6_landscape [TRIALS.json]

Prints how many candidates were scored and failed, the best ten with their folds and walks, the
Pareto front of the two fold errors, how many candidates hold each of the paper's answers
(both folds within 0.015 of the paper's, either one, the metachronal side's end found at all),
and which parameters go with a low score (Spearman's rank correlation over the scored
candidates, per parameter: a screening, not an attribution).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path
from typing import Any

import numpy as np

from lab.campaigns.campaign6_search import rescore
from lab.surface_search import PAPER_METACHRONAL_FOLD, PAPER_TRIPOD_FOLD
from lab.walk_objective import FAILED_SCORE, MISMATCH_WEIGHT

FOLD_OK = 0.015  # issue 52's adoption tolerance on each fold


def _ranks(x: np.ndarray) -> np.ndarray:
    order = np.argsort(x, kind="stable")
    r = np.empty(len(x))
    r[order] = np.arange(len(x))
    return r


def spearman(x: np.ndarray, y: np.ndarray) -> float:
    rx, ry = _ranks(x), _ranks(y)
    if rx.std() == 0 or ry.std() == 0:
        return 0.0
    return float(np.corrcoef(rx, ry)[0, 1])


def pareto(points: list[tuple[float, float, int]]) -> list[tuple[float, float, int]]:
    """The (a, b, id) no other point beats on both a and b."""

    def beaten(p: tuple[float, float, int]) -> bool:
        return any(q[0] <= p[0] and q[1] <= p[1] and q[:2] != p[:2] for q in points)

    return sorted({p for p in points if not beaten(p)})


def main() -> None:
    path = Path(sys.argv[1] if len(sys.argv) > 1 else "docs/data/campaign6_trials.json")
    trials = [rescore(t) for t in json.loads(path.read_text())["trials"]]
    done = [t for t in trials if t["state"] == "COMPLETE"]
    scored = [t for t in done if t["value"] < FAILED_SCORE]
    print(f"{len(done)} candidates, {len(done) - len(scored)} not walkable (out of reach or "
          f"invalid), {len(scored)} scored")  # fmt: skip
    if not scored:
        return

    def errs(t: dict[str, Any]) -> tuple[float, float]:
        u = t["user_attrs"]
        return (abs(u["metachronal_fold"] - PAPER_METACHRONAL_FOLD),
                abs(u["tripod_fold"] - PAPER_TRIPOD_FOLD))  # fmt: skip

    print("\nbest ten: # | ground | score | metachronal fold | tripod fold | walks against the "
          "paper | walks (side beta final holds)")  # fmt: skip
    for t in sorted(scored, key=lambda t: t["value"])[:10]:
        u = t["user_attrs"]
        walks = " ".join(f"{w[0]}{w[1]}:{'-' if w[2] is None else f'{w[2]:.2f}'}"
                         f"{'+' if w[4] else '-'}" for w in u["walks"])  # fmt: skip
        print(f"#{t['number']} | {t['params']['ground'][:4]} | {t['value']:.4f} | "
              f"{u['metachronal_fold']:.4f} | {u['tripod_fold']:.4f} | {u['against_paper']} | "
              f"{walks}")  # fmt: skip
    front = pareto([(*errs(t), t["number"]) for t in scored])
    print(
        "\nPareto front of the fold errors (metachronal, tripod; #):",
        ", ".join(f"({a:.4f}, {b:.4f}; #{n})" for a, b, n in front),
    )
    # a fold read where a walk settled in a third state is the window's edge, not an end
    clean = [t for t in scored if t["user_attrs"].get("part_third_states", 0.0) == 0.0]
    front = pareto([(*errs(t), t["number"]) for t in clean])
    print(
        f"Pareto front among the {len(clean)} without a third state:",
        ", ".join(f"({a:.4f}, {b:.4f}; #{n})" for a, b, n in front),
    )
    both = [t for t in scored if max(errs(t)) <= FOLD_OK]
    meta = [t for t in scored if errs(t)[0] <= FOLD_OK]
    trip = [t for t in scored if errs(t)[1] <= FOLD_OK]
    print(
        f"\nboth folds within {FOLD_OK}: {len(both)}; metachronal's: {len(meta)}; "
        f"tripod's: {len(trip)} (of {len(scored)})"
    )
    print("tripod's fold within it: # | score | tripod value | walks against | third states")
    for t in sorted(trip, key=lambda t: t["value"]):
        u = t["user_attrs"]
        tv = "-" if u["tripod_value"] is None else f"{u['tripod_value']:.2f}"
        print(f"  #{t['number']} | {t['value']:.4f} | {tv} | {u['against_paper']} | "
              f"{round(u.get('part_third_states', 0.0) / MISMATCH_WEIGHT)}")  # fmt: skip
    skip = ("ground", "trajectory_frame")
    names = sorted({k for t in scored for k in t["params"] if k not in skip})
    y = np.array([t["value"] for t in scored])
    rows = []
    for n in names:
        have = [(t["params"][n], t["value"]) for t in scored if n in t["params"]]
        if len(have) >= 10:
            x, v = np.array(have).T
            rows.append((spearman(x, v), n, len(have)))
    print(
        f"\nrank correlation with the score (negative: larger values score better), "
        f"{len(y)} candidates:"
    )
    for rho, n, k in sorted(rows, key=lambda r: -abs(r[0]))[:12]:
        print(f"  {n}: {rho:+.2f} (n={k})")


if __name__ == "__main__":
    main()
