"""Impact files (CSV hits, UFF 58 time histories or FRFs) -> hit checks -> windows -> FRFs
H(response point, reference point) of whatever layout was measured (H1, H2, coherence), the
hammer's force spectrum, UFF 58 export with node numbers.
The job: robomill.pipeline.jobs.modal_frf."""

from robomill.pipeline.jobs import modal_frf
from robomill.pipeline.runlog import setup

modal_frf.run(snakemake.input, snakemake.output, snakemake.params,
              log=setup(snakemake.log[0], "modal_frf"))
