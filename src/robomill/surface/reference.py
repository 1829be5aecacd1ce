"""Our profile parameters beside the ones a file states about itself (NIST SMATS XML's
``ROUGHNESS_SURFACE_PARAMETERS``, ``WAVINESS_SURFACE_PARAMETERS``; read by
:func:`robomill.importers.smats_xml.reference_parameters` into the manifest entry's
``reference``).

Each section names the profile its parameters describe: ``primary`` (the measured profile
with its least-squares line removed, or only its mean where the file says it removed no form,
``form_order`` 0; low-pass filtered at the file's ``lambda_s_mm`` by the same Gaussian where it
states one [ISO 16610-21]), ``raw`` (the NPL exports' unfiltered profile, the same without
λs), ``roughness`` and ``waviness`` (the ISO 16610-21
Gaussian split of the primary profile, :func:`robomill.surface.profile.split_profile`, at
the cut-off the file states, or at ``surface.lambda_c_mm`` when it states none; the row says
which). The parameter's type is its last letters, whatever its first (``Pq``, ``Rq`` and
``Wq`` of a roughness section are the RMS of the roughness profile) [ISO 4287, §4.2]:

.. math:: a = \\frac1n\\sum|z_i|,\\quad q = \\sqrt{\\frac1n\\sum z_i^2},\\quad
          sk = \\frac{1}{q^3 n}\\sum z_i^3,\\quad ku = \\frac{1}{q^4 n}\\sum z_i^4

with z the profile less its mean; t = max − min over the profile, p = max, v = −min, z the
mean over sampling lengths of max − min (the sampling length is the cut-off for a roughness
profile, the whole profile otherwise, as ISO 4287 takes it for the primary profile).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd

from robomill import catalogue
from robomill.surface.profile import detrend_profile, rz_um, split_profile

REFERENCE_COLUMNS = ["cut", "profile", "parameter", "unit", "file_value", "ours", "rel_diff",
           "within_tolerance", "lambda_c_mm", "filter"]
"""Columns of ``results/surface/reference_comparison.csv``."""


def profile_parameter(p_um: np.ndarray, kind: str, n_sampling: int | None = None) -> float:
    """One ISO 4287 parameter of type ``kind`` (``a q z t p v sk ku``, any case) of a
    profile [µm, or dimensionless for sk, ku]; ``z`` over sampling lengths of
    ``n_sampling`` samples (the whole profile when ``None``); NaN for another type."""
    z = np.asarray(p_um, float)
    z = z - z.mean()
    kind = kind.lower()
    q = float(np.sqrt(np.mean(z**2)))
    if kind == "a":
        return float(np.mean(np.abs(z)))
    if kind == "q":
        return q
    if kind == "t":
        return float(z.max() - z.min())
    if kind == "p":
        return float(z.max())
    if kind == "v":
        return float(-z.min())
    if kind == "z":
        return rz_um(z, n_sampling or z.size)
    if kind == "sk":
        return float(np.mean(z**3) / q**3) if q > 0 else float("nan")
    if kind == "ku":
        return float(np.mean(z**4) / q**4) if q > 0 else float("nan")
    return float("nan")


def _filter_text(section: Mapping[str, Any], lambda_c_mm: float, stated: bool) -> str:
    settings = section.get("filter") or {}
    told = ", ".join(f"{k} {v}" for k, v in settings.items())
    if stated:
        return f"the file's: {told}"
    return (f"not stated in the file{f' ({told})' if told else ''}; ours: Gaussian, "
            f"λc = {lambda_c_mm:g} mm (surface.lambda_c_mm)")


def _primary_text(form_order: int | None, lambda_s_mm: float | None) -> str:
    removed = ("the mean removed, the file's LSQ_COEFF 0" if form_order == 0
               else "least-squares line removed")
    if lambda_s_mm:
        return f"{removed}; Gaussian λs = {lambda_s_mm * 1e3:g} µm (the file's)"
    return f"no filter; {removed}"


def reference_comparison(x_mm: np.ndarray, z_um: np.ndarray, reference: Mapping[str, Any], *,
                         lambda_c_mm: float, rtol: float, cut: str = "") -> pd.DataFrame:
    """Our value of every parameter ``reference`` states, beside it.

    Parameters
    ----------
    x_mm, z_um
        The profile as imported (uniform x).
    reference
        ``{profile: {"Pq_um": …, "Psk": …, "filter": {…}, "lambda_c_mm": …}}`` with profile
        ``primary``, ``roughness`` or ``waviness`` (the manifest entry's ``reference``).
    lambda_c_mm
        The cut-off used where a section states none (``surface.lambda_c_mm``).
    rtol
        ``within_tolerance`` is ``|ours − file| ≤ rtol·|file|`` (``surface.reference_rtol``;
        for the dimensionless sk and ku ``rtol·max(|file|, 1)``).

    Returns
    -------
    pandas.DataFrame
        :data:`REFERENCE_COLUMNS`, one row per stated parameter (``ours`` NaN for a type we do not
        compute, e.g. Pc).

    Examples
    --------
    >>> x = np.arange(4000) * 0.001
    >>> z = 0.5 * np.sin(2 * np.pi * x / 0.1)
    >>> t = reference_comparison(x, z, {"primary": {"Pq_um": 0.5 / np.sqrt(2)}},
    ...                          lambda_c_mm=0.8, rtol=0.01)
    >>> bool(t["within_tolerance"].iloc[0])
    True
    """
    x = np.asarray(x_mm, float)
    dx = float(np.median(np.diff(x)))
    primary, _, _ = detrend_profile(z_um, x)
    rows = []
    for profile, section in reference.items():
        stated = section.get("lambda_c_mm") is not None
        lc = float(section["lambda_c_mm"]) if stated else float(lambda_c_mm)
        form = section.get("form_order")
        base = (np.asarray(z_um, float) - np.mean(z_um)) if form == 0 else primary
        lambda_s = section.get("lambda_s_mm")
        if profile in ("primary", "raw"):
            p, n_sampling = base, None
            if lambda_s and profile == "primary":
                p = split_profile(base, dx, float(lambda_s))[0]
        else:
            w, r = split_profile(primary, dx, lc)
            p, n_sampling = (r, max(int(round(lc / dx)), 2)) if profile == "roughness" else (
                w, None)
        for key, value in section.items():
            if key in ("filter", "lambda_c_mm", "lambda_s_mm", "form_order"):
                continue
            name, _, unit = key.partition("_")
            ours = profile_parameter(p, name[1:], n_sampling)
            file_value = float(value)
            # sk, ku: relative to max(|file|, 1) (a symmetric profile states Psk = 0)
            scale = max(abs(file_value), 1.0) if not unit else abs(file_value)
            rel = (ours - file_value) / scale if scale else float("nan")
            rows.append({"cut": cut, "profile": profile, "parameter": name, "unit": unit or "-",
                         "file_value": file_value, "ours": ours, "rel_diff": rel,
                         "within_tolerance": bool(np.isfinite(rel) and abs(rel) <= rtol),
                         "lambda_c_mm": (lc if profile not in ("primary", "raw")
                                         else float("nan")),
                         "filter": (_primary_text(form, lambda_s if profile == "primary"
                                                  else None)
                                    if profile in ("primary", "raw")
                                    else _filter_text(section, lc, stated))})
    return pd.DataFrame(rows, columns=REFERENCE_COLUMNS)


_REFERENCE = catalogue.artefact("surface.reference_comparison")


def add_reference_findings(found, table: pd.DataFrame, rtol: float) -> None:
    """Chapter 2's statements about :func:`reference_comparison`'s table: how many of the
    files' own parameters ours match within ``rtol`` (verdict ``reference_agreement``:
    pass when all do; a type we do not compute, such as the NPL exports' Pc, is listed in the
    table with ours empty and left out of the count), the largest difference, and Pq of every
    file and profile beside ours.
    Nothing is added for an empty table (the chapter then says nothing about it)."""
    if table is None or not len(table):
        return
    table = table[np.isfinite(table["ours"].astype(float))]  # types we compute (not Pc)
    if not len(table):
        return
    within = table["within_tolerance"].astype(bool)
    found.add("has_reference", True, artefact=_REFERENCE)
    found.add("reference_files", int(table["cut"].nunique()), artefact=_REFERENCE,
              what="distinct cut")
    found.add("reference_parameters", int(len(table)), artefact=_REFERENCE, what="rows")
    found.add("reference_within", int(within.sum()), artefact=_REFERENCE,
              what="within_tolerance")
    found.add("reference_worst_pct", float(100 * np.nanmax(np.abs(table["rel_diff"]))), "%",
              artefact=_REFERENCE, what="max |rel_diff|")
    found.add("reference_rtol_pct", 100 * float(rtol), "%", artefact=_REFERENCE)
    found.add("reference_agreement", bool(within.all()), artefact=_REFERENCE,
              verdict="pass" if within.all() else "fail", threshold=float(rtol),
              config_key="surface.reference_rtol", what="every within_tolerance")
    pq = table[table["parameter"].str.lower().str.endswith("q")]
    found.add("reference_pq", "; ".join(
        f"{r.cut} {r.profile}: ours {r.ours:.4g} µm, the file's {r.file_value:.4g} µm"
        for r in pq.itertuples()) or None, artefact=_REFERENCE, what="rows of parameter *q")
    found.add("reference_filters", "; ".join(
        f"{r.cut} {r.profile}: {r.filter}" for r in
        table.drop_duplicates(["cut", "profile"]).itertuples()), artefact=_REFERENCE,
        what="filter")
