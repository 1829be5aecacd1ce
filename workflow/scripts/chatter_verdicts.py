"""Chatter verdicts of every cut's force record and every sound/vibration recording
(robomill.chatter.recordings), their chatter lines tested on the cuts' air passes:
results/chatter/verdicts.csv and the pooled spectrograms."""

from robomill.pipeline.runlog import setup

log = setup(snakemake.log[0], "chatter_verdicts")

from robomill.chatter.recordings import (  # noqa: E402
    JUDGED_KINDS,
    is_air_pass,
    judge_study,
    verdict_findings,
)
from robomill.chatter.verdicts import VerdictSettings  # noqa: E402
from robomill.findings import write_findings  # noqa: E402
from robomill.io import write_artefact  # noqa: E402
from robomill.io.artefacts import write_table  # noqa: E402
from robomill.study import load_study  # noqa: E402

manifest = load_study(snakemake.input.study)
settings = VerdictSettings.from_mapping(snakemake.params.settings)
entries = [f for f in manifest.files if f["kind"] in JUDGED_KINDS]
table, spectrograms = judge_study(manifest, entries, settings, log=log)
write_table(table, snakemake.output.verdicts)
spectrograms.attrs["energy_ratio_threshold"] = settings.energy_ratio_threshold
write_artefact(spectrograms, snakemake.output.spectrograms, rule="chatter_verdicts",
               inputs=list(snakemake.input.raw), config_section=snakemake.params.settings)
counts = table["verdict"].value_counts().to_dict() if len(table) else {}
log.info("%d records judged: %s", len(table), counts)
n_air = sum(is_air_pass(e) for e in entries)
write_findings(verdict_findings(table, settings, n_air), snakemake.output.findings)
