"""FRFs of any layout -> thesis peak picking, LSCF stabilization chart over all measured FRFs,
modes (sdypy-EMA), mode shapes over the measured points, MAC matrix, sanity flags, UFF 55."""

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
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "modal_identify")
cfg = snakemake.params.modal
ds = read_frf(snakemake.input.frf)
spec = ds["force_spectrum"].values if "force_spectrum" in ds else None
choice = choose_band(ds, band_hz=cfg["band_hz"],
                     experiment_band_hz=snakemake.params.experiment_band_hz,
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
write_table(peaks, snakemake.output.peaks)
idn = identify(ds, band_hz=band, max_order=cfg["max_order"], tol_f=cfg["tol_f"],
               tol_zeta=cfg["tol_zeta"], mac_min=cfg["mac_min"],
               zeta_max=cfg["zeta_max"], cluster_tol=cfg["cluster_tol"],
               min_stable=cfg["min_stable"], coherence_min=cfg["coherence_min"])
# intervals from the hits' scatter (bootstrap of the identification)
modes_ci = mode_intervals(ds, idn.modes, idn.selected, band_hz=band, synth=idn.H_synth,
                          level=float(snakemake.params.level))
write_table(modes_ci, snakemake.output.modes)
write_table(idn.stabilization, snakemake.output.stabilization)
shapes = shapes_table(idn.shapes)
write_table(shapes, snakemake.output.shapes)
mac = pd.DataFrame(idn.mac, columns=[f"mode_{m}" for m in idn.modes["mode"]])
mac.insert(0, "mode", idn.modes["mode"].to_numpy())
write_table(mac, snakemake.output.mac)
write_modes_uff(idn.modes, idn.shapes, snakemake.output.uff)
modes = idn.modes["mode"].to_numpy()
synth = xr.Dataset(
    {"H_synth": (("output", "input", "frequency"), idn.H_synth,
                 {"units": "m/N", "long_name": "FRF synthesized from the identified poles and "
                                               "residues (windowed, as measured)"}),
     "residue": (("output", "input", "mode"), idn.residues,
                 {"units": "m/(N s)", "long_name": "modal constant A_r (LSFD)"})},
    coords={**frf_coords(ds["frequency"].values, points(ds, "output"),
                         points(ds, "input")),
            "mode": ("mode", modes, {"units": "1", "long_name": "mode number"})})
synth.attrs["band_hz"] = np.asarray(band, float)
synth.attrs["band_source"] = choice.source
synth.attrs["data_band_hz"] = np.asarray(choice.data_band_hz or (np.nan, np.nan), float)
synth.attrs["band_coverage"] = float(choice.coverage)
synth.attrs["band_flag"] = choice.flag
write_artefact(split_complex(synth), snakemake.output.synth, rule="modal_identify",
               inputs=[snakemake.input.frf], config_section=cfg)
for m in idn.modes.itertuples():
    log.info("mode %d: f_n %.3f Hz, zeta %.4f, k %.3g N/m, m %.3g kg%s", m.mode, m.f_n_hz,
             m.zeta, m.k_modal_N_m, m.m_modal_kg, f" -- {m.flags}" if m.flags else "")
log.info("%d thesis-criteria peaks of %d candidates", int(peaks["natural_frequency"].sum()),
         len(peaks))
