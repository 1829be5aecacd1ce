"""Gathering the areal scans of a study into chapter 2's artefacts: one row of ISO 25178-2
parameters per scan with what its instrument states, the spectra of every scan, and for cuts
measured both ways the stylus profile's parameters beside those of the scan's profile along
the feed (both through :func:`robomill.surface.psd.analyse_profile`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue
from robomill.surface.areal import PARAMETERS

AREAL_COLUMNS = ["cut", *PARAMETERS, "valid_share", "form_degree", "feed_angle_deg", "nx",
                 "ny", "dx_um", "dy_um", "line_rq_median_um", "line_rq_p10_um",
                 "line_rq_p90_um", "profile_source", "instrument", "probe",
                 "lateral_resolution_um", "source_file", "source_format"]
"""Columns of ``results/surface/areal.csv``."""
COMPARED = ("Wq_um", "Rq_um", "Ra_um", "Rz_um", "waviness_rms_um", "roughness_rms_um")
"""Profile parameters compared between a stylus profile and a scan's profile along the feed."""


def gather_areal(scans: Sequence[xr.Dataset], profiles: Mapping[str, tuple[np.ndarray,
                                                                           np.ndarray]],
                 stylus: Mapping[str, xr.Dataset], options: Mapping[str, Any]
                 ) -> dict[str, Any]:
    """Chapter 2's areal artefacts.

    Parameters
    ----------
    scans
        :func:`robomill.surface.areal.analyse_scan` datasets with ``attrs["cut"]`` and the
        instrument's statements.
    profiles
        cut → the scan's profile along the feed ``(x_mm, z_um)``.
    stylus
        cut → the stylus profile's analysis (``results/surface/cuts/<cut>.nc``) for the cuts
        measured both ways.
    options
        ``config.yaml: surface`` (the profile analysis' settings).

    Returns
    -------
    dict
        ``areal`` (:data:`AREAL_COLUMNS`), ``spectra`` (``psd_radial``, ``psd_along``,
        ``psd_across`` along ``cut``, each on its own frequency axis, NaN outside a scan's
        range) and ``profile_vs_areal`` (``cut, parameter, stylus, areal, ratio`` for
        :data:`COMPARED` and the areal Sq; ``note`` when the scan's profile is too short for
        the analysis).
    """
    from robomill.surface.psd import analyse_profile

    rows = []
    for ds in scans:
        a = ds.attrs
        rq = ds["line_rq_um"].to_numpy().astype(float)
        rq = rq[np.isfinite(rq)]
        cut = a["cut"]
        rows.append({"cut": cut, **{k: float(ds[k]) for k in PARAMETERS},
                     "valid_share": float(ds["valid_share"]), "form_degree": int(a["form_degree"]),
                     "feed_angle_deg": float(a["feed_angle_deg"]), "nx": int(a["nx"]),
                     "ny": int(a["ny"]), "dx_um": 1e3 * float(a["dx_mm"]),
                     "dy_um": 1e3 * float(a["dy_mm"]),
                     "line_rq_median_um": float(np.median(rq)) if rq.size else np.nan,
                     "line_rq_p10_um": float(np.percentile(rq, 10)) if rq.size else np.nan,
                     "line_rq_p90_um": float(np.percentile(rq, 90)) if rq.size else np.nan,
                     "profile_source": "stylus" if cut in stylus else "areal",
                     **{k: a.get(k) for k in ("instrument", "probe", "lateral_resolution_um",
                                              "source_file", "source_format")}})
    areal = pd.DataFrame(rows, columns=AREAL_COLUMNS)
    keep = ["psd_radial", "psd_along", "psd_across"]
    spectra = xr.concat([ds[keep].expand_dims(cut=[ds.attrs["cut"]]) for ds in scans],
                        dim="cut", join="outer")
    for k in keep:
        spectra[k].attrs = scans[0][k].attrs
    spectra["cut"].attrs = {"units": "1", "long_name": "cut"}
    compared = []
    for cut, ref in stylus.items():
        x, z = profiles[cut]
        sq = float(areal.loc[areal["cut"] == cut, "Sq_um"].iloc[0])
        try:
            ours = analyse_profile(x, z, options)
            note = ""
        except ValueError as exc:
            ours, note = None, f"the scan's profile along the feed is too short: {exc}"
        for k in COMPARED:
            s_val = float(ref[k])
            a_val = float(ours[k]) if ours is not None else np.nan
            compared.append({"cut": cut, "parameter": k, "stylus": s_val, "areal": a_val,
                             "ratio": a_val / s_val if s_val else np.nan, "note": note})
        compared.append({"cut": cut, "parameter": "Sq_um (areal) / Rq_um (stylus)",
                         "stylus": float(ref["Rq_um"]), "areal": sq,
                         "ratio": sq / float(ref["Rq_um"]) if float(ref["Rq_um"]) else np.nan,
                         "note": "the scan's Sq holds waviness and form residue too"})
    vs = pd.DataFrame(compared, columns=["cut", "parameter", "stylus", "areal", "ratio",
                                         "note"])
    return {"areal": areal, "spectra": spectra, "profile_vs_areal": vs}


_AREAL = catalogue.artefact("surface.areal")
_VS = catalogue.artefact("surface.profile_vs_areal")


def add_areal_findings(found, areal: pd.DataFrame, vs: pd.DataFrame | None) -> None:
    """Chapter 2's statements about the scans: how many, their Sq range and instruments,
    and for cuts measured both ways the range of areal/stylus ratios of Rq and Wq."""
    if areal is None or not len(areal):
        return
    found.add("has_areal", True, artefact=_AREAL)
    found.add("n_scans", int(len(areal)), artefact=_AREAL, what="rows")
    found.add("areal_Sq_um_range", [float(areal["Sq_um"].min()), float(areal["Sq_um"].max())],
              "µm", artefact=_AREAL, what="Sq_um")
    found.add("areal_form_degree", int(areal["form_degree"].iloc[0]), artefact=_AREAL,
              what="form_degree (surface.areal_form_degree)")
    found.add("areal_instruments", ", ".join(sorted({str(i) for i in areal["instrument"]
                                                     if isinstance(i, str) and i})) or
              "not stated", artefact=_AREAL, what="instrument")
    found.add("areal_only_cuts", int((areal["profile_source"] == "areal").sum()),
              artefact=_AREAL, what="profile_source = areal")
    ranges = {}
    for k in ("Rq_um", "Wq_um"):
        r = (vs.loc[vs["parameter"] == k, "ratio"].to_numpy(float) if vs is not None
             else np.array([]))
        r = r[np.isfinite(r)]
        ranges[k] = [float(r.min()), float(r.max())] if r.size else None
    both = all(v is not None for v in ranges.values())
    found.add("has_profile_vs_areal", bool(both), artefact=_VS,
              what="cuts measured both ways whose scan profile could be analysed")
    if both:
        for k, v in ranges.items():
            found.add(f"areal_vs_stylus_{k.split('_')[0]}_ratio_range", v, artefact=_VS,
                      what=f"ratio[parameter = {k}]")
        found.add("n_cuts_both", int(vs.loc[np.isfinite(vs["ratio"]), "cut"].nunique()),
                  artefact=_VS, what="distinct cut with a finite ratio")
