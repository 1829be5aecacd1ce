"""One profile's whole chapter-2 analysis as a dataset: the thesis spectra (eqs. 2.1–2.3), the
segment-averaged spectra and the segment-method RMS (eq. 2.6, Tables 2.1/2.2); and the
spectra of every cut stacked along ``cut``.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import xarray as xr

from robomill.spectra import (
    segment_averaged_spectrum,
    segment_rms,
    thesis_spectrum,
)
from robomill.surface.options import settings
from robomill.surface.profile import amplitude_parameters, detrend_profile, split_profile
from robomill.xrvars import attrs


def analyse_profile(x_mm: np.ndarray, z_um: np.ndarray, options: Mapping[str, Any] | None = None
                    ) -> xr.Dataset:
    """The whole chapter-2 analysis of one profile, as a labelled dataset.

    Variables: the measured, detrended, waviness and roughness profiles over ``x``; the
    whole-profile thesis amplitude/power spectra over ``f`` (eqs. 2.2, 2.3); the
    segment-averaged power of the waviness profile (``f_w``, 2.5 mm segments) and of the
    roughness profile (``f_r``, 0.25 mm segments); the segment-averaged power used for the
    roughness peaks (``f_peak``); scalars Wt, Wq, Rq, Ra, Rz, the segment-method RMS of
    waviness and roughness (Tables 2.1, 2.2), the whole-profile Parseval RMS (eq. 2.6), the
    removed tilt.
    """
    opts = settings(options)
    x = np.asarray(x_mm, float)
    dx = float(np.median(np.diff(x)))
    fs = 1.0 / dx
    lam = float(opts["lambda_c_mm"])
    zd, slope, offset = detrend_profile(z_um, x)
    w, r = split_profile(zd, dx, lam, end=opts["filter_end"],
                         half_width_cutoffs=float(opts["kernel_half_width_cutoffs"]))
    spec = thesis_spectrum(zd, fs)
    seg, capped = segment_lengths_mm(x.size * dx, opts)
    sw = segment_averaged_spectrum(w, fs, seg["waviness_segment_mm"])
    sr = segment_averaged_spectrum(r, fs, seg["roughness_segment_mm"])
    sp = segment_averaged_spectrum(zd, fs, seg["roughness_peak_segment_mm"])
    params = amplitude_parameters(w, r, dx, lam)
    ds = xr.Dataset(
        {
            "z_measured": ("x", np.asarray(z_um, float), attrs("um", "measured profile")),
            "z": ("x", zd, attrs("um", "detrended profile")),
            "waviness": ("x", w, attrs("um", f"waviness profile (Gaussian, λc = {lam} mm)")),
            "roughness": ("x", r, attrs("um", "roughness profile (detrended − waviness)")),
            "amplitude": ("f", spec.amplitude, attrs("um", "normalized amplitude A(k), "
                                                          "one-sided (thesis eq. 2.2)")),
            "power": ("f", spec.power, attrs("um^2", "normalized power P(k), one-sided "
                                                      "(thesis eq. 2.3)")),
            "power_waviness": ("f_w", sw.power, attrs(
                "um^2", "segment-averaged power of the waviness profile")),
            "power_roughness": ("f_r", sr.power, attrs(
                "um^2", "segment-averaged power of the roughness profile")),
            "power_peak": ("f_peak", sp.power, attrs(
                "um^2", "segment-averaged power of the detrended profile (peak search)")),
        },
        coords={
            "x": ("x", x, attrs("mm", "position along the profile")),
            "f": ("f", spec.f, attrs("1/mm", "spatial frequency k·fs/N")),
            "f_w": ("f_w", sw.f, attrs("1/mm", "spatial frequency (waviness segments)")),
            "f_r": ("f_r", sr.f, attrs("1/mm", "spatial frequency (roughness segments)")),
            "f_peak": ("f_peak", sp.f, attrs("1/mm", "spatial frequency (peak segments)")),
        },
    )
    scalars = {
        **{k: (v, "um", k.split("_")[0] + " (ISO 4287)") for k, v in params.items()},
        "waviness_rms_um": (segment_rms(w, fs, seg["waviness_segment_mm"]), "um",
                            "RMS of waviness, segment method (Table 2.1)"),
        "roughness_rms_um": (segment_rms(r, fs, seg["roughness_segment_mm"]), "um",
                             "RMS of roughness, segment method (Table 2.2)"),
        "parseval_rms_um": (float(np.sqrt(spec.power.sum())), "um",
                            "RMS of the detrended profile by Parseval (eq. 2.6)"),
        "tilt_um_per_mm": (slope, "um/mm", "stylus tilt removed by detrending"),
        "offset_um": (offset, "um", "offset removed by detrending"),
        "fs_per_mm": (fs, "1/mm", "sampling frequency"),
        "lambda_c_mm": (lam, "mm", "Gaussian filter cut-off"),
    }
    for name, (value, units, long_name) in scalars.items():
        ds[name] = ((), float(value), attrs(units, long_name))
    if capped:  # sanity flag: a profile shorter than the thesis' segments
        ds.attrs["segment_flag"] = (
            f"profile of {x.size * dx:.3g} mm is shorter than " + ", ".join(
                f"{k} {float(opts[k]):g} mm" for k in capped)
            + ": one segment of the whole profile used (not the thesis' segment method)")
    return ds


def segment_lengths_mm(length_mm: float, opts: Mapping[str, Any]) -> tuple[dict[str, float],
                                                                          list[str]]:
    """The segment lengths of the segment method (``waviness_segment_mm``,
    ``roughness_segment_mm``, ``roughness_peak_segment_mm``), each at most the profile's
    ``length_mm`` (a profile shorter than the thesis' 2.5 mm waviness segment, e.g. a
    microscope scan, is analysed as one segment rather than refused); and the keys that
    were capped (a sanity flag)."""
    keys = ("waviness_segment_mm", "roughness_segment_mm", "roughness_peak_segment_mm")
    asked = {k: float(opts[k]) for k in keys}
    return ({k: min(v, float(length_mm)) for k, v in asked.items()},
            [k for k, v in asked.items() if v > length_mm])

def common_join(per_cut: Sequence[xr.Dataset], dim: str) -> str:
    """``"override"`` when every dataset has the same ``dim`` coordinate, else ``"outer"``."""
    first = per_cut[0][dim].to_numpy()
    same = all(d.sizes[dim] == first.size and np.allclose(d[dim].to_numpy(), first, rtol=1e-9)
               for d in per_cut[1:])
    return "override" if same else "outer"


def spectra_dataset(per_cut: Sequence[xr.Dataset], cut_ids: Sequence[str]) -> xr.Dataset:
    """Stack the spectra of every cut along ``cut``: on the common frequency axis when the
    profiles have equal length and sampling (the virtual cell, one instrument), else on the
    union of the frequencies, NaN where a cut has none (a lab's profiles of several lengths,
    or a stylus profile beside an areal scan's profile)."""
    keep = ["amplitude", "power", "power_waviness", "power_roughness"]
    ds = xr.concat([d[keep] for d in per_cut], dim="cut", coords="minimal",
                   compat="override", join=common_join(per_cut, "f"))
    ds = ds.assign_coords(cut=("cut", list(cut_ids), attrs("1", "cut identifier")))
    return ds
