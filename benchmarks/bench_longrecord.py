"""Peak memory of the force analysis against the record length.

Three synthetic 25 kHz records (1 min, 10 min, 1 h: 1.5 M to 90 M samples per axis, chunked
HDF5) are written with :mod:`robomill.longrecord` and each analysed in a fresh process, the
way the ``forces_cut`` rule does; the process reports its peak RSS. The baseline of each row is
the shortest record's RSS (bounded memory gives ratios near 1.0); the note gives the size the
record would take in memory as float64.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path

from robomill.longrecord import FS_HZ, write_record

LENGTHS_S = (60.0, 600.0, 3600.0)


def run(out_dir: Path) -> list[dict]:
    rows, first = [], None
    work = Path(out_dir) / "longrecord"
    work.mkdir(parents=True, exist_ok=True)
    for seconds in LENGTHS_S:
        path = work / f"record_{int(seconds)}s.h5"
        t0 = time.perf_counter()
        write_record(path, seconds)
        t_write = time.perf_counter() - t0
        proc = subprocess.run([sys.executable, "-m", "robomill.longrecord", "analyse",
                               str(path)], capture_output=True, text=True, check=True)
        got = json.loads(proc.stdout.strip().splitlines()[-1])
        size_gb = path.stat().st_size / 1e9
        path.unlink()
        first = first or got["peak_rss_mib"]
        in_memory_mib = got["n_samples"] * 4 * 8 / 2**20
        rows.append({"benchmark": "longrecord",
                     "metric": f"force analysis peak RSS, {seconds / 60:g} min at "
                               f"{FS_HZ / 1e3:g} kHz",
                     "value": got["peak_rss_mib"], "unit": "MiB", "baseline": first,
                     "ratio": got["peak_rss_mib"] / first,
                     "note": f"{got['n_samples'] / 1e6:.1f} M samples/axis ({in_memory_mib:.0f} "
                             f"MiB as float64, {size_gb:.2f} GB file, written in "
                             f"{t_write:.1f} s), analysed in {got['wall_s']:.1f} s, "
                             f"{got['lowband_segments']} low-band segment(s); baseline: "
                             f"the {LENGTHS_S[0] / 60:g} min record"})
    return rows
