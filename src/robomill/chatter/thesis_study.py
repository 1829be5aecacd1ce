"""The thesis robot's chatter study: lobes for the +X, +Y, −Y slots, the mode-coupling
check, the force-peak comparison and the recommended parameters."""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

from robomill.chatter.lobe_maps import SOLVERS, lobes_dataset, speed_grid
from robomill.chatter.model import tool_from_modes
from robomill.chatter.thesis import (
    DIRECTIONS,
    cutting_from_coefficients,
    mode_coupling,
    modes_in_slot_frame,
    recommend,
)

MODE_COUPLING_RTOL = 0.005
"""Bisection bracket of the mode-coupling depth (its error is half of it)."""


def run_thesis(modes: pd.DataFrame, coeffs: pd.DataFrame, peaks: pd.DataFrame, cfg: dict,
               *, teeth: int, spindle_rpm: float, depths_mm: list[float],
               accuracy: float) -> tuple[xr.Dataset, pd.DataFrame]:
    """Lobes for the +X, +Y, −Y slots (converged to ``accuracy``, with their error), the
    mode-coupling check, the force-peak comparison and the recommendations table.

    The recommended depth applies the safety fraction on top of the error: a_rec =
    (1 − safety_fraction)(a_limit − a_limit_error), with a_limit the smaller of the
    regenerative and mode-coupling depths and a_limit_error the discretization error of the
    regenerative depth (sem; none for zoa) or the bisection half-bracket of the mode-coupling
    depth; ``stability_margin_min`` = (a_limit − a_limit_error)/a − 1 is the margin at the
    pessimistic end of the error and decides ``chatter_free``. The study's ``spindle_rpm`` is
    added to the speed grid (``chatter.thesis.spindle_rpm``) where the grid misses it, so that
    its recommendation rows are at the speed the study cut with."""
    cut = cutting_from_coefficients(coeffs, teeth)
    rpm = speed_grid(cfg["spindle_rpm"])
    if spindle_rpm is not None and not np.isclose(rpm, spindle_rpm, rtol=1e-9, atol=0).any():
        rpm = np.sort(np.append(rpm, float(spindle_rpm)))  # the study's own speed, exactly
    lobes, mc, rows = _slot_lobes(modes, cut, rpm, cfg, spindle_rpm=spindle_rpm,
                                  depths_mm=depths_mm, accuracy=accuracy)
    _add_mode_coupling(lobes, mc)
    fmed = _add_force_peaks(lobes, peaks)
    _add_frf(lobes, modes)
    lobes.attrs.update({"Kt_N_m2": cut.Kt_N_m2, "Kr": cut.Kr, "teeth": cut.teeth,
                        "thesis_spindle_rpm": spindle_rpm, "thesis_depths_mm": list(depths_mm)})
    return lobes, _recommendations(rows, mc, fmed, cfg["safety_fraction"])


def _slot_lobes(modes: pd.DataFrame, cut, rpm: np.ndarray, cfg: dict, *, spindle_rpm,
                depths_mm: list[float], accuracy: float):
    """Each slot direction's lobes (zoa and converged sem), its mode-coupling check and its
    recommendation rows (:func:`robomill.chatter.thesis.recommend`), the lobes concatenated
    over ``direction``."""
    dmax = cfg["depth_max_mm"] * 1e-3
    per_dir, mc, rows = [], [], []
    for d in DIRECTIONS:
        modes_d = modes_in_slot_frame(modes, d)
        tool = tool_from_modes(modes_d)
        ds = lobes_dataset(tool, cut, rpm, depth_max_m=dmax, accuracy=accuracy)
        per_dir.append(ds)
        mc.append(mode_coupling(modes_d, cut, depth_max_m=dmax, rtol=MODE_COUPLING_RTOL))
        for s in SOLVERS:
            err = ds["a_crit_error_mm"].values * 1e-3 if s == "sem" else None
            rows += recommend(ds["a_crit_mm"].sel(solver=s).values * 1e-3, rpm,
                              ds["chatter_hz"].sel(solver=s).values, d,
                              thesis_rpm=spindle_rpm,
                              thesis_depths_m=[x * 1e-3 for x in depths_mm],
                              safety_fraction=cfg["safety_fraction"], solver=s,
                              a_error_m=err)
    lobes = xr.concat(per_dir, dim=xr.DataArray(list(DIRECTIONS), dims="direction"))
    lobes["direction"].attrs = {"units": "1", "long_name": "slot feed direction (px: +X, "
                                "py: +Y, my: -Y)"}
    rel = lobes["a_crit_error_mm"] / lobes["a_crit_mm"].sel(solver="sem")
    lobes.attrs["worst_relative_error"] = float(rel.max()) if rel.notnull().any() else np.nan
    return lobes, mc, rows


def _add_force_peaks(lobes: xr.Dataset, peaks: pd.DataFrame) -> list[float]:
    """The dominant force peaks (60–120 Hz in the thesis) by direction: smallest, median and
    largest over the cuts, added to ``lobes``; returns the medians."""
    pk = peaks.copy()
    pk["direction"] = pk["cut"].astype(str).str.rsplit("_", n=1).str[-1]
    fmin = [pk.loc[pk.direction == d, "dominant_hz"].min() for d in DIRECTIONS]
    fmed = [pk.loc[pk.direction == d, "dominant_hz"].median() for d in DIRECTIONS]
    fmax = [pk.loc[pk.direction == d, "dominant_hz"].max() for d in DIRECTIONS]
    for name, vals, ln in (("force_peak_min_hz", fmin, "smallest"),
                           ("force_peak_median_hz", fmed, "median"),
                           ("force_peak_max_hz", fmax, "largest")):
        lobes[name] = ("direction", np.asarray(vals, float),
                       {"units": "Hz", "long_name": f"{ln} dominant force peak over the cuts"})
    return fmed


def _add_mode_coupling(lobes: xr.Dataset, mc: list[dict]) -> None:
    """Each direction's mode-coupling depth, frequency and coupled pair, added to ``lobes``."""
    lobes["mode_coupling_a_mm"] = ("direction", [x["a_mc_m"] * 1e3 for x in mc],
                                   {"units": "mm", "long_name": "mode-coupling critical depth "
                                    "(2-D model without delay)"})
    lobes["mode_coupling_hz"] = ("direction", [x["frequency_hz"] for x in mc],
                                 {"units": "Hz", "long_name": "mode-coupling frequency"})
    lobes["coupled_mode_hz"] = (("direction", "pair"), [x["pair_hz"] for x in mc],
                                {"units": "Hz", "long_name": "natural frequencies of the "
                                 "coupled pair"})
    lobes["coupled_mode"] = (("direction", "pair"), [x["pair"] for x in mc],
                             {"units": "1", "long_name": "row index in modes.csv of the "
                              "coupled pair"})
    lobes["pair"] = ("pair", [0, 1], {"units": "1", "long_name": "member of the pair"})


def _add_frf(lobes: xr.Dataset, modes: pd.DataFrame) -> None:
    """|G| of each direction's tool in the slot frame, 1–200 Hz, added to ``lobes``."""
    lobes["frequency"] = ("frequency", np.linspace(1.0, 200.0, 400),
                          {"units": "Hz", "long_name": "frequency"})
    frf = np.stack([np.abs(tool_from_modes(modes_in_slot_frame(modes, d))
                           .frf(lobes["frequency"].values)) for d in DIRECTIONS])
    lobes["frf_abs_m_N"] = (("direction", "out", "in", "frequency"), frf,
                            {"units": "m/N", "long_name": "|G| in the slot frame"})
    lobes["out"] = ("out", ["feed", "normal"], {"units": "1", "long_name": "response axis"})
    lobes["in"] = ("in", ["feed", "normal"], {"units": "1", "long_name": "force axis"})


def _recommendations(rows: list[dict], mc: list[dict], fmed: list[float],
                     safety_fraction: float) -> pd.DataFrame:
    """The recommendation rows with the mode-coupling cap, the limit and its error, the
    recommended depth and its margins (the rule of :func:`run_thesis`)."""
    rec = pd.DataFrame(rows)
    # mode coupling does not depend on speed: it caps the depth at every speed
    amc = {d: x["a_mc_m"] * 1e3 for d, x in zip(DIRECTIONS, mc, strict=True)}
    rec["a_mode_coupling_mm"] = rec["direction"].map(amc)
    limit = np.fmin(rec["a_crit_mm"], rec["a_mode_coupling_mm"])
    by_mc = rec["a_mode_coupling_mm"] < rec["a_crit_mm"]
    limit_err = np.where(by_mc, 0.5 * MODE_COUPLING_RTOL * rec["a_mode_coupling_mm"],
                         rec["a_crit_error_mm"].fillna(0.0))
    is_rec = rec["kind"] == "recommended"
    rec.loc[is_rec, "axial_depth_mm"] = ((1 - safety_fraction) * (limit - limit_err)[is_rec])
    rec["a_limit_mm"] = limit
    rec["a_limit_error_mm"] = limit_err
    rec["limited_by"] = np.where(by_mc, "mode_coupling", "regenerative")
    rec["stability_margin"] = rec["a_limit_mm"] / rec["axial_depth_mm"] - 1
    rec["stability_margin_min"] = ((rec["a_limit_mm"] - rec["a_limit_error_mm"])
                                   / rec["axial_depth_mm"] - 1)
    rec["chatter_free"] = rec["stability_margin_min"] > 0
    fpk = dict(zip(DIRECTIONS, fmed, strict=True))
    rec["force_peak_median_hz"] = rec["direction"].map(fpk)
    return rec
