"""Regenerate tests/data/constructed/spatialanalyzer/px_f2_sa2024.txt (run from the
repository root): the layout of a real SpatialAnalyzer 2024.2 point-stream export
(tests/data/real/spatialanalyzer/SOURCE.md: no header row, stamps to the second)."""
import datetime as dt

import numpy as np

fs, n = 200.0, 640
t = 0.65 + np.arange(n) / fs           # the stream starts 0.65 s into a clock second
rng = np.random.default_rng(2124)
x = 1520.0 + 2.0 * (t - t[0]) + rng.normal(0, 0.002, n)
y = -845.25 + rng.normal(0, 0.002, n)
z = 312.5 + rng.normal(0, 0.002, n)
clock0 = dt.datetime(2026, 2, 12, 10, 15, 7)
head = ["// SpatialAnalyzer SA 2024.2.0923.4 ( x64 )  ",
        "// Points Relative to Coordinate Frame 'A::WORLD'",
        "// AXES = CARTESIAN: X,  Y,  Z (mm)"]
rows = []
for k in range(n):
    stamp = (clock0 + dt.timedelta(seconds=float(np.floor(t[k])))).strftime("%m/%d/%y %H:%M:%S")
    rows.append(f"stream_px_f2,  feed2,  {k},  {x[k]:.6f},  {y[k]:.6f},  {z[k]:.6f},  {stamp}")
with open("tests/data/constructed/spatialanalyzer/px_f2_sa2024.txt", "w", newline="\n") as fh:
    fh.write("\n".join(head + rows) + "\n")
