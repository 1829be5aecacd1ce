"""What `make plan-check` and `make learn-round` share: a whole-study run of the workflow in a
working folder of its own, and the command line of a script that keeps its outputs under
``--out`` and its working folder under ``--work``."""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def snakemake(work: Path, target: str, configfiles: list) -> None:
    """``snakemake -j2 <target> -q`` of this repository's workflow started in ``work`` (not
    with ``--directory``, which would override the ``workdir`` a next run's config sets),
    with ``configfiles`` (relative ones from the repository) in order; raises on failure."""
    cmd = [str(Path(sys.executable).with_name("snakemake")), "-j2", target, "-q",
           "--snakefile", str(REPO / "Snakefile"),
           "--configfile", *[str(REPO / c) for c in configfiles]]
    subprocess.run(cmd, check=True, cwd=work)


def out_and_work(doc: str, name: str, argv: list[str] | None) -> tuple[Path, Path, bool]:
    """``--out`` (created) and the working folder (``--work``, else ``<out>/<name>_work``,
    created) from the command line, and whether the working folder is to be removed at the
    end (none was named)."""
    ap = argparse.ArgumentParser(description=doc)
    ap.add_argument("--out", default="results/benchmarks")
    ap.add_argument("--work", default="", help="working folder (default: a fresh one under "
                    "--out, removed at the end)")
    args = ap.parse_args(argv)
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    work = Path(args.work).resolve() if args.work else out / f"{name}_work"
    work.mkdir(parents=True, exist_ok=True)
    return out, work, not args.work
