"""The study's robot in chapter 4: lobes for each slot of the study (the cuts that share a
feed direction and a tool), the mode-coupling check, the force-peak comparison and the
recommended parameters, each cut at its own speed and depth.

The cuts come from the study (:func:`robomill.study.read_study`): a slot is the set of cuts
with one feed direction (their unit vector in the base XY plane: ``px``, ``py``, ``my`` in the
thesis' design, any ``direction_deg`` in a free one) and one tool (flutes, radial immersion,
milling); its name is the direction's (``px``, ``d45``), with the tool added where the study
cut one direction with several tools. Cut ids carry no meaning here.
"""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np
import pandas as pd
import xarray as xr

from robomill.chatter.lobe_maps import SOLVERS, lobes_dataset, speed_grid
from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel, ModeXY, tool_from_modes
from robomill.chatter.slot_model import (
    cutting_from_coefficients,
    mode_coupling,
    modes_in_slot_frame,
    recommend,
)

if TYPE_CHECKING:  # the study object is handed in; the science loads no reader of it
    from robomill.study import Study, StudyCut

MODE_COUPLING_RTOL = 0.005
"""Bisection bracket of the mode-coupling depth (its error is half of it)."""


@dataclass(frozen=True)
class Slot:
    """The cuts of the study with one feed direction and one tool."""

    name: str
    feed_xy: tuple[float, float]
    flutes: int
    radial_immersion: float
    milling: str
    cuts: tuple[StudyCut, ...]

    @property
    def points(self) -> list[tuple[float, float]]:
        """The cuts' own (spindle speed [rpm], depth [m]) pairs, each once, in order."""
        return sorted({(float(c.spindle_rpm), float(c.depth_mm) * 1e-3) for c in self.cuts})

    @property
    def spindle_rpm(self) -> float:
        """The speed most of the slot's cuts were made at (the lowest of a tie) [rpm]."""
        counts = Counter(float(c.spindle_rpm) for c in self.cuts)
        return min(counts, key=lambda s: (-counts[s], s))

    def cutting(self, coeffs: pd.DataFrame) -> CuttingModel:
        """The slot's cutting model: the identified coefficients, the slot's flutes and its
        engagement (a slot: entry 0, exit π; else :meth:`CuttingModel.from_immersion`)."""
        slot = cutting_from_coefficients(coeffs, self.flutes)
        if self.milling == "slot" or self.radial_immersion >= 1.0:
            return slot
        return CuttingModel.from_immersion(self.flutes, slot.Kt_N_m2, slot.Kr,
                                           self.radial_immersion, self.milling, slot.Ka)


def study_slots(study: Study) -> list[Slot]:
    """The slots of the study's cuts that give a speed, flutes and depth, ordered by feed
    angle (0° = +X, counter-clockwise), then tool.

    Raises
    ------
    ValueError
        No cut of the study gives a spindle speed, flutes and a depth.
    """
    groups: dict[tuple, list[StudyCut]] = {}
    for c in study.cuts:
        if c.spindle_rpm is None or c.flutes is None or c.depth_mm is None:
            continue
        key = (round(c.direction_deg % 360.0, 6), int(c.flutes),
               float(c.radial_immersion if c.radial_immersion is not None else 1.0),
               c.milling or "slot")
        groups.setdefault(key, []).append(c)
    if not groups:
        raise ValueError(f"{study.path}: no cut gives a spindle speed, flutes and a depth "
                         "(chapter 4's lobes are at the cuts' own speeds)")
    names = Counter(cuts[0].direction for cuts in groups.values())
    slots = []
    for key in sorted(groups):
        cuts = groups[key]
        _, z, ae, milling = key
        name = cuts[0].direction
        if names[name] > 1:  # one direction cut with several tools
            name = f"{name}_z{z}_ae{ae:g}_{milling}"
        slots.append(Slot(name, cuts[0].feed_xy, z, ae, milling, tuple(cuts)))
    return slots


def study_lobes(modes: pd.DataFrame, coeffs: pd.DataFrame, peaks: pd.DataFrame, cfg: dict,
               *, study: Study, accuracy: float) -> tuple[xr.Dataset, pd.DataFrame]:
    """Lobes for each slot of the study (:func:`study_slots`; converged to ``accuracy``, with
    their error), the mode-coupling check, the force-peak comparison and the recommendations
    table, each cut's (speed, depth) a row of its own.

    The recommended depth applies the safety fraction on top of the error: a_rec =
    (1 − safety_fraction)(a_limit − a_limit_error), with a_limit the regenerative depth (the
    model in which mode coupling arises with the delay) and a_limit_error its discretization
    error (sem; none for zoa); ``stability_margin_min`` = (a_limit − a_limit_error)/a − 1 is
    the margin at the pessimistic end of the error and decides ``chatter_free``. The
    delay-free mode-coupling depth is reported beside it (``a_mode_coupling_mm``) as a
    diagnostic, never as a limit: it drops the regenerative factor a slot's chip always
    carries (:mod:`robomill.chatter.coupling`). Every speed the study cut at
    is added to the speed grid (``chatter.thesis.spindle_rpm``) where the grid misses it, so
    that each cut's rows are at the speed it was made at."""
    slots = study_slots(study)
    rpm = speed_grid(cfg["spindle_rpm"])
    for s in sorted({p[0] for sl in slots for p in sl.points}):
        if not np.isclose(rpm, s, rtol=1e-9, atol=0).any():
            rpm = np.sort(np.append(rpm, s))  # the study's own speed, exactly
    lobes, mc, rows = _slot_lobes(modes, coeffs, slots, rpm, cfg, accuracy=accuracy)
    _add_mode_coupling(lobes, mc)
    fmed = _add_force_peaks(lobes, peaks, slots)
    _add_frf(lobes, modes, slots)
    speeds = sorted({p[0] for sl in slots for p in sl.points})
    teeth = sorted({sl.flutes for sl in slots})
    cut0 = slots[0].cutting(coeffs)
    lobes["study_spindle_rpm"] = ("direction", [sl.spindle_rpm for sl in slots],
                                  {"units": "rpm", "long_name": "spindle speed of most of the "
                                   "slot's cuts"})
    lobes.attrs.update({"Kt_N_m2": cut0.Kt_N_m2, "Kr": cut0.Kr,
                        "Ka": cut0.Ka if cut0.Ka is not None else float("nan"),
                        "teeth": teeth[0] if len(teeth) == 1 else teeth,
                        "thesis_spindle_rpm": speeds[0] if len(speeds) == 1 else speeds,
                        "thesis_depths_mm": sorted({float(c.depth_mm) for sl in slots
                                                    for c in sl.cuts})})
    return lobes, _recommendations(rows, mc, fmed, cfg["safety_fraction"], slots)


def _slot_lobes(modes: pd.DataFrame, coeffs: pd.DataFrame, slots: list[Slot], rpm: np.ndarray,
                cfg: dict, *, accuracy: float):
    """Each slot's lobes (zoa and converged sem), its mode-coupling check and its
    recommendation rows (:func:`robomill.chatter.slot_model.recommend`), the lobes concatenated
    over ``direction`` (the slots' names)."""
    dmax = cfg["depth_max_mm"] * 1e-3
    per_dir, mc, rows = [], [], []
    for sl in slots:
        cut = sl.cutting(coeffs)
        modes_d = modes_in_slot_frame(modes, sl.feed_xy)
        tool = tool_from_modes(modes_d)
        ds = lobes_dataset(tool, cut, rpm, depth_max_m=dmax, accuracy=accuracy)
        ds["a_crit_planar_mm"] = ("spindle_rpm", 1e3 * _planar_zoa_m(modes_d, cut, rpm),
                                  {"units": "mm", "long_name": "zero-order critical depth of "
                                   "the planar model (the axial force left out)"})
        per_dir.append(ds)
        mc.append(mode_coupling(modes_d, cut, depth_max_m=dmax, rtol=MODE_COUPLING_RTOL))
        for s in SOLVERS:
            err = ds["a_crit_error_mm"].values * 1e-3 if s == "sem" else None
            rows += recommend(ds["a_crit_mm"].sel(solver=s).values * 1e-3, rpm,
                              ds["chatter_hz"].sel(solver=s).values, sl.name,
                              study_points=sl.points,
                              safety_fraction=cfg["safety_fraction"], solver=s,
                              a_error_m=err)
    lobes = xr.concat(per_dir, dim=xr.DataArray([sl.name for sl in slots], dims="direction"))
    lobes["direction"].attrs = {"units": "1", "long_name": "slot feed direction (px: +X, "
                                "py: +Y, mx: -X, my: -Y, d<deg>: deg from +X)"}
    lobes["feed_x"] = ("direction", [sl.feed_xy[0] for sl in slots],
                       {"units": "1", "long_name": "feed direction, base X component"})
    lobes["feed_y"] = ("direction", [sl.feed_xy[1] for sl in slots],
                       {"units": "1", "long_name": "feed direction, base Y component"})
    rel = lobes["a_crit_error_mm"] / lobes["a_crit_mm"].sel(solver="sem")
    lobes.attrs["worst_relative_error"] = float(rel.max()) if rel.notnull().any() else np.nan
    return lobes, mc, rows


def _planar_zoa_m(modes: list[ModeXY], cut: CuttingModel, rpm: np.ndarray) -> np.ndarray:
    """The zero-order depth [m] of the planar model of the same modes and cut: the axial
    force and the modes' axial components left out (what the lobes would be without them)."""
    planar = [ModeXY(m.f_hz, m.zeta, m.k_N_m, m.shape[:2]) for m in modes]
    return zoa_lobes(tool_from_modes(planar), replace(cut, Ka=None), rpm)[0]


def _add_force_peaks(lobes: xr.Dataset, peaks: pd.DataFrame, slots: list[Slot]) -> list[float]:
    """The dominant force peaks (60–120 Hz in the thesis) of each slot's cuts: smallest,
    median and largest, added to ``lobes``; returns the medians."""
    slot_of = {c.id: sl.name for sl in slots for c in sl.cuts}
    pk = peaks.copy()
    pk["direction"] = pk["cut"].astype(str).map(slot_of)
    names = [sl.name for sl in slots]
    fmin = [pk.loc[pk.direction == d, "dominant_hz"].min() for d in names]
    fmed = [pk.loc[pk.direction == d, "dominant_hz"].median() for d in names]
    fmax = [pk.loc[pk.direction == d, "dominant_hz"].max() for d in names]
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
                                    "(the modal model without delay)"})
    lobes["mode_coupling_hz"] = ("direction", [x["frequency_hz"] for x in mc],
                                 {"units": "Hz", "long_name": "mode-coupling frequency"})
    lobes["coupled_mode_hz"] = (("direction", "pair"), [x["pair_hz"] for x in mc],
                                {"units": "Hz", "long_name": "natural frequencies of the "
                                 "coupled pair"})
    lobes["coupled_mode"] = (("direction", "pair"), [x["pair"] for x in mc],
                             {"units": "1", "long_name": "row index in modes.csv of the "
                              "coupled pair"})
    lobes["pair"] = ("pair", [0, 1], {"units": "1", "long_name": "member of the pair"})


def _add_frf(lobes: xr.Dataset, modes: pd.DataFrame, slots: list[Slot]) -> None:
    """|G| of each slot's tool in the slot frame, 1–200 Hz, added to ``lobes``."""
    lobes["frequency"] = ("frequency", np.linspace(1.0, 200.0, 400),
                          {"units": "Hz", "long_name": "frequency"})
    frf = np.stack([np.abs(tool_from_modes(modes_in_slot_frame(modes, sl.feed_xy))
                           .frf(lobes["frequency"].values)) for sl in slots])
    lobes["frf_abs_m_N"] = (("direction", "out", "in", "frequency"), frf,
                            {"units": "m/N", "long_name": "|G| in the slot frame (in-plane "
                             "response to each force axis)"})
    lobes["out"] = ("out", ["feed", "normal"], {"units": "1", "long_name": "response axis"})
    lobes["in"] = ("in", ["feed", "normal", "axis"][:frf.shape[2]],
                   {"units": "1", "long_name": "force axis"})


def _recommendations(rows: list[dict], mc: list[dict], fmed: list[float],
                     safety_fraction: float, slots: list[Slot]) -> pd.DataFrame:
    """The recommendation rows with the mode-coupling diagnostic, the limit and its error, the
    recommended depth and its margins (the rule of :func:`study_lobes`)."""
    rec = pd.DataFrame(rows)
    # the delay-free depth does not depend on speed: reported per direction, never a limit
    names = [sl.name for sl in slots]
    amc = {d: x["a_mc_m"] * 1e3 for d, x in zip(names, mc, strict=True)}
    rec["a_mode_coupling_mm"] = rec["direction"].map(amc)
    limit = rec["a_crit_mm"]
    limit_err = rec["a_crit_error_mm"].fillna(0.0).to_numpy()
    is_rec = rec["kind"] == "recommended"
    rec.loc[is_rec, "axial_depth_mm"] = ((1 - safety_fraction) * (limit - limit_err)[is_rec])
    rec["a_limit_mm"] = limit
    rec["a_limit_error_mm"] = limit_err
    rec["limited_by"] = "regenerative"
    rec["stability_margin"] = rec["a_limit_mm"] / rec["axial_depth_mm"] - 1
    rec["stability_margin_min"] = ((rec["a_limit_mm"] - rec["a_limit_error_mm"])
                                   / rec["axial_depth_mm"] - 1)
    rec["chatter_free"] = rec["stability_margin_min"] > 0
    fpk = dict(zip(names, fmed, strict=True))
    rec["force_peak_median_hz"] = rec["direction"].map(fpk)
    return rec
