"""Progress of a long job in its log: percentage done and time left, then a summary line.

Only :mod:`logging` and :mod:`time`: the simulators and the analyses may report progress
without importing the pipeline's tooling (:mod:`robomill.pipeline.runlog` re-exports it).
"""

from __future__ import annotations

import logging
import time


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
