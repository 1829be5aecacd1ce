"""3x3 FRF matrix -> thesis peak picking, LSCF stabilization chart, modes (sdypy-EMA)."""

import xarray as xr

from robomill import modal
from robomill.io import write_artefact, write_table
from robomill.io.impact import read_frf
from robomill.runlog import setup

log = setup(snakemake.log[0], "modal_identify")
cfg = snakemake.params.modal
ds = read_frf(snakemake.input.frf)
band = cfg["band_hz"]
peaks = modal.peak_picking(ds, band_hz=band, coherence_min=cfg["coherence_min"],
                           prominence=cfg["peak_prominence"],
                           real_window_hz=cfg["real_window_hz"])
write_table(peaks, snakemake.output.peaks)
idn = modal.identify(ds, band_hz=band, max_order=cfg["max_order"], tol_f=cfg["tol_f"],
                     tol_zeta=cfg["tol_zeta"], mac_min=cfg["mac_min"],
                     zeta_max=cfg["zeta_max"], cluster_tol=cfg["cluster_tol"],
                     min_stable=cfg["min_stable"])
write_table(idn.modes, snakemake.output.modes)
write_table(idn.stabilization, snakemake.output.stabilization)
mode_coord = {"mode": ("mode", idn.modes["mode"].to_numpy(),
                       {"units": "1", "long_name": "mode number"})}
synth = xr.Dataset(
    {"H_synth": (("output", "input", "frequency"), idn.H_synth,
                 {"units": "m/N", "long_name": "FRF synthesized from the identified poles and "
                                               "residues (windowed, as measured)"}),
     "residue": (("output", "input", "mode"), idn.residues,
                 {"units": "m/(N s)", "long_name": "modal constant A_r (LSFD)"})},
    coords={**modal.frf_coords(ds["frequency"].values), **mode_coord})
write_artefact(modal.split_complex(synth), snakemake.output.synth, rule="modal_identify",
               inputs=[snakemake.input.frf], config_section=cfg)
for _, m in idn.modes.iterrows():
    log.info("mode %d: f_n %.3f Hz, zeta %.4f, k %.3g N/m, m %.3g kg", m["mode"], m["f_n_hz"],
             m["zeta"], m["k_modal_N_m"], m["m_modal_kg"])
log.info("%d thesis-criteria peaks of %d candidates", int(peaks["natural_frequency"].sum()),
         len(peaks))
