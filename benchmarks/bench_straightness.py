"""Chapter 3.2 benchmarks: one tracker run simulated (IK on a path grid + spline, against IK at
every sample) and analysed (re-ordering, spectrum, IK of the measured line, peaks, matching,
against a bare periodogram of the same profile), measured in the same run."""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np
import scipy.signal

from robomill import straightness as st
from robomill.pipeline.config import load_config, repo_root
from robomill.synth import tracker
from robomill.synth.cell import cell_from_config
from robomill.synth.process import simulate_cut


def _timed(fn, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def run(out_dir: str | Path) -> list[dict]:
    cfg = load_config(repo_root() / "config.yaml")
    cell = cell_from_config(cfg)
    r = next(x for x in tracker.tracker_runs(cfg) if x["direction"] == "px"
             and x["feed_mm_s"] == 10.0)
    cut_sim = simulate_cut(cell, r["cut"], cfg)  # the cut itself: the cell's, not the tracker's
    sim_s, df = _timed(lambda: tracker.simulate_run(cfg, cell, r["direction"], r["feed_mm_s"],
                                                    r["cut"], sim=cut_sim), repeat=2)
    t, s = tracker.motion_law(40.0, 10.0, 100.0, 815.0)

    def per_sample_ik():
        return cell.tcp_error_mm(cell.joint_path_rad(r["cut"], s))

    base_s, _ = _timed(per_sample_ik, repeat=1)
    opt = cfg["straightness"]
    kw = {k: opt[k] for k in ("ds_mm", "trim_mm", "nfft", "fmin_cycles", "fmax_per_mm",
                              "threshold", "n_peaks", "tol_bins", "detrend_order")}
    pts = df[["x_mm", "y_mm", "z_mm"]].to_numpy()
    ana_s, (prof, *_rest) = _timed(lambda: st.analyse_run(
        df["t_s"].to_numpy(), pts, robot=cell.robot, gears=cell.gears,
        tool_rotation=cell.tool_rotation(), q0_rad=cell.q_home_rad, **kw))
    per_s, _ = _timed(lambda: scipy.signal.periodogram(prof.deviation_um, fs=1 / prof.ds_mm,
                                                       window="hann", nfft=opt["nfft"]))
    n = len(df)
    return [
        {"benchmark": "straightness", "metric": "simulate one tracker run (px, 10 mm/s)",
         "value": sim_s, "unit": "s", "baseline": base_s, "ratio": base_s / sim_s,
         "note": f"{n} samples; baseline: IK + Jacobian at every sample (no grid/spline)"},
        {"benchmark": "straightness", "metric": "analyse one tracker run",
         "value": ana_s, "unit": "s", "baseline": per_s, "ratio": per_s / ana_s,
         "note": "re-order, resample, Hann spectrum, IK of the measured line, peaks, gear "
                 "match; baseline: scipy periodogram of the profile alone"},
    ]
