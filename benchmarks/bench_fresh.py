"""What a newcomer waits for: the default study from a fresh clone, caches cold.

The repository's committed ``HEAD`` is cloned into an empty folder and built there as a new
user's ``make all`` builds it, with this run's virtual environment (the package install is
the one thing not timed: its figure depends on the network and the package cache):

1. what ``make venv`` adds to the install for the clone: its sources' bytecode
   (``compileall``) and every numba kernel compiled into an empty cache
   (``python -m robomill.kernels``, :mod:`robomill.kernels`);
2. ``snakemake -j2 all`` in the clone (its own ``src`` first on ``PYTHONPATH``, the
   kernels' cache of step 1), beside the floor of that run (:mod:`floor`: the summed work of
   its jobs over 2 cores), and the sum of both steps.

The warm figure (the same target in a fresh results folder of this checkout, whose kernels
and bytecode are compiled already) is :mod:`bench_study`'s. Set ``ROBOMILL_BENCH_FRESH=0`` to
skip this one (about 3 minutes on 2 cores), ``ROBOMILL_BENCH_FRESH_KEEP=1`` to keep the clone's
``results`` as ``<out>/fresh_clone_results`` (to compare them with another run's).
"""

from __future__ import annotations

import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from floor import floor_rows, floor_summary

REPO = Path(__file__).resolve().parents[1]
PYTHON = sys.executable
SNAKEMAKE = str(Path(PYTHON).with_name("snakemake"))
GOAL_FRESH_S = 150.0
"""The goal (2 cores) for a fresh clone's ``snakemake -j2 all``."""
TARGET = "all"
"""The target built in the clone."""


def _timed(cmd: list[str], cwd: Path, env: dict) -> tuple[float, str]:
    t0 = time.perf_counter()
    proc = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if proc.returncode:
        raise RuntimeError(f"{' '.join(cmd)} failed in {cwd}:\n{proc.stderr[-3000:]}")
    return wall, proc.stdout + proc.stderr


def fresh_clone_env(clone: Path, cache: Path) -> dict:
    """The environment of a run in ``clone``: its sources first on the path, an empty kernel
    cache of its own."""
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join([str(clone / "src")]
                                        + [p for p in [env.get("PYTHONPATH")] if p])
    env["NUMBA_CACHE_DIR"] = str(cache)
    env.pop("PYTHONDONTWRITEBYTECODE", None)
    return env


def run(out_dir: Path) -> list[dict]:
    if os.environ.get("ROBOMILL_BENCH_FRESH", "1") == "0":
        return []
    rows: list[dict] = []

    def row(metric, value, unit, baseline=None, note=""):
        ratio = value / baseline if baseline else None
        rows.append({"benchmark": "fresh clone", "metric": metric, "value": value,
                     "unit": unit, "baseline": baseline, "ratio": ratio, "note": note})

    head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=REPO,
                          capture_output=True, text=True, check=True).stdout.strip()
    with tempfile.TemporaryDirectory(prefix="robomill-fresh-") as tmp:
        clone, cache = Path(tmp) / "clone", Path(tmp) / "numba-cache"
        subprocess.run(["git", "clone", "--quiet", "--no-hardlinks", str(REPO), str(clone)],
                       check=True)
        env = fresh_clone_env(clone, cache)
        t_bytecode, _ = _timed([PYTHON, "-m", "compileall", "-q", "src"], clone, env)
        t_kernels, _ = _timed([PYTHON, "-m", "robomill.kernels"], clone, env)
        t_all, log = _timed([SNAKEMAKE, "-j2", TARGET], clone, env)
        floor_s = floor_summary(clone / "results", t_all, cores=2)["floor_s"]
        rows.extend(floor_rows("fresh clone", clone / "results", t_all, cores=2))
        if os.environ.get("ROBOMILL_BENCH_FRESH_KEEP") == "1":
            kept = Path(out_dir) / "fresh_clone_results"
            shutil.rmtree(kept, ignore_errors=True)
            shutil.move(clone / "results", kept)
    n_jobs = log.count("Finished jobid")
    row("fresh clone: `snakemake -j2 all`", t_all, "s", floor_s,
        f"clone of {head}, {n_jobs} jobs, kernels compiled before (row below); baseline: the "
        f"floor of this run (summed work / 2 cores, floor.py); the goal {GOAL_FRESH_S:g} s")
    row("fresh clone: what `make venv` adds (bytecode, numba kernels)", t_bytecode + t_kernels,
        "s", t_all, f"compileall {t_bytecode:.1f} s, python -m robomill.kernels into an empty "
                    f"cache {t_kernels:.1f} s; baseline: the study's run")
    row("fresh clone: `make all` less the package install", t_bytecode + t_kernels + t_all,
        "s", GOAL_FRESH_S, "the two rows above; baseline: the goal for the study's run")
    return rows
