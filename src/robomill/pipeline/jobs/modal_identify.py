"""The impact test's identification as one job: an FRF artefact in, every modal artefact out.

The FRFs of any layout (:func:`robomill.io.impact.read_frf`) give the band of interest
(:func:`robomill.modal.band.choose_band`), the peak picking of the thesis
(:func:`robomill.modal.peaks.peak_picking`), the LSCF stabilization chart and the modes with
their shapes, MAC matrix and sanity flags (:func:`robomill.modal.identification.identify`),
the modes' intervals (:func:`robomill.modal.uncertainty.mode_intervals`), a UFF 55 file
(:func:`robomill.modal.uff.write_modes_uff`) and the FRF synthesized from the modes.
"""

from __future__ import annotations

import logging
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.io import write_artefact, write_table
from robomill.io.impact import read_frf
from robomill.modal.band import choose_band
from robomill.modal.identification import identify
from robomill.modal.layout import frf_coords, points
from robomill.modal.ncio import split_complex
from robomill.modal.peaks import peak_picking
from robomill.modal.tables import shapes_table
from robomill.modal.uff import write_modes_uff
from robomill.modal.uncertainty import mode_intervals

#: the outputs :func:`identify_frf_file` writes, by name
OUTPUTS = ("peaks", "modes", "stabilization", "shapes", "mac", "uff", "synth")


def identify_frf_file(frf: str, outputs: Mapping[str, str], *, settings: Mapping[str, Any],
                      experiment_band_hz: Sequence[float] | None, level: float,
                      log: logging.Logger, rule: str = "modal_identify") -> None:
    """Identify the modes of the FRF artefact ``frf`` and write each of :data:`OUTPUTS` to
    ``outputs[name]``; ``settings``: the ``modal`` configuration section;
    ``experiment_band_hz``: the study's band of interest (``experiment.modal_band_hz``);
    ``level``: the confidence level of the modes' intervals."""
    cfg = settings
    ds = read_frf(frf)
    spec = ds["force_spectrum"].values if "force_spectrum" in ds else None
    choice = choose_band(ds, band_hz=cfg["band_hz"], experiment_band_hz=experiment_band_hz,
                         force_spectrum=spec, coherence_min=cfg["coherence_min"])
    band = list(choice.band_hz)
    if choice.source == "data":
        basis = [w for w, ok in (("the hammer spectrum", spec is not None),
                                  ("the coherence", "coherence" in ds)) if ok]
        log.info("band %.4g-%.4g Hz from %s", *band,
                 " and ".join(basis) or "the frequency axis (no coherence: from 2 % of its top)")
    else:
        log.info("band %.4g-%.4g Hz (%s)", *band, choice.source)
    if choice.flag:
        log.warning("sanity flag: %s", choice.flag)
    peaks = peak_picking(ds, band_hz=band, coherence_min=cfg["coherence_min"],
                         prominence=cfg["peak_prominence"], floor_db=cfg["peak_floor_db"],
                         real_window_hz=cfg["real_window_hz"])
    write_table(peaks, outputs["peaks"])
    idn = identify(ds, band_hz=band, max_order=cfg["max_order"], tol_f=cfg["tol_f"],
                   tol_zeta=cfg["tol_zeta"], mac_min=cfg["mac_min"],
                   zeta_max=cfg["zeta_max"], cluster_tol=cfg["cluster_tol"],
                   min_stable=cfg["min_stable"], coherence_min=cfg["coherence_min"])
    # intervals from the hits' scatter (bootstrap of the identification)
    modes_ci = mode_intervals(ds, idn.modes, idn.selected, band_hz=band, synth=idn.H_synth,
                              level=float(level))
    write_table(modes_ci, outputs["modes"])
    write_table(idn.stabilization, outputs["stabilization"])
    write_table(shapes_table(idn.shapes), outputs["shapes"])
    mac = pd.DataFrame(idn.mac, columns=[f"mode_{m}" for m in idn.modes["mode"]])
    mac.insert(0, "mode", idn.modes["mode"].to_numpy())
    write_table(mac, outputs["mac"])
    write_modes_uff(idn.modes, idn.shapes, outputs["uff"])
    synth = _synthesis(ds, idn, band, choice)
    write_artefact(split_complex(synth), outputs["synth"], rule=rule, inputs=[frf],
                   config_section=cfg)
    for m in idn.modes.itertuples():
        log.info("mode %d: f_n %.3f Hz, zeta %.4f, k %.3g N/m, m %.3g kg%s", m.mode, m.f_n_hz,
                 m.zeta, m.k_modal_N_m, m.m_modal_kg, f" -- {m.flags}" if m.flags else "")
    log.info("%d thesis-criteria peaks of %d candidates", int(peaks["natural_frequency"].sum()),
             len(peaks))


def _synthesis(ds: xr.Dataset, idn: Any, band: list[float], choice: Any) -> xr.Dataset:
    """The FRF synthesized from the identified poles and residues, with the band's choice in
    its attributes."""
    synth = xr.Dataset(
        {"H_synth": (("output", "input", "frequency"), idn.H_synth,
                     {"units": "m/N", "long_name": "FRF synthesized from the identified poles "
                                                   "and residues (windowed, as measured)"}),
         "residue": (("output", "input", "mode"), idn.residues,
                     {"units": "m/(N s)", "long_name": "modal constant A_r (LSFD)"})},
        coords={**frf_coords(ds["frequency"].values, points(ds, "output"),
                             points(ds, "input")),
                "mode": ("mode", idn.modes["mode"].to_numpy(),
                         {"units": "1", "long_name": "mode number"})})
    synth.attrs["band_hz"] = np.asarray(band, float)
    synth.attrs["band_source"] = choice.source
    synth.attrs["data_band_hz"] = np.asarray(choice.data_band_hz or (np.nan, np.nan), float)
    synth.attrs["band_coverage"] = float(choice.coverage)
    synth.attrs["band_flag"] = choice.flag
    if "impact_tcp_mm" in ds.attrs:  # where the test was made (the modes' pose)
        synth.attrs["impact_tcp_mm"] = np.asarray(ds.attrs["impact_tcp_mm"], float)
    return synth
