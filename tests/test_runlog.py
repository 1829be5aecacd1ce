"""Progress of long jobs: percentage and time left in the log, and a final summary line."""

import logging

from robomill.pipeline.runlog import Progress


def test_progress_logs_percentage_time_left_and_summary(caplog):
    log = logging.getLogger("test_progress")
    with caplog.at_level(logging.INFO, logger="test_progress"):
        p = Progress(log, 4, "lobe map", every_s=0.0)
        for k in range(1, 5):
            p.update(k)
        p.finish("4 speeds done")
    lines = [r.getMessage() for r in caplog.records]
    assert lines[0].startswith("lobe map: 25% done, about ") and lines[0].endswith(" s left")
    assert lines[3].startswith("lobe map: 100% done")
    assert lines[-1].startswith("4 speeds done in ") and lines[-1].endswith(" s")


def test_progress_is_rate_limited(caplog):
    log = logging.getLogger("test_progress2")
    with caplog.at_level(logging.INFO, logger="test_progress2"):
        p = Progress(log, 1000, "simulation", every_s=3600.0)
        for k in range(1, 1000):
            p.update(k)
    assert len(caplog.records) == 0  # nothing until the cadence or the end
