"""Logging for rule scripts: stderr and the ``logging`` module go to the rule's log file."""

from __future__ import annotations

import logging
import sys
import time
from pathlib import Path


def setup(log_path: str | Path | None, name: str = "robomill") -> logging.Logger:
    """Send stderr and log records to ``log_path`` (line-buffered); return a logger.

    Rule scripts call this first, so a failing job's log holds its traceback and every
    message (Snakemake prints the log path of a failed job).
    """
    if log_path:
        Path(log_path).parent.mkdir(parents=True, exist_ok=True)
        sys.stderr = open(log_path, "w", buffering=1)  # noqa: SIM115 (lives for the process)
    logging.basicConfig(stream=sys.stderr, level=logging.INFO, force=True,
                        format="%(asctime)s %(levelname)s %(name)s: %(message)s")
    return logging.getLogger(name)


class Progress:
    """Log percentage done and time left at most every ``every_s`` seconds."""

    def __init__(self, logger: logging.Logger, total: float, what: str, every_s: float = 3.0):
        self.logger, self.total, self.what, self.every_s = logger, float(total), what, every_s
        self.t0 = self.last = time.monotonic()

    def update(self, done: float) -> None:
        now = time.monotonic()
        if now - self.last < self.every_s and done < self.total:
            return
        self.last = now
        frac = done / self.total if self.total else 1.0
        left = (now - self.t0) * (1 - frac) / frac if frac > 0 else float("nan")
        self.logger.info("%s: %.0f%% done, about %.0f s left", self.what, 100 * frac, left)

    def finish(self, summary: str) -> None:
        self.logger.info("%s in %.1f s", summary, time.monotonic() - self.t0)
