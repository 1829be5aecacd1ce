"""Chapter 3.1's findings (robomill.forces.findings): the dominant peak and its verdict
against the modes, the records, the kinematic peak and its sanity flag, the force levels and
the cutting coefficients, with the scorecard rows of the stage for its "Against the thesis"
section.

The job of the rule script ``workflow/scripts/forces_findings.py``."""

from __future__ import annotations

import logging

import pandas as pd

from robomill.findings import write_findings
from robomill.forces.findings import forces_findings
from robomill.forces.tables import planted_coefficients
from robomill.io import open_artefact
from robomill.pipeline.design_tables import describe_design, design_factors
from robomill.pipeline.scorecard import stage_comparisons


def run(inputs, outputs, params, *, log: logging.Logger) -> None:
    """The rule's job: ``inputs``, ``outputs`` and ``params`` are the rule's own
    (Snakemake's named lists, read by name), ``log`` its logger
    (:func:`robomill.pipeline.runlog.setup`)."""
    modes = pd.read_csv(inputs.modes) if "modes" in inputs.keys() else None
    truth = open_artefact(inputs.truth) if "truth" in inputs.keys() else None
    cuts = pd.read_csv(inputs.cuts)
    design = {"design": describe_design(cuts, params.experiment),
              "grouping": list(design_factors(cuts, params.experiment).grouping)}
    found = forces_findings(pd.read_csv(inputs.peaks), modes, mode_match_hz=params.mode_match_hz,
                            band_hz=params.band_hz, prominence_db=params.prominence_db,
                            spectra=open_artefact(inputs.spectra), means=pd.read_csv(inputs.means),
                            coefficients=pd.read_csv(inputs.coefficients),
                            design=design, planted=planted_coefficients(truth),
                            experiment=params.experiment, settings=params.settings,
                            thesis_design=params.thesis_design)
    found.comparisons = stage_comparisons("forces", thesis_study=bool(params.thesis_study))
    write_findings(found, outputs.findings)
    log.info("%d findings, %d comparison rows", len(found.items), len(found.comparisons))
