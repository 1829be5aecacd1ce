"""The force accuracy each position tolerance needs: results/hexapod/force_accuracy.csv
(see robomill.hexapod.sensitivity.force_accuracy_requirement)."""

from robomill.hexapod.sensitivity import force_accuracy_requirement
from robomill.io import open_artefact
from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "hexapod")
sens = open_artefact(snakemake.input.sensitivity)
force_N = float(open_artefact(snakemake.input.forces)["vertical_force_N"][0, 0])
table = force_accuracy_requirement(sens, force_N)
table.to_csv(snakemake.output[0], index=False)
log.info("force accuracy for %d tolerances (worst actuator %d)", len(table),
         table["worst_actuator"].iloc[0])
