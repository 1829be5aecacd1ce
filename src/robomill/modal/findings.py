"""The findings of the modal stage (chapter 3.3): every number, flag and verdict the chapter
states, computed from the stage's artefacts (:mod:`robomill.findings`).

Inputs are the artefacts as read (the FRF dataset, the synthesized FRFs and the tables of
``results/modal/``); the thresholds come from ``config.yaml: modal`` (``coherence_min``: the
thesis' peak-picking criterion, §3.3; ``coupling_tolerance``: how close to the cutting
vibration frequency a mode counts as close, thesis §3.3's mode-coupling argument).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill import catalogue, references
from robomill.findings import Findings
from robomill.modal.checks import synthesis_misfit
from robomill.modal.layout import TOOLTIP, measured_directions, points

FRF = catalogue.artefact("modal.frf")
MODES = catalogue.artefact("modal.modes")


def _layout(f: Findings, ds: xr.Dataset, synth: xr.Dataset) -> list[tuple[str, str]]:
    outs, ins = points(ds, "output"), points(ds, "input")
    measured = [(o, i) for o in ds["output"].values.tolist() for i in ds["input"].values.tolist()
                if np.isfinite(ds["H"].sel(output=o, input=i).values[1:]).any()]
    f.add("n_outputs", len(outs), artefact=FRF, what="output coordinate")
    f.add("n_inputs", len(ins), artefact=FRF, what="input coordinate")
    f.add("outputs", [str(v) for v in ds["output"].values], artefact=FRF, what="output")
    f.add("inputs", [str(v) for v in ds["input"].values], artefact=FRF, what="input")
    f.add("n_frf_measured", len(measured), artefact=FRF, what="H finite per pair")
    f.add("tooltip_layout", outs == list(TOOLTIP) and ins == list(TOOLTIP), artefact=FRF,
          what="output/input points equal the thesis' X, Y, Z at the tool tip")
    dirs = {k: " and ".join(v) for k, v in measured_directions(ds).items()}
    for key, value in (("directions_hit", dirs["hammer"]),
                       ("directions_response", dirs["response"]),
                       ("directions_not_measured", dirs["not_measured"] or None)):
        f.add(key, value, artefact=FRF, what="input/output direction codes (axes)")
    f.add("directions_measured_text", dirs["measured"] or "no axis", artefact=FRF,
          what="axes both hit and measured")
    band = [float(b) for b in np.atleast_1d(synth.attrs["band_hz"])]
    f.add("band_hz", band, "Hz", artefact=catalogue.artefact("modal.frf_synth"),
          what="attrs.band_hz")
    f.add("band_source", str(synth.attrs.get("band_source", "")),
          artefact=catalogue.artefact("modal.frf_synth"), what="attrs.band_source")
    flag = synth.attrs.get("band_flag")
    f.add("band_flag", str(flag) if flag else None, artefact=catalogue.artefact("modal.frf_synth"),
          what="attrs.band_flag")
    freq = ds["frequency"].values
    f.add("line_hz", float(freq[1] - freq[0]), "Hz", artefact=FRF, what="frequency")
    return measured


def _hits(f: Findings, ds: xr.Dataset, hits: pd.DataFrame) -> None:
    f.add("has_hits", bool(len(hits)), artefact=catalogue.artefact("modal.hits"), what="rows")
    f.add("n_hits", len(hits), artefact=catalogue.artefact("modal.hits"), what="rows")
    n_rej = int((~hits["accepted"].astype(bool)).sum()) if len(hits) else 0
    f.add("n_rejected", n_rej, artefact=catalogue.artefact("modal.hits"), what="accepted == False")
    per_ref = hits.groupby("reference").size() if len(hits) else pd.Series(dtype=int)
    f.add("hits_per_reference", [f"{k}: {int(v)}" for k, v in per_ref.items()],
          artefact=catalogue.artefact("modal.hits"), what="rows per reference")
    f.add("fs_hz", ds.attrs.get("fs_hz"), "Hz", artefact=FRF, what="attrs.fs_hz")
    f.add("record_samples", ds.attrs.get("record_samples"), artefact=FRF,
          what="attrs.record_samples")
    f.add("window_sigma_per_s", ds.attrs.get("window_sigma_per_s"), "1/s", artefact=FRF,
          what="attrs.window_sigma_per_s")


def _peaks(f: Findings, peaks: pd.DataFrame, groups: pd.DataFrame,
           coherence_min: float) -> None:
    art = catalogue.artefact("modal.peak_picking")
    f.add("n_peak_candidates", len(peaks), artefact=art, what="rows")
    f.add("n_real_sign_change", int(peaks["real_sign_change"].astype(bool).sum()),
          artefact=art, what="real_sign_change")
    f.add("n_coherence_ok", int(peaks["coherence_ok"].astype(bool).sum()), artefact=art,
          what="coherence_ok", verdict="pass", threshold=coherence_min,
          config_key="modal.coherence_min")
    f.add("n_natural", int(peaks["natural_frequency"].astype(bool).sum()), artefact=art,
          what="natural_frequency")
    f.add("n_peak_groups", len(groups), artefact=catalogue.artefact("modal.peak_groups"),
          what="rows")
    f.add("peak_groups_hz", groups["f_hz"].to_numpy(float), "Hz",
          artefact=catalogue.artefact("modal.peak_groups"), what="f_hz")


def _modes(f: Findings, modes: pd.DataFrame, stab: pd.DataFrame, mac: pd.DataFrame) -> None:
    f.add("n_stable_poles", int((stab["status"] == "stable").sum()),
          artefact=catalogue.artefact("modal.stabilization"), what="status == stable")
    f.add("n_modes", len(modes), artefact=MODES, what="rows")
    fn = modes["f_n_hz"].to_numpy(float)
    f.add("modes_hz", fn, "Hz", artefact=MODES, what="f_n_hz")
    f.add("f_min_hz", float(fn.min()) if fn.size else None, "Hz", artefact=MODES,
          what="f_n_hz min")
    f.add("f_max_hz", float(fn.max()) if fn.size else None, "Hz", artefact=MODES,
          what="f_n_hz max")
    flags = modes["flags"].fillna("").astype(str) if "flags" in modes else pd.Series([], str)
    flagged = modes[flags != ""]
    f.add("n_flagged", len(flagged), artefact=MODES, what="flags not empty")
    f.add("flagged", [f"mode {int(m.mode)} ({m.f_n_hz:.2f} Hz): {m.flags}"
                      for m in flagged.itertuples()], artefact=MODES, what="flags")
    m = mac.set_index("mode").to_numpy(float) if "mode" in mac else mac.to_numpy(float)
    off = m[~np.eye(len(m), dtype=bool)] if m.size else np.array([])
    f.add("mac_offdiag_max", float(off.max()) if off.size else None,
          artefact=catalogue.artefact("modal.mac"), what="largest off-diagonal value")


def _truth(f: Findings, check: pd.DataFrame, modes: pd.DataFrame) -> None:
    art = catalogue.artefact("modal.truth_check")
    has = bool(len(check))
    f.add("has_truth", has, artefact=art, what="rows")
    if not has:
        return
    f.add("truth_f_err_pct_max", float(check["f_err_pct"].abs().max()), "%", artefact=art,
          what="|f_err_pct| max")
    f.add("truth_zeta_err_pct_max", float(check["zeta_err_pct"].abs().max()), "%",
          artefact=art, what="|zeta_err_pct| max")
    f.add("truth_k_err_pct_max", float(check["k_err_pct"].abs().max()), "%", artefact=art,
          what="|k_err_pct| max")
    f.add("truth_shape_mac_min", float(check["shape_mac"].min()), artefact=art,
          what="shape_mac min")
    bias = 100 * (modes["zeta_windowed"] / modes["zeta"] - 1).abs().max()
    f.add("window_zeta_bias_pct_max", float(bias), "%", artefact=MODES,
          what="|zeta_windowed/zeta - 1| max")


def _misfit(f: Findings, ds: xr.Dataset, synth: xr.Dataset) -> None:
    band = [float(b) for b in np.atleast_1d(synth.attrs["band_hz"])]
    err = synthesis_misfit(ds, synth["H_synth"].values, band).to_numpy(float)
    finite = err[np.isfinite(err)]
    f.add("misfit_median_pct", float(np.median(finite)) if finite.size else None, "%",
          artefact=catalogue.artefact("modal.frf_synth"), what="‖H_synth − H‖/‖H‖ per FRF, median")
    f.add("misfit_worst_pct", float(finite.max()) if finite.size else None, "%",
          artefact=catalogue.artefact("modal.frf_synth"), what="‖H_synth − H‖/‖H‖ per FRF, max")


def _coupling(f: Findings, coupling: pd.DataFrame, pairs: pd.DataFrame,
              tolerance: float) -> None:
    art = catalogue.artefact("modal.coupling")
    has = bool(len(coupling))
    f.add("has_coupling", has, artefact=art, what="rows")
    if not has:
        return
    close = coupling[coupling["close"].astype(bool)]
    f.add("vibration_hz", float(coupling["vibration_hz"].iloc[0]), "Hz", artefact=art,
          what="vibration_hz (median dominant force frequency of chapter 3.1)")
    f.add("coupling_tolerance_pct", 100 * tolerance, "%", artefact=art, what="close")
    f.add("n_close", len(close), artefact=art, what="close", threshold=tolerance,
          config_key="modal.coupling_tolerance",
          verdict="possible" if len(pairs) else "not_possible")
    f.add("close_hz", close["f_n_hz"].to_numpy(float), "Hz", artefact=art, what="f_n_hz")
    f.add("coupling_pairs", [f"modes {int(p.mode_a)}–{int(p.mode_b)}: shapes "
                             f"{p.shape_angle_deg:.0f}° apart" for p in pairs.itertuples()],
          artefact=catalogue.artefact("modal.coupling_pairs"), what="shape_angle_deg")
    f.add("has_coupling_pairs", bool(len(pairs)),
          artefact=catalogue.artefact("modal.coupling_pairs"), what="rows")


def _stability(f: Findings, settings: Mapping[str, float]) -> None:
    """The stabilization tolerances the chart used (``config.yaml: modal``)."""
    for key, name, scale in (("stab_tol_f_pct", "tol_f", 100), ("stab_tol_zeta_pct", "tol_zeta",
                                                                   100),
                             ("stab_mac_min", "mac_min", 1)):
        if name in settings:
            f.add(key, scale * float(settings[name]), "%" if scale == 100 else "",
                  artefact="config.yaml", what=f"modal.{name}", config_key=f"modal.{name}")


def _sources(f: Findings) -> None:
    """The thesis' test numbers the chapter names (``robomill/data/references.yaml``)."""
    for key, ref in (("ref_hits_per_direction", "thesis.modal.hits_per_direction"),
                     ("ref_coherence_min", "thesis.modal.coherence_min")):
        f.add(key, references.value(ref), artefact="src/robomill/data/references.yaml",
              what=ref)


def modal_findings(ds: xr.Dataset, synth: xr.Dataset, tables: Mapping[str, pd.DataFrame], *,
                   coherence_min: float, coupling_tolerance: float,
                   stability: Mapping[str, float] | None = None) -> Findings:
    """The findings of chapter 3.3.

    ``ds``: the FRF dataset (:func:`robomill.io.impact.read_frf`); ``synth``: the synthesized
    FRFs with complex ``H_synth`` (:func:`robomill.modal.ncio.join_complex`); ``tables``: the
    stage's tables by name: ``hits``, ``modes``, ``peaks``, ``stabilization``, ``mac``,
    ``peak_groups``, ``truth_check``, ``coupling``, ``coupling_pairs``; ``stability``: the
    stabilization tolerances ``tol_f``, ``tol_zeta``, ``mac_min`` of ``config.yaml: modal``.
    """
    f = Findings("modal")
    _layout(f, ds, synth)
    _hits(f, ds, tables["hits"])
    _peaks(f, tables["peaks"], tables["peak_groups"], coherence_min)
    _modes(f, tables["modes"], tables["stabilization"], tables["mac"])
    _truth(f, tables["truth_check"], tables["modes"])
    _misfit(f, ds, synth)
    _coupling(f, tables["coupling"], tables["coupling_pairs"], coupling_tolerance)
    _stability(f, stability or {})
    _sources(f)
    return f


TABLE_NAMES: tuple[str, ...] = ("hits", "modes", "peaks", "stabilization", "mac",
                                "peak_groups", "truth_check", "coupling", "coupling_pairs")
"""The tables :func:`modal_findings` reads, by the names of the findings rule's inputs."""


def read_tables(paths: Mapping[str, Any]) -> dict[str, pd.DataFrame]:
    """The tables of :data:`TABLE_NAMES` read from ``paths`` (name → CSV path)."""
    return {name: pd.read_csv(paths[name]) for name in TABLE_NAMES}
