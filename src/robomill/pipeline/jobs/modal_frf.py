"""Impact files (CSV hits, UFF 58 time histories or FRFs) -> hit checks -> windows -> FRFs
H(response point, reference point) of whatever layout was measured (H1, H2, coherence), the
hammer's force spectrum, UFF 58 export with node numbers.

The job of the rule script ``workflow/scripts/modal_frf.py``."""

from __future__ import annotations

import logging

from robomill.io import write_artefact, write_table
from robomill.io.impact import load_impact_test
from robomill.modal.frf import combine_frfs, force_spectrum, frf_from_groups
from robomill.modal.hits import check_and_group, empty_traces, hit_table_empty, hit_traces
from robomill.modal.layout import measured_directions
from robomill.modal.ncio import split_complex
from robomill.modal.uff import write_frf_uff
from robomill.study import load_study


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    cfg = params.modal
    manifest = load_study(inputs.study)
    test = load_impact_test(manifest, params.files)
    if test.hits and test.frfs:
        raise ValueError("the impact files mix hit records and FRFs: give one or the other")
    if test.hits:
        hits, groups = check_and_group(
            test.hits, trigger_fraction=cfg["trigger_fraction"],
            double_hit_fraction=cfg["double_hit_fraction"],
            overload_samples=cfg["overload_samples"], force_range_N=cfg["force_range_N"],
            accel_range_ms2=cfg["accel_range_ms2"])
        for row in hits.itertuples():
            log.info("hit %s_%s (%s -> %s): %s", row.direction, row.hit, row.reference,
                     row.responses, row.reason)
        fs = test.hits[0][0].fs_hz
        ds = frf_from_groups(groups, int(round(fs)), force_window_s=cfg["force_window_s"],
                             exponential_end=cfg["exponential_end"])
        ds["force_spectrum"] = (("frequency",), force_spectrum(groups, ds),
                                {"units": "N^2/Hz", "long_name": "mean hammer force auto-spectrum "
                                                                 "of the accepted, windowed hits"})
        traces = hit_traces(test.hits, hits, fs)
    else:
        ds = combine_frfs(test.frfs)
        ds.attrs["window_sigma_per_s"] = 0.0
        hits, traces = hit_table_empty(), None
        log.info("FRFs read from %d UFF file(s): %d responses x %d references", len(test.frfs),
                 ds.sizes["output"], ds.sizes["input"])
    if test.tcp_mm is not None:  # the pose of the test, for the planner's reference pose
        ds.attrs["impact_tcp_mm"] = list(test.tcp_mm)
    dirs = measured_directions(ds)  # one-direction tests: what the plan must extrapolate
    ds.attrs["directions_hit"] = dirs["hammer"]
    ds.attrs["directions_measured"] = dirs["measured"]
    ds.attrs["directions_not_measured"] = dirs["not_measured"]
    if dirs["not_measured"]:
        log.info("directions not measured (no hit and response along them): %s",
                 dirs["not_measured"])
    read = [str(p) for p in inputs.hits]
    write_artefact(split_complex(ds), outputs.frf, rule="modal_frf", inputs=read,
                   config_section=cfg)
    write_frf_uff(ds, outputs.uff)
    write_table(hits, outputs.hits)
    if traces is None:
        traces = empty_traces()
    write_artefact(traces, outputs.traces, rule="modal_frf", inputs=read,
                   config_section=cfg)
    if len(hits):
        log.info("FRFs from %d accepted hits; %d rejected", int(hits["accepted"].sum()),
                 int((~hits["accepted"]).sum()))
