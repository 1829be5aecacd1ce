"""Per-rule wall time and peak RSS from the rules' `benchmark:` files of the last run."""

from __future__ import annotations

from pathlib import Path

import pandas as pd


def run(out_dir: Path) -> list[dict]:
    rows = []
    root = Path("results/benchmarks/rules")
    for tsv in sorted(root.rglob("*.tsv")):
        df = pd.read_csv(tsv, sep="\t")
        rule = tsv.relative_to(root).with_suffix("").as_posix()
        rows.append({"benchmark": "rule", "metric": f"{rule} wall", "value": df["s"].max(),
                     "unit": "s", "baseline": None, "ratio": None, "note": ""})
        rows.append({"benchmark": "rule", "metric": f"{rule} peak RSS",
                     "value": pd.to_numeric(df["max_rss"], errors="coerce").max(), "unit": "MB",
                     "baseline": None, "ratio": None, "note": ""})
    if rows:
        pd.DataFrame(rows).to_csv(out_dir / "rules.csv", index=False)
    return rows
