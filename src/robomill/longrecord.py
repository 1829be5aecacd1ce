"""Long force recordings (hours at 25 kHz): a streamed synthetic HDF5 record and the per-cut
force analysis run over it, reporting the peak resident memory of the analysing process.

The analysis is exactly the ``forces_cut`` rule's (:class:`robomill.forces.ForceSpectrumAccumulator`
over :meth:`robomill.io.forces.ForceRecord.chunks`), so a measurement here is one of the
pipeline. Used by the bounded-memory test and ``make bench``::

    python -m robomill.longrecord write  rec.h5 --seconds 3600      # one hour, ~1.1 GB
    python -m robomill.longrecord analyse rec.h5                    # prints one JSON line
"""

from __future__ import annotations

import argparse
import json
import resource
import sys
import time
from collections.abc import Iterator
from pathlib import Path

import numpy as np

FS_HZ = 25_000.0
BLOCK = 262_144


def synthetic_blocks(n_samples: int, fs_hz: float = FS_HZ, *, seed: int = 0,
                     block: int = BLOCK) -> Iterator[tuple[np.ndarray, np.ndarray]]:
    """Blocks ``(t_s, force_N (n, 3))`` of a stationary record: a 30 N mean, tooth-passing
    lines at 933.3 Hz and 1866.7 Hz, a 67 Hz low-frequency line and white noise (0.5 N rms),
    generated one block at a time (memory independent of ``n_samples``)."""
    rng = np.random.default_rng(seed)
    amp = np.array([[8.0, 5.0, 2.0], [3.0, 2.0, 1.0], [1.5, 1.0, 0.5]])
    freq = np.array([933.33, 1866.67, 67.0])
    for i0 in range(0, n_samples, block):
        t = np.arange(i0, min(i0 + block, n_samples)) / fs_hz
        lines = np.sin(2 * np.pi * np.outer(t, freq)) @ amp
        yield t, 30.0 + lines + rng.normal(0.0, 0.5, (t.size, 3))


def write_record(path: str | Path, seconds: float, fs_hz: float = FS_HZ, *,
                 seed: int = 0) -> Path:
    """Write a synthetic record of ``seconds`` in the contract's chunked HDF5 layout."""
    from robomill.io.forces import write_forces_h5

    n = int(round(seconds * fs_hz))
    return write_forces_h5(path, n, fs_hz, synthetic_blocks(n, fs_hz, seed=seed))


def peak_rss_mib() -> float:
    """Peak resident set size of this process so far [MiB] (Linux ``ru_maxrss`` is in KiB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


def analyse_record(path: str | Path, fs_hz: float = FS_HZ, settings: dict | None = None,
                   chunk_samples: int = BLOCK) -> dict:
    """Run the ``forces_cut`` analysis over a record; returns the sample count, the number of
    low-band segments, the wall time [s], this process's peak RSS [MiB] and the mean forces."""
    from robomill.forces.settings import ForceAnalysisSettings
    from robomill.forces.stream import ForceSpectrumAccumulator
    from robomill.io.forces import open_force_record

    t0 = time.perf_counter()
    record = open_force_record(path, fs_hz)
    acc = ForceSpectrumAccumulator(record.fs_hz, record.n_samples,
                                   ForceAnalysisSettings.from_mapping(settings or {}))
    for t, force in record.chunks(chunk_samples):
        acc.add(t, force)
    result = acc.result()
    return {"n_samples": record.n_samples, "lowband_segments": int(result["lowband_segments"]),
            "wall_s": time.perf_counter() - t0, "peak_rss_mib": peak_rss_mib(),
            "mean_N": [float(x) for x in result["mean"]]}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m robomill.longrecord", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    w = sub.add_parser("write", help="write a synthetic record")
    w.add_argument("path")
    w.add_argument("--seconds", type=float, required=True)
    w.add_argument("--seed", type=int, default=0)
    a = sub.add_parser("analyse", help="analyse a record, print a JSON line")
    a.add_argument("path")
    a.add_argument("--fs-hz", type=float, default=FS_HZ)
    a.add_argument("--settings", default="{}", help="forces settings as JSON")
    args = ap.parse_args(argv)
    if args.command == "write":
        write_record(args.path, args.seconds, seed=args.seed)
    else:
        print(json.dumps(analyse_record(args.path, args.fs_hz, json.loads(args.settings))))
    return 0


if __name__ == "__main__":
    sys.exit(main())
