"""Regenerate tests/data/constructed/dynoware/dynoware25_window.csv (run from the repository
root): the layout of a real DynoWare 2.5.1.2 channel export (tests/data/real/dynoware/
SOURCE.md), planted values."""
import numpy as np

fs = 10000.0
n = 1000
t = 8.0 + np.arange(n) / fs
phi = 2 * np.pi * 200.0 * (t - 8.0)
rng = np.random.default_rng(2125)
tool = np.column_stack([60 + 80 * np.cos(phi), -40 + 90 * np.sin(phi), 55 + 20 * np.cos(2 * phi)])
plate = -tool + rng.normal(0, 0.5, tool.shape)
head = ["DynoWare,Version 2.5.1.2", "Path:,C:\\Users\\lab\\Desktop\\robomill\\",
        "Filename:,slot_s1_g1_px.dwd", "Config ID:,slot_s1_g1_px.cfg", "Setup ID:,0",
        "Manipulated:,0", "Filename 1:, ", "Filename 2:, ", "Date:, ", "Time:, ",
        "Sampling rate [Hz]:,10000", "Measuring time [s]:,20", "Delay time [s]:,0",
        "Cycle time [s]:,0", "Cycles:,1", "Samples per channel:,200001",
        "Cycle interval:,0", "Cycle No:,1", "Time,Fx,Fy,Fz", "s,N,N,N"]
rows = [",".join([f"{round(ti, 4):.4f}".rstrip("0").rstrip(".")]
                 + [f"{v:.6g}" for v in p]) for ti, p in zip(t, plate, strict=True)]
with open("tests/data/constructed/dynoware/dynoware25_window.csv", "w", newline="\n") as fh:
    fh.write("\n".join(head + rows) + "\n")
