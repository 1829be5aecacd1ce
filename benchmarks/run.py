"""`make bench`: performance measurements, each beside a baseline measured in the same run.

Every benchmark is a function ``bench_<name>(out_dir) -> list[dict]`` registered in
``BENCHMARKS``; rows have ``benchmark, metric, value, unit, baseline, ratio, note``. Results go
to ``results/benchmarks/summary.csv`` (and per-benchmark CSVs).
"""

from __future__ import annotations

import argparse
import importlib
import sys
import time
from pathlib import Path

import pandas as pd

BENCH_DIR = Path(__file__).resolve().parent
sys.path.insert(0, str(BENCH_DIR))

MODULES = ["bench_chatter", "bench_surface", "bench_forces", "bench_straightness",
           "bench_longrecord", "bench_fresh", "bench_study", "bench_plan"]
"""Benchmark modules in benchmarks/; each exposes ``run(out_dir) -> list[dict]``."""


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__)
    ap.add_argument("--out", default="results/benchmarks")
    ap.add_argument("--only", nargs="*", help="run only these benchmark modules")
    ap.add_argument("--book", default="results/thesis",
                    help="book folder that gets the benchmarks page (if it exists)")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for name in MODULES:
        if args.only and name not in args.only:
            continue
        if not (BENCH_DIR / f"{name}.py").exists():
            continue
        t0 = time.perf_counter()
        mod = importlib.import_module(name)
        got = mod.run(out)
        print(f"{name}: {len(got)} rows in {time.perf_counter() - t0:.1f} s", flush=True)
        rows.extend(got)
    df = pd.DataFrame(rows)
    summary = out / "summary.csv"
    if args.only and summary.exists():  # a partial run keeps the other benchmarks' rows
        old = pd.read_csv(summary)
        df = pd.concat([old[~old["benchmark"].isin(df.get("benchmark", []))], df])
    df.to_csv(summary, index=False)
    print(df.to_string(index=False))
    if Path(args.book).joinpath("index.html").exists():
        from robomill.pipeline.book import add_benchmarks_page

        print(f"book page: {add_benchmarks_page(args.book, out / 'summary.csv')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
