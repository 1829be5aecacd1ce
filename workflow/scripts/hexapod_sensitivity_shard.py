"""One shard of the sensitivity study: one actuator in error, every error size."""

from robomill.pipeline.runlog import Progress, setup

log = setup(snakemake.log[0], "hexapod")

from robomill.hexapod.study import sensitivity_shard  # noqa: E402
from robomill.io import write_artefact  # noqa: E402

section = snakemake.params.hexapod
progress = Progress(log, 1.0, f"sensitivity of actuator {snakemake.params.actuator}")
ds = sensitivity_shard(section, int(snakemake.params.actuator), progress=progress.update)
write_artefact(ds, snakemake.output[0], rule=snakemake.rule, config_section=section)
progress.finish(f"actuator {snakemake.params.actuator}: {ds.sizes['force_error_pct']} force "
                f"errors, drift {ds['drift_mm'].values.round(4).tolist()} mm")
