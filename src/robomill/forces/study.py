"""The force study's datasets (thesis §3.1): one cut's analysis with its peaks as a
self-describing dataset, and the per-cut datasets gathered into the chapter's artefacts
(spectra, peaks, mean forces, harmonics, identified cutting coefficients).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Collection, Mapping

import numpy as np
import pandas as pd

from robomill.experiment import feed_per_tooth_mm, tooth_passing_hz
from robomill.forces.coefficients import (
    identify_cutting_coefficients,
    not_identified_reason,
    not_identified_table,
)
from robomill.forces.model import (
    AXES,
    CuttingCoefficients,
    cut_frame,
    engagement_angles_rad,
    slot_forces,
)
from robomill.forces.peaks import cut_peaks, harmonic_powers
from robomill.forces.settings import ForcePeakSettings
from robomill.settings import schema_default
from robomill.xrvars import var


def force_cut_dataset(result: Mapping[str, np.ndarray], *, cut: Mapping, fs_hz: float,
                      n_samples: int, spindle_rpm: float, flutes: int, n_harmonics: int,
                      dominant_band_hz: tuple[float, float] | None = None,
                      kinematic_band_per_mm: tuple[float, float] | None = None,
                      min_peak_cycles: float | None = None,
                      peaks: ForcePeakSettings | None = None):
    """The analysis of one cut (from
    :meth:`robomill.forces.stream.ForceSpectrumAccumulator.result`) as a dataset, with its
    peaks (:func:`robomill.forces.peaks.cut_peaks`: the dominant low-frequency peak and the
    kinematic peak in spatial frequency f/v, NaN where none stands out of its floor) and the
    tooth-passing harmonics (Welch).

    ``peaks`` holds the search's settings (config ``forces``); ``dominant_band_hz``,
    ``kinematic_band_per_mm`` and ``min_peak_cycles``, when given, replace its fields.

    Sanity flags (:func:`robomill.spectra.below_resolution`): a peak with fewer than
    ``min_peak_cycles`` periods in the low-band record (resolution 1/T in time, 1/(v T) = 1/L
    in space, L the record's length along the cut) is flagged ``*_below_resolution`` (and so
    is a missing peak): a short record (5–25 mm) cannot resolve a kinematic peak near
    0.5 1/mm."""
    import xarray as xr

    from robomill.experiment import DIRECTION_VECTORS
    from robomill.spectra import below_resolution

    given = {"dominant_band_hz": dominant_band_hz, "kinematic_band_per_mm": kinematic_band_per_mm,
             "min_peak_cycles": min_peak_cycles}
    s = dataclasses.replace(peaks or ForcePeakSettings(),
                            **{k: x for k, x in given.items() if x is not None})
    min_peak_cycles = float(s.min_peak_cycles)
    v = float(cut["feed_mm_s"])
    f_low = np.asarray(result["f_low"])
    df_hz = float(result.get("lowband_resolution_hz", fs_hz / max(int(n_samples), 1)))
    pk = cut_peaks(f_low, result["power_low"], feed_mm_s=v, spindle_rpm=spindle_rpm,
                   resolution_hz=df_hz, settings=s)
    f_dom, p_dom = pk["dominant_hz"], pk["dominant_power"]
    f_kin, p_kin = pk["kinematic_per_mm"], pk["kinematic_power"]
    dom_flag = bool(below_resolution(f_dom, df_hz, min_cycles=min_peak_cycles))
    kin_flag = bool(below_resolution(f_kin, df_hz / v, min_cycles=min_peak_cycles))
    f_tp = tooth_passing_hz(spindle_rpm, flutes)
    fk, hp = harmonic_powers(result["f_welch"], result["psd"], f_tp, n_harmonics)
    R = cut_frame(DIRECTION_VECTORS[cut["direction"]] if cut.get("direction_deg") is None
                  else (np.cos(np.deg2rad(cut["direction_deg"])),
                        np.sin(np.deg2rad(cut["direction_deg"])), 0.0))
    mean = np.asarray(result["mean"])
    ds = xr.Dataset(
        {
            "mean_force": var("axis", mean, "N", "mean force on the tool, R0 axes"),
            "mean_force_cut": var("component", R.T @ mean, "N",
                                   "mean force on the tool, cut frame"),
            "psd": var(("axis", "frequency"), result["psd"], "N^2/Hz",
                        "Welch power spectral density (Hann, 50 % overlap)"),
            "power_low": var(("axis", "lf_bin"), result["power_low"], "N^2",
                              "thesis normalized power |Z(k)|^2/N^2 of the whole record "
                              "(one-sided, eq. 2.3), low band"),
            "f_low": var("lf_bin", f_low, "Hz", "frequency of the low-band bin k/T"),
            "f_spatial_low": var("lf_bin", f_low / v, "1/mm",
                                  "spatial frequency of the low-band bin f/v"),
            "harmonic_power": var(("axis", "harmonic"), hp, "N^2",
                                   "power of the tooth-passing harmonic (Welch, +-2 bins)"),
            "harmonic_hz": var("harmonic", fk, "Hz", "tooth-passing harmonic frequency"),
            "envelope_min": var(("axis", "block"), result["env_min"], "N",
                                 "minimum force in the block"),
            "envelope_max": var(("axis", "block"), result["env_max"], "N",
                                 "maximum force in the block"),
            "envelope_t": var("block", result["env_t"], "s", "block centre time"),
            "excerpt": var(("axis", "sample"), result["excerpt"], "N",
                            "raw force samples from the middle of the record"),
            "excerpt_t": var("sample", result["excerpt_t"], "s", "time of the raw sample"),
            "dominant_hz": var((), f_dom, "Hz", "dominant low-frequency peak"),
            "dominant_power": var((), p_dom, "N^2",
                                   "thesis power at the dominant peak, summed over axes"),
            "kinematic_per_mm": var((), f_kin, "1/mm", "kinematic (spatial) peak"),
            "kinematic_power": var((), p_kin, "N^2",
                                    "thesis power at the kinematic peak, summed over axes"),
            "lowband_resolution_hz": var((), df_hz, "Hz",
                                          "frequency resolution of the low band 1/T"),
            "kinematic_resolution_per_mm": var((), df_hz / v, "1/mm",
                                                "spatial resolution of the low band 1/(v T)"),
            "dominant_below_resolution": var((), dom_flag, "1",
                                              f"dominant peak has fewer than {min_peak_cycles:g} "
                                              "periods in the record (or none was found)"),
            "kinematic_below_resolution": var((), kin_flag, "1",
                                               f"kinematic peak has fewer than "
                                               f"{min_peak_cycles:g} periods in the record "
                                               "(or none was found)"),
        },
        coords={
            "axis": var("axis", list(AXES), "1", "force channel (R0 axes)"),
            "component": var("component", ["feed", "cross_feed", "axial"], "1",
                              "cut-frame component"),
            "frequency": var("frequency", result["f_welch"], "Hz", "Welch frequency"),
            "harmonic": var("harmonic", np.arange(1, fk.size + 1), "1",
                             "tooth-passing harmonic order"),
        },
        attrs={"cut": cut["id"],
               **{k: int(cut[k]) for k in ("set", "segment") if cut.get(k) is not None},
               "direction": cut.get("direction") or f"{float(cut['direction_deg']):g} deg",
               "feed_mm_s": v, "depth_mm": float(cut["depth_mm"]),
               "fs_hz": float(fs_hz), "n_samples": int(n_samples),
               "feed_per_tooth_mm": feed_per_tooth_mm(v, spindle_rpm, flutes),
               "tooth_passing_hz": f_tp,
               "lowband_segments": int(result.get("lowband_segments", 1)),
               "decimation": int(result.get("decimation", 0)),
               "min_peak_cycles": float(min_peak_cycles)},
    )
    return ds



def force_record_chatter(verdicts: pd.DataFrame) -> list[str]:
    """The cuts whose force record is judged to chatter in ``results/chatter/verdicts.csv``
    (rows of ``kind`` force, else every row): the record the mean force comes from; a
    recording's verdict is another instrument's reading, compared in chapter 4."""
    own = (verdicts["kind"] == "force") if "kind" in verdicts else True
    return sorted(set(verdicts.loc[own & (verdicts["verdict"] == "chatter"), "cut"]
                      .astype(str)))


def gather_force_study(cut_datasets: list, *, flutes: int,
                       confidence: float = schema_default("forces", "confidence"),
                       model_feed_per_tooth_mm: float | None = None,
                       model_depth_mm: float | None = None,
                       processes: Mapping[str, Mapping] | None = None,
                       chattered: Collection[str] = ()):
    """Combine per-cut datasets into the study's artefacts.

    Returns ``(spectra, peaks, means, harmonics, coefficients)``: the ``spectra.nc`` dataset
    (dims ``cut, axis, frequency, lf_bin, harmonic, block, sample``; the low band is padded
    with NaN to the longest record), the ``peaks.csv`` table (``cut, dominant_hz,
    dominant_power, kinematic_per_mm``), per-cut mean forces, harmonic powers, and the
    identified cutting coefficients (:func:`identify_cutting_coefficients`); ``peaks.csv``
    then carries the sanity flags ``kinematic_resolution_per_mm, kinematic_below_resolution,
    dominant_below_resolution`` (:func:`force_cut_dataset`) and the coefficients theirs
    (:func:`coefficient_flags`: ``negative, fit_residual_rms_N, fit_signal_rms_N,
    residual_exceeds_signal, physical``). The spectra
    dataset also holds the model force shape of thesis Fig 3.2 over one revolution with the
    identified coefficients (``model_force``).

    Cuts that cannot identify the coefficients (fewer than three, or one feed per tooth:
    :func:`robomill.forces.coefficients.not_identified_reason`) are a legitimate design: the
    spectra, peaks, mean forces and harmonics are as always, the coefficients table is
    :func:`robomill.forces.coefficients.not_identified_table` (NaN values, ``identified``
    False, ``not_identified_reason``) and ``model_force`` is NaN.

    ``processes`` (cut id → :func:`robomill.experiment.cut_process`), given for a design that
    is not the thesis' (free cut ids, per-cut spindle speed, flutes, immersion, milling mode):
    the cuts keep their given order, ``set``/``segment`` are columns only when every cut has
    them, ``mean_forces.csv`` gains the columns ``spindle_rpm, flutes, radial_immersion,
    milling, entry_deg, exit_deg`` and the coefficients come from each cut's own chip model
    (:func:`identify_cutting_coefficients_general`); the model force is that of the first
    cut's tool and engagement window.
    """
    import xarray as xr

    grouped = all(d.attrs.get("set") is not None and d.attrs.get("segment") is not None
                  for d in cut_datasets)
    if processes is None:
        cut_datasets = sorted(cut_datasets, key=lambda d: (
            d.attrs["set"], d.attrs["segment"], "py px my".split().index(d.attrs["direction"])))
    ids = [d.attrs["cut"] for d in cut_datasets]
    nlow = max(d.sizes["lf_bin"] for d in cut_datasets)
    per_cut = ("psd", "power_low", "f_low", "f_spatial_low", "harmonic_power", "envelope_min",
               "envelope_max", "envelope_t", "excerpt", "excerpt_t", "mean_force",
               "mean_force_cut")
    parts = []
    for d in cut_datasets:
        d = d[list(per_cut)]
        parts.append(d.pad(lf_bin=(0, nlow - d.sizes["lf_bin"])))
    spectra = xr.concat(parts, dim="cut", join="outer", combine_attrs="override",
                        coords="minimal", compat="override")
    spectra.attrs = {}
    attr_vars = {"feed_mm_s": ("mm/s", "feed speed"), "depth_mm": ("mm", "axial depth"),
                 "feed_per_tooth_mm": ("mm", "feed per tooth"), "set": ("1", "set"),
                 "segment": ("1", "segment"), "direction": ("1", "cut direction"),
                 "n_samples": ("1", "samples per axis"),
                 "tooth_passing_hz": ("Hz", "tooth-passing frequency")}
    if not grouped:
        attr_vars = {k: v for k, v in attr_vars.items() if k not in ("set", "segment")}
    for name, (unit, ln) in attr_vars.items():
        spectra[name] = var("cut", [d.attrs[name] for d in cut_datasets], unit, ln)
    flags = ("lowband_resolution_hz", "kinematic_resolution_per_mm",
             "dominant_below_resolution", "kinematic_below_resolution")
    have_flags = all(name in d for d in cut_datasets for name in flags)
    for name in ("dominant_hz", "dominant_power", "kinematic_per_mm", "kinematic_power",
                 *(flags if have_flags else ())):
        cast = bool if name.endswith("below_resolution") else float
        spectra[name] = var("cut", [cast(d[name]) for d in cut_datasets],
                             cut_datasets[0][name].attrs["units"],
                             cut_datasets[0][name].attrs["long_name"])
    spectra = spectra.assign_coords(cut=var("cut", ids, "1", "cut id"))
    if processes is None:
        spectra["harmonic_hz"] = cut_datasets[0]["harmonic_hz"]
    else:  # each cut's own tooth passing (NaN past a cut's last harmonic below Nyquist)
        nh = spectra.sizes["harmonic"]
        hz = np.full((len(cut_datasets), nh), np.nan)
        for i, d in enumerate(cut_datasets):
            hz[i, :d.sizes["harmonic"]] = d["harmonic_hz"].values
        spectra["harmonic_hz"] = var(("cut", "harmonic"), hz, "Hz",
                                      "tooth-passing harmonic frequency of the cut")
    for name in ("block", "sample"):
        spectra = spectra.assign_coords({name: var(name, np.arange(spectra.sizes[name]), "1",
                                                    f"{name} index")})
    spectra = spectra.assign_coords(lf_bin=var("lf_bin", np.arange(nlow), "1",
                                                "low-band bin index k"))
    peaks = pd.DataFrame({"cut": ids,
                          "dominant_hz": spectra["dominant_hz"].values,
                          "dominant_power": spectra["dominant_power"].values,
                          "kinematic_per_mm": spectra["kinematic_per_mm"].values})
    if have_flags:  # sanity flags after the thesis columns
        for name in ("kinematic_resolution_per_mm", "kinematic_below_resolution",
                     "dominant_below_resolution"):
            peaks[name] = spectra[name].values
    means = pd.DataFrame({"cut": ids, **{k: spectra[k].values for k in
                                         ("set", "segment", "direction", "feed_mm_s",
                                          "depth_mm", "feed_per_tooth_mm") if k in spectra}})
    z = np.full(len(ids), int(flutes))
    st, ex = np.zeros(len(ids)), np.full(len(ids), np.pi)
    if processes is not None:
        procs = [processes[c] for c in ids]
        z = np.array([int(p["flutes"]) for p in procs])
        st, ex = np.array([engagement_angles_rad(p["radial_immersion"], p["milling"])
                           for p in procs]).reshape(-1, 2).T
        means["spindle_rpm"] = [float(p["spindle_rpm"]) for p in procs]
        means["flutes"] = z
        means["radial_immersion"] = [float(p["radial_immersion"]) for p in procs]
        means["milling"] = [p["milling"] for p in procs]
        means["entry_deg"] = np.degrees(st)
        means["exit_deg"] = np.degrees(ex)
    for i, a in enumerate(AXES):
        means[f"{a}_N"] = spectra["mean_force"].values[:, i]
    for i, comp in enumerate(("feed", "cross_feed", "axial")):
        means[f"F_{comp}_N"] = spectra["mean_force_cut"].values[:, i]
    hp = spectra["harmonic_power"]
    harmonics = pd.DataFrame([{"cut": c, "harmonic": int(k), "f_hz": float(f),
                               **{f"{a}_power_N2": float(hp.sel(cut=c, axis=a, harmonic=k))
                                  for a in AXES}}
                              for i, c in enumerate(ids)
                              for k, f in zip(spectra["harmonic"].values,
                                              spectra["harmonic_hz"].values if processes is None
                                              else spectra["harmonic_hz"].values[i],
                                              strict=True) if np.isfinite(f)])
    fit = np.array([c not in set(chattered) for c in ids], bool)
    if (not_identified_reason(means["feed_per_tooth_mm"].to_numpy()[fit]) is not None
            and not_identified_reason(means["feed_per_tooth_mm"].to_numpy()) is None):
        fit[:] = True  # without the chattering cuts the design identifies nothing: keep them
    means["in_fit"] = fit
    why = not_identified_reason(means["feed_per_tooth_mm"].to_numpy()[fit])
    if why is None:
        coeffs = identify_cutting_coefficients(
            means["feed_per_tooth_mm"].to_numpy()[fit], means["depth_mm"].to_numpy()[fit],
            means[["F_feed_N", "F_cross_feed_N", "F_axial_N"]].to_numpy()[fit],
            flutes=flutes if processes is None else z[fit], confidence=confidence,
            **({} if processes is None else {"entry_rad": st[fit], "exit_rad": ex[fit]}))
    else:  # a legitimate design (one feed per tooth, < 3 cuts): NaN and the reason
        coeffs = not_identified_table(why)
    c_mod = model_feed_per_tooth_mm or float(np.median(means["feed_per_tooth_mm"]))
    a_mod = model_depth_mm or float(np.median(means["depth_mm"]))
    phi = np.linspace(0, 4 * np.pi, 721)
    if why is None:
        k = CuttingCoefficients(**dict(zip(coeffs["name"], coeffs["value"], strict=True)))
        F = slot_forces(phi, c_mod, a_mod, k, flutes=int(z[0]), entry_rad=float(st[0]),
                        exit_rad=float(ex[0]))
    else:
        F = np.full((phi.size, 3), np.nan)
    spectra["model_force"] = var(("model_angle", "component"), F, "N",
                                  f"eq. 3.1 force on the tool, identified coefficients, "
                                  f"c = {c_mod * 1e3:.2f} um, a = {a_mod:.2f} mm"
                                  + ("" if why is None else f" (NaN: coefficients {why})"))
    spectra = spectra.assign_coords(model_angle=var("model_angle", np.degrees(phi), "deg",
                                                     "rotation angle of tooth 1"))
    spectra.attrs.update({"model_feed_per_tooth_mm": c_mod, "model_depth_mm": a_mod})
    return spectra, peaks, means, harmonics, coeffs
