"""``robomill plan DIR --request plan.yaml``: plan the next cuts from a study's measurements
 by running the pipeline's ``plan`` target for that folder.

DIR is a raw folder (it has ``manifest.yaml``: the study is run on it with
``--config data=DIR``) or a project folder (it has a ``Snakefile``: run there with its own
``config.yaml``). The request is validated first (one line per problem); a plan that cannot
be made ends with the one line saying why (the constraint that binds, or the missing
measurement).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path
from typing import Any

HELP = "plan the next cuts (pose, speed, depth, feed) from a study's measurements"

PLAN_LOG = Path("results/logs/plan/make.log")


def project_root(start: Path) -> Path | None:
    """The folder with the pipeline's Snakefile: ``start`` or one above it, else the
    repository this package was installed from."""
    for d in (start, *start.parents):
        if (d / "Snakefile").exists() and (d / "workflow").is_dir():
            return d
    repo = Path(__file__).resolve().parents[3]
    return repo if (repo / "Snakefile").exists() else None


def plan_command(folder: Path, request: Path, *, cores: int = 2, dry_run: bool = False,
                 cwd: Path | None = None) -> tuple[list[str], Path]:
    """The snakemake command line and the folder to run it in.

    Raises
    ------
    ValueError
        DIR is neither a raw folder nor a project folder, or no pipeline is found.
    """
    folder = folder.resolve()
    if (folder / "Snakefile").exists():
        root, data = folder, None
    elif (folder / "manifest.yaml").exists():
        root, data = project_root((cwd or Path.cwd()).resolve()), folder
        if root is None:
            raise ValueError(f"{folder}: no robomill pipeline (Snakefile) found to run")
    else:
        raise ValueError(f"{folder}: neither a raw folder (manifest.yaml) nor a project folder "
                         "(Snakefile)")
    cmd = [sys.executable, "-m", "snakemake", f"-j{int(cores)}", "--config",
           "plan=" + json.dumps({"request": str(request.resolve())})]
    if data is not None:
        cmd.append(f"data={data}")
    if dry_run:
        cmd.append("-n")
    cmd += ["--", "plan"]
    return cmd, root


def last_reason(log: Path) -> str | None:
    """The one line of a refused plan (``PlanInfeasible`` or a bad request) in the rule log."""
    if not log.exists():
        return None
    for line in reversed(log.read_text(errors="replace").splitlines()):
        for tag in ("PlanInfeasible: ", "PlanRequestError: "):
            if tag in line:
                return line.split(tag, 1)[1]
    return None


def add_parser(sub: Any) -> None:  # what ArgumentParser.add_subparsers() returns
    p = sub.add_parser("plan", help=HELP, description=HELP + ": runs snakemake's plan target "
                       "(results/plan/, chapter 7).")
    p.add_argument("dir", type=Path, metavar="DIR",
                   help="raw folder (manifest.yaml) or project folder (Snakefile)")
    p.add_argument("--request", type=Path, default=Path("plan.yaml"),
                   help="the planning request, kind plan (default plan.yaml)")
    p.add_argument("--cores", type=int, default=2, help="snakemake -j (default 2)")
    p.add_argument("-n", "--dry-run", action="store_true", help="show the jobs, run nothing")
    p.set_defaults(run=run)


def run(args: argparse.Namespace) -> int:
    from robomill.plan.request import PlanRequestError, read_request

    try:
        read_request(args.request)
        cmd, root = plan_command(args.dir, args.request, cores=args.cores,
                                 dry_run=args.dry_run)
    except (PlanRequestError, ValueError) as exc:
        print(exc)
        return 1
    done = subprocess.run(cmd, cwd=root, check=False)
    if done.returncode != 0:
        why = last_reason(root / PLAN_LOG)
        print(f"robomill plan: {why}" if why else "robomill plan: the pipeline failed "
              "(see the failure summary above)")
        return 1
    if not args.dry_run:
        print(f"plan: {root / 'results/plan/plan.csv'}; next experiment: "
              f"{root / 'results/plan/next/manifest.yaml'}; chapter 7: "
              f"{root / 'results/chapters/ch7.html'}")
        print("run the planned cuts in their own folder (results/plan/next/run): snakemake "
              "-j2 all --configfile results/plan/next/config.yaml")
    return 0
