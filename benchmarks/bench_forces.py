"""Force analysis at thesis scale: peak memory and throughput next to a bare FFT baseline.

Streams a synthetic 40 s record at 25 kHz (10⁶ samples × 3 axes, the longest cut) through
:class:`robomill.forces.ForceSpectrumAccumulator` in 2¹⁸-sample chunks, the way the
``forces_cut`` rule does, and measures samples/s and the peak traced memory; the baseline is
one ``numpy.fft.rfft`` of the whole record (what an unchunked spectrum would cost). The whole
study is 45 such records, ~17 M samples per axis; memory is per record, independent of count.
"""

from __future__ import annotations

import time
import tracemalloc
from pathlib import Path

import numpy as np


def run(out_dir: Path) -> list[dict]:
    from robomill.forces import (
        CuttingCoefficients,
        ForceAnalysisSettings,
        ForceSpectrumAccumulator,
        slot_force_tables,
        slot_forces_band_limited,
    )

    fs, n, chunk = 25000.0, 1_000_000, 262_144
    k = CuttingCoefficients(796, 168, 222, 27.7, 30.8, 6.7)
    tables = slot_force_tables(2, 24)
    rng = np.random.default_rng(0)

    def chunks():
        for i0 in range(0, n, chunk):
            t = np.arange(i0, min(i0 + chunk, n)) / fs
            F = slot_forces_band_limited(2 * np.pi * 466.67 * t, 0.001, 0.25, k, tables)
            yield t, F + rng.normal(0, 0.1, F.shape)

    blocks = list(chunks())  # generate outside the timed/traced region
    def analyse():
        acc = ForceSpectrumAccumulator(fs, n, ForceAnalysisSettings())
        for t, F in blocks:
            acc.add(t, F)
        return acc.result()

    t0 = time.perf_counter()
    analyse()
    dt = time.perf_counter() - t0
    tracemalloc.start()  # second pass for memory (tracing slows it down)
    analyse()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    whole = np.concatenate([b[1] for b in blocks])
    t0 = time.perf_counter()
    np.fft.rfft(whole, axis=0)
    dt_fft = time.perf_counter() - t0
    rate, rate_fft = 3 * n / dt, 3 * n / dt_fft
    return [
        {"benchmark": "forces", "metric": "chunked analysis throughput", "value": rate,
         "unit": "samples/s", "baseline": rate_fft, "ratio": rate / rate_fft,
         "note": "baseline: one numpy rfft of the whole 3-axis record"},
        {"benchmark": "forces", "metric": "peak traced memory (one 40 s record)",
         "value": peak / 2**20, "unit": "MiB", "baseline": whole.nbytes / 2**20,
         "ratio": peak / whole.nbytes, "note": "baseline: the whole record as float64; "
         "limit 2048 MiB"},
        {"benchmark": "forces", "metric": "thesis-scale analysis time (17.1 M samples/axis)",
         "value": 3 * 17.1e6 / rate, "unit": "s", "baseline": 3 * 17.1e6 / rate_fft,
         "ratio": rate_fft / rate, "note": "extrapolated from the measured throughput"},
    ]
