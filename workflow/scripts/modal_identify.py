"""FRFs of any layout -> thesis peak picking, LSCF stabilization chart over all measured FRFs,
modes (sdypy-EMA), mode shapes over the measured points, MAC matrix, sanity flags, UFF 55
(robomill.pipeline.jobs.modal_identify)."""

from robomill.pipeline.jobs.modal_identify import identify_frf_file
from robomill.pipeline.runlog import setup

identify_frf_file(snakemake.input.frf, snakemake.output,
                  settings=snakemake.params.modal,
                  experiment_band_hz=snakemake.params.experiment_band_hz,
                  level=snakemake.params.level, log=setup(snakemake.log[0], "modal_identify"))
