"""The findings of the chatter stage (chapter 4): every number, flag and verdict the chapter
states, computed from the stage's artefacts (:mod:`robomill.findings`).

Inputs: the lobes of the configured cases (``results/chatter/cases/<name>.nc``), the Shagniev 2019
time-domain study (``simulation.nc``), the lobes of the identified robot (``lobes.nc``) and
its recommendations (``recommendations.csv``). A cut is chatter-free when its pessimistic
stability margin is positive (``stability_margin_min > 0``, decided upstream by
:mod:`robomill.chatter.slot_model`); the recommended depth keeps ``chatter.thesis.safety_fraction``
below the limit; the lobes are converged to ``chatter.accuracy``.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue, references
from robomill.chatter.tables import onset_table
from robomill.findings import Findings

BENCHMARK = "insperger2004_down005"
SLOT = "insperger2004_slot"
SIM = catalogue.artefact("chatter.simulation")
LOBES = catalogue.artefact("chatter.lobes")
RECS = catalogue.artefact("chatter.recommendations")
CHECK_RPM = (6400.0, 8400.0)
"""Speeds at which the benchmark's converged semi-discretization depth is known."""


def _case(f: Findings, name: str, ds: xr.Dataset) -> None:
    art = catalogue.artefact("chatter.case", chatter_case=name)
    rpm = ds["spindle_rpm"].values
    a_z = ds["a_crit_mm"].sel(solver="zoa").values
    a_s = ds["a_crit_mm"].sel(solver="sem").values
    err = ds["a_crit_error_mm"].values
    kind = ds["bifurcation"].values.astype(str)
    flip = kind == "flip"
    f.add("bench_case", name, artefact=art, what="attrs.case_name")
    f.add("bench_published", name == BENCHMARK, artefact=art,
          what=f"attrs.case_name == {BENCHMARK} (the published benchmark)")
    _case_setup(f, art, ds.attrs)
    f.add("bench_accuracy_pct", 100 * float(ds.attrs["accuracy"]), "%", artefact=art,
          what="attrs.accuracy", config_key="chatter.accuracy")
    f.add("bench_hopf_min_mm", float(np.nanmin(np.where(kind == "hopf", a_s, np.nan))), "mm",
          artefact=art, what="a_crit_mm[solver=sem] where bifurcation == hopf, min")
    f.add("bench_n_speeds", int(rpm.size), artefact=art, what="spindle_rpm")
    f.add("bench_n_flip", int(flip.sum()), artefact=art, what="bifurcation == flip")
    f.add("bench_has_flip", bool(flip.any()), artefact=art, what="bifurcation == flip")
    if flip.any():
        i = int(np.nanargmin(np.where(flip, a_s, np.nan)))
        f.add("bench_flip_rpm", [float(rpm[flip].min()), float(rpm[flip].max())], "rpm",
              artefact=art, what="spindle_rpm where flip")
        f.add("bench_flip_min_mm", float(a_s[i]), "mm", artefact=art,
              what="a_crit_mm[solver=sem] where flip, min")
        f.add("bench_flip_min_rpm", float(rpm[i]), "rpm", artefact=art, what="its speed")
        f.add("bench_flip_zoa_mm", float(a_z[i]), "mm", artefact=art,
              what="a_crit_mm[solver=zoa] at that speed")
    rel = 100 * err / a_s
    w = int(np.nanargmax(rel))
    f.add("bench_worst_err_pct", float(rel[w]), "%", artefact=art,
          what="a_crit_error_mm / a_crit_mm[solver=sem], max", verdict=(
              "pass" if rel[w] <= 100 * float(ds.attrs["accuracy"]) else "fail"),
          threshold=float(ds.attrs["accuracy"]), config_key="chatter.accuracy")
    f.add("bench_worst_err_mm", float(err[w]), "mm", artefact=art, what="a_crit_error_mm")
    f.add("bench_worst_rpm", float(rpm[w]), "rpm", artefact=art, what="spindle_rpm")
    f.add("bench_worst_order", int(ds["collocation_order"].values[w]), artefact=art,
          what="collocation_order")
    checks = [n for n in CHECK_RPM if (rpm == n).any()]
    f.add("bench_has_checks", bool(checks) and name == BENCHMARK, artefact=art,
          what="spindle_rpm 6400 and 8400")
    for n in checks:
        f.add(f"bench_a_{n:.0f}rpm_mm", float(a_s[rpm == n][0]), "mm", artefact=art,
              what=f"a_crit_mm[solver=sem,spindle_rpm={n}]")
        f.add(f"bench_err_{n:.0f}rpm_mm", float(err[rpm == n][0]), "mm", artefact=art,
              what=f"a_crit_error_mm[spindle_rpm={n}]")


def _case_setup(f: Findings, art: str, attrs: Mapping[str, Any]) -> None:
    """The configured case as the chapter describes it (``config.yaml: chatter.cases``, kept
    in the case's attributes); the speed of the deepest flip lobe of a one-mode tool,
    Ω ≈ 60·2 f_n / (3 N) rpm (Insperger & Stépán 2004)."""
    teeth = int(attrs["case_teeth"])
    f.add("bench_teeth", teeth, artefact=art, what="attrs.case_teeth")
    f.add("bench_Kt_N_m2", float(attrs["case_Kt_N_m2"]), "N/m²", artefact=art,
          what="attrs.case_Kt_N_m2")
    f.add("bench_Kn_N_m2", float(attrs["case_Kt_N_m2"]) * float(attrs["case_Kr"]), "N/m²",
          artefact=art, what="attrs.case_Kt_N_m2 × attrs.case_Kr")
    f.add("bench_milling", str(attrs["case_milling"]), artefact=art, what="attrs.case_milling")
    f.add("bench_immersion", float(attrs["case_radial_immersion"]), artefact=art,
          what="attrs.case_radial_immersion")
    rng = json.loads(attrs["case_spindle_rpm"])
    f.add("bench_rpm_range", [float(rng["start"]), float(rng["stop"])], "rpm", artefact=art,
          what="attrs.case_spindle_rpm")
    f.add("bench_depth_max_mm", float(attrs["depth_max_mm"]), "mm", artefact=art,
          what="attrs.depth_max_mm")
    modes = [m for axis in json.loads(attrs["case_modes"]).values() for m in axis]
    f.add("bench_one_mode", len(modes) == 1, artefact=art, what="attrs.case_modes")
    if len(modes) == 1:
        m = modes[0]
        f.add("bench_fn_hz", float(m["f_hz"]), "Hz", artefact=art, what="attrs.case_modes")
        f.add("bench_zeta", float(m["zeta"]), artefact=art, what="attrs.case_modes")
        f.add("bench_k_N_m", float(m["k_N_m"]), "N/m", artefact=art, what="attrs.case_modes")
        f.add("bench_flip_speed_rpm", 60 * 2 * float(m["f_hz"]) / (3 * teeth), "rpm",
              artefact=art, what="60·2 f_n / (3 N)")


def _seed_setup(f: Findings, sim: xr.Dataset) -> None:
    """The Shagniev 2019 model's parameters (``attrs.seed_params``) and its tool's partial
    frequency on the suspension, √(c_s/m_s)/2π."""
    p = json.loads(sim.attrs["seed_params"])
    for key, name, unit, scale in (("seed_m_kg", "m_kg", "kg", 1), ("seed_m_s_kg", "m_s_kg",
                                                                    "kg", 1),
                                   ("seed_c_s_N_m", "c_s_N_m", "N/m", 1),
                                   ("seed_teeth", "teeth", "", 1),
                                   ("seed_Kt_MPa", "Kt_N_m2", "MPa", 1e-6),
                                   ("seed_Kr", "Kr", "", 1),
                                   ("seed_phi_ex_deg", "phi_ex_rad", "°", 180 / np.pi),
                                   ("seed_feed_m_s", "feed_m_s", "m/s", 1),
                                   ("seed_force_N", "force_setpoint_N", "N", 1)):
        f.add(key, scale * p[name], unit, artefact=SIM, what=f"attrs.seed_params.{name}")
    f.add("seed_tool_hz", float(np.sqrt(p["c_s_N_m"] / p["m_s_kg"]) / (2 * np.pi)), "Hz",
          artefact=SIM, what="sqrt(c_s / m_s) / 2π")


def _slot(f: Findings, ds: xr.Dataset | None) -> None:
    f.add("has_slot", ds is not None,
          artefact=catalogue.artefact("chatter.case", chatter_case=SLOT), what="file")
    if ds is None:
        return
    art = catalogue.artefact("chatter.case", chatter_case=SLOT)
    f.add("slot_teeth", int(ds.attrs["case_teeth"]), artefact=art, what="attrs.case_teeth")
    modes = json.loads(ds.attrs["case_modes"])
    f.add("slot_symmetric", modes.get("x") == modes.get("y"), artefact=art,
          what="attrs.case_modes: the x modes equal the y modes")
    az, asd = (ds["a_crit_mm"].sel(solver=s).values for s in ("zoa", "sem"))
    f.add("slot_zoa_min_mm", float(np.nanmin(az)), "mm", artefact=art,
          what="a_crit_mm[solver=zoa] min")
    f.add("slot_sem_min_mm", float(np.nanmin(asd)), "mm", artefact=art,
          what="a_crit_mm[solver=sem] min")
    f.add("slot_max_diff_pct", 100 * float(np.nanmax(np.abs(asd / az - 1))), "%",
          artefact=art, what="|sem/zoa - 1| max")
    f.add("slot_worst_err_pct", 100 * float(ds.attrs["worst_relative_error"]), "%",
          artefact=art, what="attrs.worst_relative_error")


def _seed(f: Findings, sim: xr.Dataset) -> None:
    a = sim.attrs
    if "seed_params" in a:
        _seed_setup(f, sim)
    for key, attr, unit in (("seed_a_star_mm", "a_star_mm", "mm"),
                            ("seed_n_rpm", "spindle_rpm_seed", "rpm"),
                            ("seed_boundary_mm", "a_boundary_at_n_mm", "mm"),
                            ("seed_point1_mm", "point1_depth_mm", "mm"),
                            ("seed_point2_mm", "point2_depth_mm", "mm"),
                            ("seed_chatter_hz_zoa", "chatter_hz_zoa_at_n", "Hz"),
                            ("seed_sdm_steps", "sdm_steps_per_period", ""),
                            ("seed_sdm_chatter_hz", "sdm_chatter_hz_at_n", "Hz"),
                            ("seed_sdm_bifurcation", "sdm_bifurcation_at_n", ""),
                            ("seed_tooth_hz", "tooth_hz", "Hz"),
                            ("seed_growth_sdm_1_s", "growth_rate_sdm_point2_1_s", "1/s"),
                            ("seed_growth_sim_1_s", "growth_rate_simulated_point2_1_s", "1/s"),
                            ("seed_growth_window_teeth", "growth_window_teeth", ""),
                            ("seed_detector_window_s", "detector_window_s", "s"),
                            ("seed_adapted_mm", "adapted_depth_mm", "mm"),
                            ("seed_growth_adapted_1_s", "growth_rate_sdm_adapted_1_s", "1/s"),
                            ("seed_indicator_p1_N", "indicator_final_point1_N", "N"),
                            ("seed_indicator_p2_N", "indicator_final_point2_N", "N"),
                            ("seed_indicator_p2_adaptive_N", "indicator_final_point2_adaptive_N",
                             "N")):
        f.add(key, a.get(attr), unit, artefact=SIM, what=f"attrs.{attr}")
    f.add("seed_boundary_ratio", a["a_boundary_at_n_mm"] / a["a_star_mm"], artefact=SIM,
          what="a_boundary_at_n_mm / a_star_mm")
    f.add("seed_kt_noise_pct", 100 * float(a["Kt_noise_fraction"]), "%", artefact=SIM,
          what="attrs.Kt_noise_fraction", config_key="chatter.seed.params.Kt_noise_fraction")
    f.add("seed_efold_s", -1 / a["growth_rate_sdm_adapted_1_s"], "s", artefact=SIM,
          what="-1 / growth_rate_sdm_adapted_1_s")
    f.add("seed_adapted_below_pct", 100 * (1 - a["adapted_depth_mm"] / a["a_boundary_at_n_mm"]),
          "%", artefact=SIM, what="1 - adapted_depth_mm / a_boundary_at_n_mm")
    f.add("seed_adaptive_share", a["indicator_final_point2_adaptive_N"]
          / a["indicator_final_point2_N"], artefact=SIM,
          what="indicator_final_point2_adaptive_N / indicator_final_point2_N")
    a_sdm = sim["seed_a_crit_mm"].sel(solver="sdm").values
    rel = 100 * sim["seed_a_crit_error_mm"].values / a_sdm
    w = int(np.nanargmax(rel))
    f.add("seed_sdm_worst_err_pct", float(rel[w]), "%", artefact=SIM,
          what="seed_a_crit_error_mm / seed_a_crit_mm[solver=sdm], max")
    f.add("seed_sdm_worst_rpm", float(sim["spindle_rpm"].values[w]), "rpm", artefact=SIM,
          what="spindle_rpm")
    f.add("seed_sdm_median_err_pct", float(np.nanmedian(rel)), "%", artefact=SIM,
          what="relative error, median")
    f.add("seed_a_star_sem_mm", float(np.nanmin(sim["seed_a_crit_sem_mm"].values)), "mm",
          artefact=SIM, what="seed_a_crit_sem_mm min")
    ind2 = sim["indicator_N"].sel(run="point2").values
    f.add("seed_point2_chatter_hz",
          float(sim["indicator_hz"].sel(run="point2").values[int(np.nanargmax(ind2))]), "Hz",
          artefact=SIM, what="indicator_hz[run=point2] at the largest indicator")
    d1 = np.atleast_1d(a.get("detections_point1_s", []))
    f.add("seed_point1_detections_s", d1, "s", artefact=SIM, what="attrs.detections_point1_s")
    f.add("seed_point1_stable", d1.size == 0, artefact=SIM, what="no detection at point 1")
    det = np.atleast_1d(a.get("detections_adaptive_s", []))
    f.add("seed_first_detection_s", float(det[0]) if det.size else None, "s", artefact=SIM,
          what="attrs.detections_adaptive_s first")
    steps = np.atleast_1d(a.get("adaptation_setpoint_fraction", []))
    f.add("seed_setpoint_pct", 100 * steps, "%", artefact=SIM,
          what="attrs.adaptation_setpoint_fraction")
    f.add("seed_lowered_pct", 100 * float(a["adaptation_lowered_fraction"]), "%",
          artefact=SIM, what="attrs.adaptation_lowered_fraction")
    onset = onset_table(sim)
    f.add("onset_n", len(onset), artefact=SIM, what="onset runs")
    f.add("onset_agree", int(onset["agree"].sum()), artefact=SIM,
          what="lobes and time domain agree")


def _robot(f: Findings, lobes: xr.Dataset, rec: pd.DataFrame, safety_fraction: float) -> None:
    thesis = rec[(rec["kind"] == "thesis") & (rec["solver"] == "sem")]
    speeds = sorted({float(n) for n in thesis["spindle_rpm"]})
    f.add("robot_rpms", speeds, "rpm", artefact=RECS,
          what="kind == thesis: spindle_rpm, each speed once (the cuts' own)")
    f.add("robot_rpm", speeds[0] if len(speeds) == 1 else None, "rpm", artefact=RECS,
          what="kind == thesis: spindle_rpm, where every cut has the same")
    f.add("robot_speeds", (f"{speeds[0]:.0f} rpm" if len(speeds) == 1 else
                           ", ".join(f"{n:.0f}" for n in speeds) + " rpm"), artefact=RECS,
          what="kind == thesis: spindle_rpm")
    f.add("robot_accuracy_pct", 100 * float(lobes.attrs["accuracy"]), "%", artefact=LOBES,
          what="attrs.accuracy", config_key="chatter.accuracy")
    rel = (lobes["a_crit_error_mm"] / lobes["a_crit_mm"].sel(solver="sem")).values
    iw = np.unravel_index(int(np.nanargmax(rel)), rel.shape)
    f.add("robot_worst_err_pct", 100 * float(rel[iw]), "%", artefact=LOBES,
          what="a_crit_error_mm / a_crit_mm[solver=sem], max")
    f.add("robot_worst_direction", str(lobes["direction"].values[iw[0]]), artefact=LOBES,
          what="direction")
    f.add("robot_worst_rpm", float(lobes["spindle_rpm"].values[iw[1]]), "rpm", artefact=LOBES,
          what="spindle_rpm")
    f.add("robot_worst_err_mm", float(lobes["a_crit_error_mm"].values[iw]), "mm",
          artefact=LOBES, what="a_crit_error_mm")
    _axial(f, lobes, thesis)
    ok = rec[(rec["kind"] == "thesis") & (rec["solver"] == "sem")]
    best = rec[(rec["kind"] == "recommended") & (rec["solver"] == "sem")]
    at = (lambda r: "") if len(speeds) == 1 else (lambda r: f" at {r.spindle_rpm:.0f} rpm")
    f.add("cut_margins", [f"{r.direction} {r.axial_depth_mm:.2f} mm{at(r)}: "
                          f"{100 * r.stability_margin:.0f} %" for r in ok.itertuples()],
          artefact=RECS, what="kind == thesis, solver == sem: stability_margin")
    f.add("n_cuts_chatter_free", int(ok["chatter_free"].astype(bool).sum()), artefact=RECS,
          what="chatter_free (stability_margin_min > 0)")
    f.add("n_cuts", len(ok), artefact=RECS, what="kind == thesis, solver == sem")
    f.add("safety_pct", 100 * safety_fraction, "%", artefact=RECS,
          what="recommended depth = (1 - safety) (a_limit - a_limit_error)",
          config_key="chatter.thesis.safety_fraction")
    f.add("recommendations", [
        f"slot **{r.direction}**: at {r.spindle_rpm:.0f} rpm, a ≤ {r.axial_depth_mm:.2f} mm "
        f"(margin {100 * r.stability_margin:.0f} %, {100 * r.stability_margin_min:.0f} % at "
        f"the pessimistic end of the error; {r.limited_by} limit {r.a_limit_mm:.2f} mm)"
        for r in best.itertuples()], artefact=RECS, what="kind == recommended, solver == sem")


def _axial(f: Findings, lobes: xr.Dataset, thesis: pd.DataFrame) -> None:
    """What the axial force does to the robot's lobes: per slot, at the speed most of its
    cuts were made at, the zero-order depth with it and without it (the planar model)."""
    ka = float(lobes.attrs.get("Ka", np.nan))
    f.add("robot_axial_force", bool(np.isfinite(ka)), artefact=LOBES,
          what="attrs.Ka = Kac/Ktc finite: the lobes carry the axial force's row")
    if not np.isfinite(ka) or "a_crit_planar_mm" not in lobes:
        return
    f.add("robot_Kac_N_mm2", ka * float(lobes.attrs["Kt_N_m2"]) * 1e-6, "N/mm^2",
          artefact=LOBES, what="attrs.Ka × attrs.Kt_N_m2")
    lines, ratios = [], []
    for d in lobes["direction"].values:
        rpm = float(lobes["study_spindle_rpm"].sel(direction=d))
        # the study's own speeds are on the grid (slot_lobes); nearest: a speed within the
        # grid's 1e-9 tolerance of a grid point was not added again
        at = lobes.sel(direction=d).sel(spindle_rpm=rpm, method="nearest")
        axial, planar = float(at["a_crit_mm"].sel(solver="zoa")), float(at["a_crit_planar_mm"])
        ratios.append(axial / planar)
        lines.append(f"{d}: {axial:.2f} mm with the axial force, {planar:.2f} mm without "
                     f"({100 * (axial / planar - 1):+.0f} %) at {rpm:.0f} rpm")
    f.add("robot_axial_lines", lines, artefact=LOBES,
          what="a_crit_mm[solver=zoa] and a_crit_planar_mm at study_spindle_rpm")
    f.add("robot_axial_over_planar", [float(min(ratios)), float(max(ratios))], artefact=LOBES,
          what="a_crit_mm[solver=zoa] / a_crit_planar_mm at study_spindle_rpm: min, max")


def _sources(f: Findings) -> None:
    """The benchmark's converged first-order semi-discretization: numbers
    the chapter states about the literature method it replaces."""
    for key, ref in (("ref_sdm_m40_pct", "insperger2004.sdm_m40_excess_6400rpm_pct"),
                     ("ref_sdm_m80_pct", "insperger2004.sdm_m80_excess_6400rpm_pct"),
                     ("ref_sdm_m160_pct", "insperger2004.sdm_m160_excess_6400rpm_pct"),
                     ("ref_sdm_converged_6400_mm", "insperger2004.sdm_converged_6400rpm_mm"),
                     ("ref_sdm_6400_mm", "insperger2004.chatter.insperger2004_down005.a_crit_mm."
                                         "solver_sem_spindle_rpm_6400_0"),
                     ("ref_sdm_8400_mm", "insperger2004.chatter.insperger2004_down005.a_crit_mm."
                                         "solver_sem_spindle_rpm_8400_0"),
                     ("ref_force_band_hz", "thesis.forces.peak_band_hz"),
                     ("ref_hopf_minima_mm", "insperger2004.hopf_minima_mm")):
        r = references.reference(ref)
        f.add(key, r["value"], r["unit"], artefact="src/robomill/data/references.yaml",
              what=ref)


def chatter_findings(cases: Mapping[str, xr.Dataset], sim: xr.Dataset,
                     lobes: xr.Dataset | None, recommendations: pd.DataFrame | None, *,
                     safety_fraction: float, thesis_study: bool = False) -> Findings:
    """The findings of chapters 4 and 6.1 from the stage's artefacts (``cases``: name → lobes
    of a configured case; the benchmark is ``insperger2004_down005`` when configured, else the
    first case); ``safety_fraction``: ``chatter.thesis.safety_fraction``.

    Chapter 6.1 (the reference studies: the benchmark cases and Shagniev 2019) needs no data of
    the study; the robot's lobes and recommendations (chapter 4) are left out (``has_robot``
    false) when the study measured no modes or no cutting coefficients (``lobes`` None).
    ``thesis_study``: whether chapter 4 closes with its comparison with the thesis."""
    f = Findings("chatter")
    f.add("thesis_study", bool(thesis_study), what="robomill.experiment.is_thesis_study")
    f.add("has_robot", lobes is not None and recommendations is not None, artefact=LOBES,
          what="the study's lobes were computed (impact and force data)")
    if cases:
        name = BENCHMARK if BENCHMARK in cases else next(iter(cases))
        _case(f, name, cases[name])
    _slot(f, cases.get(SLOT))
    _seed(f, sim)
    if lobes is not None and recommendations is not None:
        _robot(f, lobes, recommendations, safety_fraction)
    _sources(f)
    return f


def load_cases(paths: Any, open_artefact) -> dict[str, xr.Dataset]:
    """Case datasets by their ``case_name`` attribute."""
    paths = [paths] if isinstance(paths, str) else list(paths)
    out = {}
    for p in paths:
        ds = open_artefact(p)
        out[str(ds.attrs["case_name"])] = ds
    return out
