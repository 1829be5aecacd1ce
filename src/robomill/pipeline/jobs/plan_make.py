"""The next cuts from what was measured: candidates, the chosen cuts, the Pareto
front, the study's own cuts beside the plan, and the next experiment's manifest and config.

The job of the rule script ``workflow/scripts/plan_make.py``."""

from __future__ import annotations

import logging

import pandas as pd
import yaml

from robomill.io import write_artefact, write_table
from robomill.io.atomic import atomic_path
from robomill.plan.binding import binding_table, read_before
from robomill.plan.conditioning import EVIDENCE_COLUMNS
from robomill.plan.inputs import INPUT_KEYS, load_inputs, model_record
from robomill.plan.make import make_plan
from robomill.plan.outputs import compact
from robomill.plan.program import program_cell, write_program
from robomill.plan.workobject import BASE


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    # the study's artefacts and parameters (robomill.plan.inputs): the same routine serves
    # robomill predict, which reads them back from results/plan/model.yaml
    paths = {k: str(inputs[k]) for k in INPUT_KEYS if k in inputs.keys()}
    model_params = {"waviness_noise": params.waviness_noise, "fmin_cycles": params.fmin_cycles,
                    "level": float(params.level)}
    loaded = load_inputs(paths, model_params, log=log)
    for note in loaded.notes:
        log.warning("%s", note)
    req, measured, cell = loaded.req, loaded.measured, loaded.cell
    # the study's cuts with the process the ingestion rule resolved (robomill.study), each
    # predicted as a planning candidate (robomill.plan.candidate)
    cuts = loaded.study_cuts
    experiment, cell_file = loaded.experiment, loaded.cell_file
    log.info("study reach: %s", loaded.reach)
    # an earlier plan's binding interval (config plan.binding_before): the narrowing is measured
    # on its binding prediction
    before = read_before(inputs.binding_before) if "binding_before" in inputs.keys() else None
    plan = make_plan(req, measured, cell, cuts, experiment, robot_name=cell.robot.name,
                     reach=loaded.reach, study_slots=loaded.slots,
                     binding_constraint=(None if before is None
                                         else str(before["constraint"].iloc[-1])),
                     binding_before=before,
                     stability=loaded.stability, impact_tcp_mm=loaded.impact_tcp_mm)
    if plan.candidates.attrs.get("stability_evidence_note"):
        log.warning("%s", plan.candidates.attrs["stability_evidence_note"])
    read = [str(f) for f in inputs]
    write_artefact(compact(plan.candidates), outputs.candidates, rule="plan_make", inputs=read,
                   config_section=req.raw)
    write_artefact(plan.pose_map, outputs.pose_map, rule="plan_make", inputs=read,
                   config_section=req.raw)
    write_table(plan.plan, outputs.plan)
    with atomic_path(outputs.model) as tmp:
        tmp.write_text(yaml.safe_dump(model_record(paths, model_params), sort_keys=False))
    if plan.candidates.attrs.get("shortfall"):
        log.warning("%s", plan.candidates.attrs["shortfall"])
    write_table(plan.pareto, outputs.pareto)
    write_table(plan.study, outputs.study)
    write_table(plan.comparison, outputs.comparison)
    write_table(plan.path_summary, outputs.path_summary)
    write_table(plan.evidence if plan.evidence is not None
                else pd.DataFrame(columns=list(EVIDENCE_COLUMNS)), outputs.evidence)
    wobj = req.work_object or BASE
    header = (f"robomill plan of {req.path}: the planned cuts, ranked by removal rate; "
              f"robot {cell.robot.name}\ncheck it in the offline programming tool before running")
    pcell = program_cell(cell.robot, wobj.T_base_part, cell_file.mass_model,
                         frames=cell_file.controller_frames, spindle=cell_file.spindle,
                         motion=req.motion, q_home_deg=cell_file.q_home_deg)
    program = write_program(plan.paths, cell_file.controller, pcell, outputs.program, header=header)
    log.info("program (%s): %s", cell_file.controller or "no controller named: stations only",
             ", ".join(str(f) for f in program))
    for path in plan.paths:
        if path.refused:
            log.info("cut %s refused: %s", path.cut, path.refused)
    write_table(binding_table(plan.binding, req.purpose, len(cuts), int(params.raw_folders),
                              before), outputs.binding)
    for path, data in ((outputs.manifest, plan.manifest), (outputs.config, plan.config)):
        with atomic_path(path) as tmp:
            tmp.write_text(yaml.safe_dump(data, sort_keys=False))
    log.info("missing predictions: %s", plan.candidates.attrs["missing_predictions"] or "none")
    log.info("plan:\n%s", plan.plan.to_string())
    log.info("comparison:\n%s", plan.comparison.to_string())
