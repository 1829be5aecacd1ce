"""``robomill predict STUDY CUTS [--out FILE]``: any list of cuts predicted from a study's
results with the plan's own code (:mod:`robomill.plan.cutlist`): per cut the probability of
a stable cut, the critical depth with its interval, the mean force, the static deflection and
the waviness with their intervals, and whether (and why) the prediction is extrapolated.

STUDY is the project folder whose plan was made (``snakemake -j2 plan``: its
``results/plan/model.yaml`` records what the plan read), or its ``results`` folder; CUTS a
CSV or YAML list of cuts with the manifest's cut keys. The table is written as CSV to
``--out`` (else standard output). A bad input ends with one line naming the file, the cut and
the key.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Any

HELP = ("predict any cuts from a study's results: p_stable, critical depth, force, "
        "deflection and waviness with their intervals, extrapolation flag")


def add_parser(sub: Any) -> None:  # what ArgumentParser.add_subparsers() returns
    p = sub.add_parser("predict", help=HELP, description=HELP + " (the plan's own code).")
    p.add_argument("study", type=Path, metavar="STUDY",
                   help="project folder whose plan was made (or its results folder)")
    p.add_argument("cuts", type=Path, metavar="CUTS",
                   help="CSV or YAML list of cuts (id, spindle_rpm, depth_mm, feed_mm_s, "
                        "direction or direction_deg, start_mm, ...)")
    p.add_argument("--out", type=Path, default=None,
                   help="write the table here as CSV (default: standard output)")
    p.add_argument("--request", type=Path, default=None,
                   help="another planning request (its tool, constraints and stability "
                        "settings; default: the one the plan used)")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from robomill.errors import RawDataError
    from robomill.io.cutlist import check_placeable, parse_cuts, read_cut_entries
    from robomill.plan.cutlist import predict_table
    from robomill.plan.inputs import load_recorded
    from robomill.plan.request import PlanRequestError

    try:
        cuts = parse_cuts(args.cuts, read_cut_entries(args.cuts))
        inputs = load_recorded(args.study, request=args.request)
        check_placeable(args.cuts, cuts, inputs.experiment)
    except (RawDataError, PlanRequestError) as exc:
        print(f"robomill predict: {exc}", file=sys.stderr)
        return 1
    table = predict_table(inputs, cuts)
    if args.out is None:
        table.to_csv(sys.stdout, index=False)
    else:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        table.to_csv(args.out, index=False)
        print(f"robomill predict: {len(table)} cut(s) -> {args.out}")
    return 0
