"""Rybak n.d.: the programme's inverse dynamics and replay, and the vertical move with a force
error → trajectory.nc and forces.nc."""

from robomill.hexapod.study import dynamics_datasets
from robomill.io import write_artefact
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "hexapod")
section = snakemake.params.hexapod
traj, forces = dynamics_datasets(section)
write_artefact(traj, snakemake.output.trajectory, rule=snakemake.rule, config_section=section)
write_artefact(forces, snakemake.output.forces, rule=snakemake.rule, config_section=section)
log.info("vertical move final drift %s mm, replay holds %.3f s",
         traj["vertical_final_drift_mm"].values.round(4), float(traj["replay_hold_s"]))
