"""Chapter 1's findings: the numbers the calibration chapter states, computed from its
artefacts and rendered by the chapter (:mod:`robomill.pipeline.prose`): the circle fits,
the joint-error regression on the held-out steps and the backlash, the base deflection
against the joint-2 compliance (eq. 1.6) and the accuracy of the three models on the points
not used for identification."""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue
from robomill.calibration.accuracy import improvement_ratios
from robomill.findings import Findings

_MODEL = catalogue.artefact("calibration.model")
_ACCURACY = catalogue.artefact("calibration.accuracy")
_ARCSEC_RAD = np.pi / 180 / 3600
_FORMS = ("polynomial", "fourier", "fourier+polynomial")


def _span(values) -> list[float]:
    v = np.asarray(values, float)
    return [float(np.nanmin(v)), float(np.nanmax(v))]


def calibration_findings(model: xr.Dataset, accuracy: pd.DataFrame, *,
                         holdout_every: int | None = None) -> Findings:
    """The findings of the calibration stage.

    Parameters
    ----------
    model
        ``results/calibration/model.nc`` (``circle_rms_mm``, ``circle_radius_mm``,
        ``error_validation_rms_rad(joint, form)``, ``backlash_rad``,
        ``base_compliance_rad_per_Nm``, ``base_fit_r2``, ``compliance_rad_per_Nm``; attribute
        ``gravity_model``).
    accuracy
        ``results/calibration/accuracy.csv`` indexed by ``model`` (``nominal``,
        ``geometric``, ``full``; ``n_points, mean_mm, rms_mm, p95_mm, max_mm``).
    holdout_every
        ``calibration.error_model.holdout_every``: every such step was held out to choose the
        polynomial degree (``None``: not stated).

    Returns
    -------
    Findings
        ``circle_rms_um`` (per joint), ``circle_radius_mm_range``; ``n_joints``,
        ``n_forms`` (regression forms compared), ``holdout_every``,
        ``combined_form_best_joints`` (joints whose held-out RMS is smallest with the
        combined Fourier + polynomial form), ``heldout_rms_arcsec_range``,
        ``backlash_arcsec_range``; ``has_gravity_model``, ``gravity_model``, and with it
        ``base_compliance_nrad_per_Nm``, ``base_fit_r2``, ``joint2_compliance_urad_per_Nm``,
        ``base_share_of_joint2_pct``; ``n_points`` and ``{nominal,geometric,full}_{mean,rms,
        p95,max}_mm``, ``improvement_geometric``, ``improvement_full`` (nominal RMS over the
        model's).
    """
    found = Findings("calibration")
    found.add("circle_rms_um", [1000.0 * float(v) for v in model["circle_rms_mm"].values],
              "um", artefact=_MODEL, what="circle_rms_mm per joint")
    found.add("circle_radius_mm_range", _span(model["circle_radius_mm"].values), "mm",
              artefact=_MODEL, what="circle_radius_mm")
    val = model["error_validation_rms_rad"].to_pandas() / _ARCSEC_RAD
    forms = [f for f in _FORMS if f in val.columns]
    best = val[forms].idxmin(axis=1)
    found.add("n_joints", int(len(val)), artefact=_MODEL, what="joint")
    found.add("n_forms", len(forms), artefact=_MODEL, what="error_validation_rms_rad: form")
    if holdout_every is not None:
        found.add("holdout_every", int(holdout_every), artefact="config.yaml",
                  what="every n-th step held out",
                  config_key="calibration.error_model.holdout_every")
    found.add("combined_form_best_joints", int((best == "fourier+polynomial").sum()),
              artefact=_MODEL, what="error_validation_rms_rad: smallest held-out RMS")
    found.add("heldout_rms_arcsec_range", _span(val["fourier+polynomial"]), "arcsec",
              artefact=_MODEL, what="error_validation_rms_rad[form = fourier+polynomial]")
    found.add("backlash_arcsec_range", _span(model["backlash_rad"].values / _ARCSEC_RAD),
              "arcsec", artefact=_MODEL, what="backlash_rad")
    gravity = str(model.attrs.get("gravity_model", ""))
    has_gravity = not gravity.startswith("none")
    found.add("has_gravity_model", has_gravity, artefact=_MODEL, what="attribute gravity_model")
    found.add("gravity_model", gravity, artefact=_MODEL, what="attribute gravity_model")
    if has_gravity:
        c_base = float(model["base_compliance_rad_per_Nm"])
        c2 = float(model["compliance_rad_per_Nm"].sel(joint=2))
        found.add("base_compliance_nrad_per_Nm", 1e9 * c_base, "nrad/(N m)", artefact=_MODEL,
                  what="base_compliance_rad_per_Nm")
        found.add("base_fit_r2", float(model["base_fit_r2"]), artefact=_MODEL,
                  what="base_fit_r2")
        found.add("joint2_compliance_urad_per_Nm", 1e6 * c2, "urad/(N m)", artefact=_MODEL,
                  what="compliance_rad_per_Nm[joint = 2]")
        found.add("base_share_of_joint2_pct", 100.0 * c_base / c2 if c2 > 0 else None, "%",
                  artefact=_MODEL, what="base over joint-2 compliance (none: joint 2 rigid)")
    found.add("n_points", int(accuracy.loc["nominal", "n_points"]), artefact=_ACCURACY,
              what="n_points")
    for m in ("nominal", "geometric", "full"):
        for stat in ("mean", "rms", "p95", "max"):
            found.add(f"{m}_{stat}_mm", float(accuracy.loc[m, f"{stat}_mm"]), "mm",
                      artefact=_ACCURACY, what=f"{stat}_mm[model = {m}]")
    ratios = improvement_ratios(accuracy)
    found.add("improvement_geometric", float(ratios["geometric"]), artefact=_ACCURACY,
              what="rms_mm[nominal] / rms_mm[geometric]")
    found.add("improvement_full", float(ratios["full"]), artefact=_ACCURACY,
              what="rms_mm[nominal] / rms_mm[full]")
    return found
