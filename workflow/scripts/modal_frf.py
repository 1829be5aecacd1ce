"""Impact hits -> rejection -> windows -> 3x3 FRF matrix (H1, H2, coherence), UFF 58 export."""

import numpy as np
import pandas as pd
import xarray as xr

from robomill import modal
from robomill.io import write_artefact, write_table
from robomill.io.impact import read_hit, write_frf_uff
from robomill.io.manifest import load_manifest
from robomill.runlog import setup

log = setup(snakemake.log[0], "modal_frf")
cfg = snakemake.params.modal
manifest = load_manifest(snakemake.input.manifest)
rows, groups, traces = [], {d: [] for d in modal.AXES}, []
fs = None
for f in snakemake.params.files:
    path = manifest.verify_file(f["path"])
    fs_k, force, acc = read_hit(path, fs_hz=fs)
    fs = fs or fs_k
    check = modal.check_hit(force, acc, fs, trigger_fraction=cfg["trigger_fraction"],
                            double_hit_fraction=cfg["double_hit_fraction"],
                            overload_samples=cfg["overload_samples"],
                            force_range_N=cfg["force_range_N"],
                            accel_range_ms2=cfg["accel_range_ms2"])
    rows.append({"direction": f["direction"], "hit": f["hit"], "path": f["path"],
                 "accepted": check.accepted, "reason": check.reason,
                 "peak_force_N": float(force.max()),
                 "trigger_s": check.trigger_index / fs})
    log.info("hit %s_%d: %s", f["direction"], f["hit"], check.reason)
    if check.accepted:
        groups[f["direction"]].append((force, acc, check.trigger_index))
    n_keep = min(force.size, int(round(1.0 * fs)))
    traces.append(np.column_stack([force, acc])[:n_keep])

ds = modal.frf_matrix(groups, int(round(fs)), force_window_s=cfg["force_window_s"],
                      exponential_end=cfg["exponential_end"])
inputs = [str(p) for p in snakemake.input.hits]
write_artefact(modal.split_complex(ds), snakemake.output.frf, rule="modal_frf", inputs=inputs,
               config_section=cfg)
write_frf_uff(ds, snakemake.output.uff)
hits = pd.DataFrame(rows)
write_table(hits, snakemake.output.hits)

n = min(len(t) for t in traces)
tr = xr.Dataset(
    {name: (("hit_file", "time"), np.array([t[:n, c] for t in traces]),
            {"units": unit, "long_name": long})
     for c, (name, unit, long) in enumerate([
         ("force_N", "N", "hammer force"), ("ax_ms2", "m/s^2", "tool-tip acceleration X"),
         ("ay_ms2", "m/s^2", "tool-tip acceleration Y"),
         ("az_ms2", "m/s^2", "tool-tip acceleration Z")])},
    coords={"hit_file": ("hit_file", hits["path"].tolist(),
                         {"units": "1", "long_name": "raw file of the hit"}),
            "time": ("time", np.arange(n) / fs, {"units": "s", "long_name": "time"}),
            "direction": ("hit_file", hits["direction"].tolist(),
                          {"units": "1", "long_name": "hit direction"}),
            "accepted": ("hit_file", hits["accepted"].to_numpy(),
                         {"units": "1", "long_name": "hit accepted"})})
write_artefact(tr, snakemake.output.traces, rule="modal_frf", inputs=inputs, config_section=cfg)
log.info("FRF matrix from %s accepted hits per direction; %d rejected",
         ds["n_hits"].values.tolist(), int((~hits["accepted"]).sum()))
