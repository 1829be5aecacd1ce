"""Logging for rule scripts: stderr and the ``logging`` module go to the rule's log file, and
the seconds of the job's own work go beside its benchmark (``make bench``'s floor)."""

from __future__ import annotations

import atexit
import json
import logging
import sys
import time
from pathlib import Path

from robomill.progress import Progress

__all__ = ["Progress", "WORK_DIR", "record_work_at_exit", "setup", "work_path"]

WORK_DIR = Path("benchmarks") / "work"
"""Where :func:`setup` records a job's work, beside ``logs`` under the results folder:
``results/logs/<job>.log`` -> ``results/benchmarks/work/<job>.json``."""


def setup(log_path: str | Path | None, name: str = "robomill") -> logging.Logger:
    """Send stderr and log records to ``log_path`` (line-buffered); return a logger.

    Rule scripts call this first, so a failing job's log holds its traceback and every
    message (Snakemake prints the log path of a failed job). It also starts the job's work
    clock (:func:`record_work_at_exit`): rule scripts import their libraries before calling it,
    so the time from here to the end of the process is the library call and its output.
    """
    if log_path:
        Path(log_path).parent.mkdir(parents=True, exist_ok=True)
        sys.stderr = open(log_path, "w", buffering=1)  # noqa: SIM115 (lives for the process)
        record_work_at_exit(log_path)
    logging.basicConfig(stream=sys.stderr, level=logging.INFO, force=True,
                        format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    return logging.getLogger(name)


def work_path(log_path: str | Path) -> Path | None:
    """The work record of the job logging to ``log_path``: its last ``logs`` folder replaced by
    :data:`WORK_DIR` and the suffix by ``.json``; None for a log outside a ``logs`` folder."""
    parts = Path(log_path).parts
    if "logs" not in parts[:-1]:
        return None
    i = len(parts) - 1 - parts[::-1].index("logs")
    return Path(*parts[:i], WORK_DIR, *parts[i + 1:]).with_suffix(".json")


def record_work_at_exit(log_path: str | Path) -> Path | None:
    """Start the work clock now; at interpreter exit write ``{"work_s": seconds, "log": path}``
    to :func:`work_path` (the floor of ``make bench``: the job's time less Snakemake's and
    Python's start-up and the imports)."""
    path = work_path(log_path)
    if path is None:
        return None
    t0 = time.perf_counter()

    def write() -> None:
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(json.dumps({"work_s": time.perf_counter() - t0,
                                        "log": str(log_path)}) + "\n")
        except OSError:  # a measurement only: never fail the job over it
            pass

    atexit.register(write)
    return path
