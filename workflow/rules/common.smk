# Helpers shared by the rules: where raw data comes from, the study plan, target lists.
# Keep this file small: computation lives in src/robomill/.
import os
from pathlib import Path

from robomill.codedeps import code_files, load_cache, save_cache
from robomill.experiment import cuts_by_set
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
    """Library modules named by hand as inputs of a rule (`io.manifest` →
    src/robomill/io/manifest.py). Not needed for what the rule's script or notebook imports:
    derive_code_inputs adds those to every rule."""
    return [
        str(REPO.joinpath("src", "robomill", *m.split(".")).with_suffix(".py"))
        for m in modules
    ]


def derive_code_inputs(rules):
    """Declare, as inputs of every rule with a script, the library files its script and
    notebook import, followed through the import graph (robomill.codedeps: ast only,
    cached), so that editing any of them reruns the rule (Snakemake's own code trigger sees
    only the script). Called once, after every rule is defined (Snakefile)."""
    src = REPO / "src"
    cache = Path(".snakemake") / "robomill-codedeps.json"
    load_cache(cache)
    for r in rules:
        if not r.script:
            continue
        script = r.basedir.join(r.script).get_path_or_uri(secret_free=False)
        have = {str(f) for f in r.input if not callable(f)}
        notebooks = [f for f in have if f.endswith(".ipynb")]
        new = [f for f in code_files([script, *notebooks], src) if f not in have]
        if new:
            if r.input_modifier is None:  # a rule without inputs of its own
                r.input_modifier = workflow.modifier.path_modifier
            r.set_input(*new)
    save_cache(cache)
