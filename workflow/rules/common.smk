# Helpers shared by the rules: where raw data comes from, the study plan, target lists.
# Keep this file small: computation lives in src/robomill/.
import os
from pathlib import Path

from robomill.experiment import cuts_by_set, tracker_run_id
from robomill.io.manifest import load_manifest
from robomill.synth.plan import experiment_header, planned_files, synthetic_cuts

REPO = Path(workflow.basedir)
SYNTHETIC = config["data"]["source"] == "synthetic"
RAW = "results/synthetic/raw" if SYNTHETIC else config["data"]["raw_dir"]
MANIFEST = f"{RAW}/manifest.yaml"
ENV = "../envs/robomill.yaml"

# The study plan: from the configuration for synthetic data, from the manifest for raw data.
if SYNTHETIC:
    CUTS = synthetic_cuts(config)
    RAW_FILES = planned_files(config)
    EXPERIMENT = experiment_header(config)
else:
    _manifest = load_manifest(MANIFEST)
    CUTS = _manifest.cuts
    RAW_FILES = _manifest.files
    EXPERIMENT = _manifest.experiment
CUT_IDS = [c.id for c in CUTS]

# The cell (robot, home posture, tool orientation, gear trains): the raw folder's cell.yaml
# (kind cell; synthetic mode writes one from config cell:), else the configuration's cell:
# section written to results/ingest/cell.yaml (raw folders from before cell files).
CELL_RELPATH = next((f["path"] for f in RAW_FILES if f["kind"] == "cell"), "")
CELL = f"{RAW}/{CELL_RELPATH}" if CELL_RELPATH else "results/ingest/cell.yaml"


wildcard_constraints:
    cut="s[0-9]+_g[0-9]+_(px|py|my)",


# Every stage appends the outputs that `all` must build (chapters, book).
ALL_TARGETS = []


def all_targets(wildcards):
    return ALL_TARGETS


def raw_files(kind, **meta):
    """Paths of the raw files of `kind` (matching `meta`) in the active raw folder."""
    return [
        f"{RAW}/{f['path']}"
        for f in RAW_FILES
        if f["kind"] == kind and all(f.get(k) == v for k, v in meta.items())
    ]


def notebook(name):
    """A chapter notebook in the repository (works with --directory elsewhere)."""
    return str(REPO / "notebooks" / name)


def code(*modules):
    """Library modules a rule uses, declared as inputs so that editing one reruns the rule
    (Snakemake's own code trigger sees only the rule's script). `io.manifest` →
    src/robomill/io/manifest.py."""
    return [
        str(REPO.joinpath("src", "robomill", *m.split(".")).with_suffix(".py"))
        for m in modules
    ]
