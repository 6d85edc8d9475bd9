"""`run`, `params` and `return-map`: one walk, the parameters, one return map."""

from __future__ import annotations

import argparse
import json
import sys
from typing import Any

from pydantic import ValidationError

from sim_core.cli.common import EXIT_USAGE, doc_with_section
from sim_core.cli.model import add_model_args, choice_from_args, model_json, model_line
from sim_core.cli.runflags import add_run_flags, run_fields, validation_message
from sim_core.model.params import ModelParams
from sim_core.model.spec import INSECT_WORDS, RunSpec, cost_problem, numerics_problem

# `run` without --duration-s runs until settled: a first command should name a gait. The settled
# rule needs a last quarter of >= 40 touchdowns (16-20 s); a tripod start near its fold can sit
# 15-25 s on a ghost before it slides (README, "Status"), so the try is 30 s and the cap 60 s
SETTLE_TRY_S = 30.0
SETTLE_CAP_S = 60.0


def _add_run(sub: Any) -> None:
    p = sub.add_parser(
        "run",
        help="simulate one walk and report Delta31 and the gait",
        description="Simulate one walk. Every option is a field of the run's spec (RunSpec, "
        "sim_core.contract), checked by the same rules and in the same words as the REST "
        "API's; --ground, --setting and --param set the model's parameters, as a job's "
        "ground, setting and params do.",
    )
    add_run_flags(
        p,
        required=("beta",),
        defaults={
            "duration_s": f"until settled: the run stops at {SETTLE_TRY_S:g} s if Delta31 has "
            f"settled by the settled rule, else goes on to {SETTLE_CAP_S:g} s",
            "stop_if_settled_s": f"{SETTLE_TRY_S:g} without --duration-s, else none",
        },
    )
    add_model_args(p)
    p.add_argument("--json", action="store_true", help="print one JSON object")
    p.set_defaults(func=_cmd_run)


def _spec_from_args(args: argparse.Namespace) -> RunSpec:
    fields = run_fields(args)
    if "duration_s" not in fields:  # until settled: a first command names a gait
        fields["duration_s"] = SETTLE_CAP_S
        fields.setdefault("stop_if_settled_s", SETTLE_TRY_S)
    return RunSpec(**fields)


def _cmd_run(args: argparse.Namespace) -> int:
    from sim_core.model.runner import simulate

    choice = choice_from_args(args)  # a UsageError names the flag and the leaf
    try:
        spec = _spec_from_args(args)
    except ValidationError as exc:
        print(f"insect-gait run: error: {validation_message(exc)}", file=sys.stderr)
        return EXIT_USAGE
    # the REST API's rule and words (server/kinds/ calls the same function)
    problem = numerics_problem(spec.integrator, spec.dt_s, spec.control_dt_s)
    if problem:
        print(f"insect-gait run: error: --dt-s: {problem}", file=sys.stderr)
        return EXIT_USAGE
    # the REST API's cost rule and words (server/kinds/, server/routes/jobs.py)
    problem = cost_problem(spec.duration_s, spec.integrator, spec.dt_s, spec.control_dt_s)
    if problem:
        print(f"insect-gait run: error: --duration-s: {problem}", file=sys.stderr)
        return EXIT_USAGE
    result = simulate(spec, choice.model_params())
    summary = result.summary()
    if args.json:
        print(json.dumps(summary | {"model": model_json(choice)}))
    else:
        _print_summary(result.summary(), spec, choice.model_params())
        if model_line(choice):
            print(model_line(choice))
    return 0 if not result.diverged else 1


def _print_summary(s: dict[str, Any], spec: RunSpec, p: ModelParams) -> None:
    from sim_core.model.params import nominal_speed

    v_nom = nominal_speed(spec.beta, p.trajectory.stroke, p.trajectory.swing_duration) * 100
    if s["diverged"]:
        f = s.get("failure") or {}
        kind, at = f.get("kind", ""), f.get("time_s")
        when = "" if at is None else f" at t = {at:.2f} s"
        if kind in INSECT_WORDS:
            print(f"the insect {INSECT_WORDS[kind]}{when}: {f.get('reason', s['error'])}")
            print("(the model's physics under these conditions, not a numerical problem: a "
                  "smaller --dt-s will not help)")  # fmt: skip
        else:
            print(f"the simulation diverged{when}: {f.get('reason', s['error'])}")
            print("(numerical: try a smaller --dt-s)")
        return
    d31 = s["d31"]
    ran = s.get("duration_s") or spec.duration_s
    how = ""
    if spec.stop_if_settled_s is not None:
        how = (" (stopped settled)" if ran < spec.duration_s else
               f" (not settled by {spec.stop_if_settled_s:g} s: ran to the cap)")  # fmt: skip
    print(f"beta {spec.beta:.3f}  d31_init {spec.d31_init:.3f} rad  ran {ran:g} s{how}")
    print(f"Delta31 at leg-1 touchdowns ({len(d31)}): " + " ".join(f"{x:.2f}" for x in d31[-12:]))
    final = "n/a" if s["d31_final"] is None else f"{s['d31_final']:.3f} rad"
    print(f"final Delta31 {final} (mean of the last quarter)  gait {s['gait']}")
    if s["drift_per_cycle"] is not None:
        verdict = "settled" if s["settled"] else f"not settled: {s['settled_why']}"
        print(f"drift {1e3 * s['drift_per_cycle']:+.3f} mrad per cycle over the last quarter: "
              f"{verdict}")  # fmt: skip
    if s["speed_cm_s"] is not None:
        print(f"speed {s['speed_cm_s']:.2f} cm/s (eq. 2: {v_nom:.2f})")
    if s["duty_factor_measured"] is not None:
        print(f"duty factor measured {s['duty_factor_measured']:.3f} (commanded {spec.beta:.3f})")
    if s["slip_fraction"] is not None:
        print(f"foot slip per stance {100 * s['slip_fraction']:.1f}% of the stroke")
    if s["landing_swing_share"] is not None:
        print(f"feet land at {s['landing_swing_share']:.2f} of their swing (1 = at the AEP, "
              "above 1 = late, below = early)")  # fmt: skip
    if s["retouches_per_stance"] is not None:
        print(f"stance feet leave and re-touch the ground {s['retouches_per_stance']:.2f} times "
              "per stance")  # fmt: skip
    for w in s["warnings"]:
        print(f"warning: {w}")


def _add_params(sub: Any) -> None:
    p = sub.add_parser("params", help="every model parameter with its origin and reason")
    p.add_argument("--json", action="store_true")
    p.add_argument("--update-doc", metavar="MD",
                   help="rewrite the table between the <!-- params:begin --> and <!-- params:end "
                   "--> lines of this markdown file (docs/MODEL.md has them)")  # fmt: skip
    p.set_defaults(func=_cmd_params)


def _cmd_params(args: argparse.Namespace) -> int:
    from sim_core.docsections import parameter_markdown, update_parameter_doc
    from sim_core.model.params import parameter_table

    if args.update_doc:
        path = doc_with_section(args.update_doc, "params", "--update-doc")
        path.write_text(update_parameter_doc(path.read_text()))
        print(f"updated the parameter table in {path}")
        return 0
    if args.json:
        rows = [row._asdict() for row in parameter_table()]
        print(json.dumps(rows, indent=1))
    else:
        print(parameter_markdown())
    return 0


# a return map's runs are short: the pairs come from the transient itself (Fig. 7)
RETURN_MAP_DURATION_S = 3.0


def _add_return_map(sub: Any) -> None:
    p = sub.add_parser(
        "return-map",
        help="Delta31(n) -> Delta31(n+4) drift from many starts",
        description="The paper's Fig. 7 return map: --n-init runs at one beta from initial "
        "Delta31 spread evenly over [0, 2 pi), and the mean drift of Delta31 per gait cycle "
        "in bins of Delta31. The runs' other options are the run's (RunSpec), as `run` "
        "takes them.",
        formatter_class=argparse.ArgumentDefaultsHelpFormatter,
    )
    add_run_flags(p, vary=("d31_init",), required=("beta",),
                  defaults={"duration_s": str(RETURN_MAP_DURATION_S)})  # fmt: skip
    p.add_argument("--n-init", type=int, default=16,
                   help="runs, one per initial Delta31, spread over [0, 2 pi); >= 1")  # fmt: skip
    add_model_args(p)
    p.add_argument("--json", action="store_true",
                   help="print one JSON object (pairs, bin centres, drift per cycle)")  # fmt: skip
    p.set_defaults(func=_cmd_return_map)


def _return_map_problems(args: argparse.Namespace) -> list[str]:
    """Only the rules this command line breaks, each once (RunSpec's words for its fields,
    the contract's numerics and cost rules for the runs together)."""
    problems = []
    if args.n_init < 1:
        problems.append(f"--n-init: must be >= 1 (one run per initial Delta31), got {args.n_init}")
    try:
        spec = RunSpec(**_return_map_fields(args))
    except ValidationError as exc:
        problems.append(validation_message(exc))
        return problems
    if not problems:
        problem = numerics_problem(spec.integrator, spec.dt_s, spec.control_dt_s)
        if problem:
            return [f"--dt-s: {problem}"]
        cost = cost_problem(spec.duration_s, spec.integrator, spec.dt_s, spec.control_dt_s,
                            runs=args.n_init)  # fmt: skip
        if cost:
            problems.append(f"--duration-s: {cost}")
    return problems


def _return_map_fields(args: argparse.Namespace) -> dict[str, Any]:
    return {"duration_s": RETURN_MAP_DURATION_S} | run_fields(args)


def _cmd_return_map(args: argparse.Namespace) -> int:
    import numpy as np

    from sim_core.paper.protocols import return_map
    from sim_core.paper.returnmap import initial_values

    choice = choice_from_args(args)  # a UsageError names the flag and the leaf
    problems = _return_map_problems(args)
    if problems:
        print(f"insect-gait return-map: error: {'; '.join(problems)}", file=sys.stderr)
        return EXIT_USAGE
    inits = initial_values(args.n_init).tolist()
    rm = return_map(choice.model_params(), inits=inits, **_return_map_fields(args))
    centers, drift = rm.drift_per_cycle()
    if args.json:
        drift_list = [None if np.isnan(d) else float(d) for d in drift]
        obj = {"beta": args.beta, "x": rm.x.tolist(), "y": rm.y.tolist()}
        obj.update({"bin_centers": centers.tolist(), "drift_per_cycle": drift_list})
        print(json.dumps(obj | {"model": model_json(choice)}))
        return 0
    print(f"beta {args.beta}: {rm.x.size} pairs; mean drift of Delta31 per cycle by bin")
    for c, d in zip(centers, drift, strict=True):
        bar = "" if np.isnan(d) else ("+" if d > 0 else "-") * min(40, int(abs(d) / 0.005))
        shown = "   n/a" if np.isnan(d) else f"{d:+.3f}"
        print(f"  {c:5.2f} rad  {shown}  {bar}")
    if model_line(choice):
        print(model_line(choice))
    return 0


def register(sub: Any) -> None:
    _add_run(sub)
    _add_params(sub)
    _add_return_map(sub)
