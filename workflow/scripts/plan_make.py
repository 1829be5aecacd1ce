"""The next cuts from what was measured: candidates, the chosen cuts, the Pareto
front, the study's own cuts beside the plan, and the next experiment's manifest and config."""

import numpy as np
import pandas as pd
import xarray as xr
import yaml

from robomill.errors import RawDataError
from robomill.experiment import cut_endpoints_mm
from robomill.forces.prediction import regression_from_means
from robomill.io import write_artefact, write_table
from robomill.io.atomic import atomic_path
from robomill.io.cell import read_cell
from robomill.pipeline.runlog import setup
from robomill.plan.binding import binding_table, read_before
from robomill.plan.check import waviness_min_cycles
from robomill.plan.conditioning import EVIDENCE_COLUMNS
from robomill.plan.evidence import read_verdicts, verdict_stability
from robomill.plan.extrapolation import reach_from_means
from robomill.plan.make import make_plan
from robomill.plan.measured import Measured, cut_mid_poses, gear_joint_amplitudes
from robomill.plan.outputs import cell_of, compact
from robomill.plan.program import program_cell, write_program
from robomill.plan.request import read_request
from robomill.plan.workobject import BASE
from robomill.study import load_study

log = setup(snakemake.log[0], "plan")
inp, out, p = snakemake.input, snakemake.output, snakemake.params
req = read_request(inp.request)
cell_file = read_cell(inp.cell)
study = load_study(inp.study)
cuts = study.cuts  # the study's own cuts (raw folder or virtual cell)
experiment = dict(study.experiment)  # the study's (the manifest's), its block layout resolved
# where the study's cuts lie needs their length; without it they are not placed
placed = bool(cuts) and experiment.get("cut_length_mm") is not None
if cuts and not placed:
    log.info("the study gives no cut_length_mm: its cuts are not placed (no gear lines carried)")
mids = np.array([np.mean(cut_endpoints_mm(c, experiment), 0) for c in cuts]) if placed else None
cell = cell_of(cell_file, req, mids)


def table(name):
    return pd.read_csv(inp[name]) if name in inp.keys() else None


gears = None
noise = p.waviness_noise  # config plan.waviness_noise, filled by its schema (robomill.plan.noise)
if "peaks" in inp.keys() and placed:
    poses = cut_mid_poses(cell.robot, cuts, experiment, tool_rotation=cell.R0,
                          q0_rad=cell.q_seed_rad)
    profiles = xr.load_dataset(inp.profiles) if "profiles" in inp.keys() else None
    gears = gear_joint_amplitudes(
        pd.read_csv(inp.peaks), cell.robot, poses, profiles=profiles,
        noise_band_bins=float(noise["band_bins"]),
        noise_exclude_bins=float(noise["exclude_bins"]), level=float(p.level))
    log.info("gear elements (joint amplitudes, tracker noise):\n%s", gears.to_string())
regression = regression_from_means(table("means"), int(experiment.get("flutes", req.flutes)))
measured = Measured(modes=table("modes"), coefficients=table("coefficients"),
                    joints=table("joints"), gears=gears, force_regression=regression,
                    level=float(p.level),
                    waviness_coverage=float(noise["coverage"]),
                    waviness_min_cycles=waviness_min_cycles(
                        p.fmin_cycles, float(noise["exclude_bins"])))
# what the study measured: the identifying cuts' ranges, the cuts' midpoints, the modal band
band = None
if "modal_fit" in inp.keys():
    with xr.open_dataset(inp.modal_fit) as fit:
        band = [float(b) for b in np.atleast_1d(fit.attrs.get("band_hz", []))] or None
reach = reach_from_means(table("means"), experiment, mids, band)
log.info("study reach: %s", reach)
slots = [np.asarray(cut_endpoints_mm(c, experiment), float) for c in cuts] if placed else None
# an earlier plan's binding interval (config plan.binding_before): the narrowing is measured
# on its binding prediction
before = read_before(inp.binding_before) if "binding_before" in inp.keys() else None
# the study's chatter verdicts condition the stability limit (robomill.plan.conditioning); a
# file that breaks its contract: one line, and the prior interval
stability = None
if "verdicts" in inp.keys():
    try:
        stability = verdict_stability(read_verdicts(inp.verdicts))
    except RawDataError as err:
        log.warning("%s (the stability limit is not conditioned on verdicts)", err)
plan = make_plan(req, measured, cell, cuts, experiment, robot_name=cell.robot.name,
                 reach=reach, study_slots=slots,
                 binding_constraint=None if before is None else str(before["constraint"].iloc[-1]),
                 binding_before=before,
                 stability=stability)
if plan.candidates.attrs.get("stability_evidence_note"):
    log.warning("%s", plan.candidates.attrs["stability_evidence_note"])
inputs = [str(f) for f in inp]
write_artefact(compact(plan.candidates), out.candidates, rule="plan_make", inputs=inputs,
               config_section=req.raw)
write_artefact(plan.pose_map, out.pose_map, rule="plan_make", inputs=inputs,
               config_section=req.raw)
write_table(plan.plan, out.plan)
write_table(plan.pareto, out.pareto)
write_table(plan.study, out.study)
write_table(plan.comparison, out.comparison)
write_table(plan.path_summary, out.path_summary)
write_table(plan.evidence if plan.evidence is not None
            else pd.DataFrame(columns=list(EVIDENCE_COLUMNS)), out.evidence)
wobj = req.work_object or BASE
header = (f"robomill plan of {req.path}: the planned cuts, ranked by removal rate; "
          f"robot {cell.robot.name}\ncheck it in the offline programming tool before running")
pcell = program_cell(cell.robot, wobj.T_base_part, cell_file.mass_model,
                     frames=cell_file.controller_frames, spindle=cell_file.spindle,
                     motion=req.motion, q_home_deg=cell_file.q_home_deg)
program = write_program(plan.paths, cell_file.controller, pcell, out.program, header=header)
log.info("program (%s): %s", cell_file.controller or "no controller named: stations only",
         ", ".join(str(f) for f in program))
for path in plan.paths:
    if path.refused:
        log.info("cut %s refused: %s", path.cut, path.refused)
write_table(binding_table(plan.binding, req.purpose, len(cuts), int(p.raw_folders), before),
            out.binding)
for path, data in ((out.manifest, plan.manifest), (out.config, plan.config)):
    with atomic_path(path) as tmp:
        tmp.write_text(yaml.safe_dump(data, sort_keys=False))
log.info("missing predictions: %s", plan.candidates.attrs["missing_predictions"] or "none")
log.info("plan:\n%s", plan.plan.to_string())
log.info("comparison:\n%s", plan.comparison.to_string())
