# robomill: the study of robotic milling quality, as one workflow.
# A table of contents: configuration, one include per stage, and the targets.
import os
import sys

from snakemake.utils import min_version

from robomill.io import ConfigError
from robomill.kernels import cache_dir
from robomill.pipeline.config import (
    check_run_folder,
    run_folder,
    validate_config_cached,
)
from robomill.settings import SCHEMAS

min_version("9.0")

# numba's compiled kernels: one cache per virtual environment, which every job shares (set
# before any job starts; robomill.kernels), not one per clone of the sources
os.environ.setdefault("NUMBA_CACHE_DIR", str(cache_dir()))


configfile: "config.yaml"


# Values as users write them (`data=FOLDER`, numbers given as text: YAML 1.1, --config), then
# the whole configuration and each section by its own schema, defaults filled. A bad key stops
# the run with one line naming it (robomill.pipeline.config.validate_config); the answer is
# kept in .snakemake/robomill-config/ for the next run with the same configuration and schemas
# (the package's own: robomill.settings.SCHEMAS).
try:
    checked = validate_config_cached(
        config,
        SCHEMAS / "config.schema.yaml",
        ".snakemake/robomill-config",
    )
except ConfigError as exc:
    print(f"robomill: {exc}", file=sys.stderr)
    sys.exit(1)
config.clear()
config.update(checked)


# The run's folder: here, or the one the configuration names (config workdir), entered by
# Snakemake's workdir directive. The next experiment's configuration
# (results/plan/next/config.yaml) names its own, so that running the planned cuts leaves the
# study's results as they are. Under snakemake --directory D Snakemake ignores the directive:
# D must then be that folder itself, or the run stops with one line (check_run_folder).
RUN_FOLDER = run_folder(config)
if RUN_FOLDER:
    STARTED_IN = os.getcwd()

    workdir: RUN_FOLDER

    try:
        check_run_folder(RUN_FOLDER, STARTED_IN, os.getcwd())
    except ConfigError as exc:
        print(f"robomill: {exc}", file=sys.stderr)
        sys.exit(1)


report: "workflow/report/workflow.rst"


include: "workflow/rules/common.smk"
include: "workflow/rules/chapter.smk"
include: "workflow/rules/synth.smk"
include: "workflow/rules/ingest.smk"
include: "workflow/rules/calibration.smk"
include: "workflow/rules/surface.smk"
include: "workflow/rules/forces.smk"
include: "workflow/rules/straightness.smk"
include: "workflow/rules/modal.smk"
include: "workflow/rules/chatter.smk"
include: "workflow/rules/stiffness.smk"
include: "workflow/rules/hexapod.smk"
include: "workflow/rules/plan.smk"
include: "workflow/rules/chapters.smk"
include: "workflow/rules/book.smk"


# the import graph that code_inputs followed (common.smk), kept for the next run
save_cache(CODE_CACHE)


onerror:
    import atexit
    from robomill.pipeline.failures import summarize_failures

    # printed at exit, so it is the last thing on screen, after Snakemake's own messages
    atexit.register(print, summarize_failures(log), file=sys.stderr, flush=True)


rule all:
    default_target: True
    input:
        all_targets,


# Every artefact the chapters of `all` read, without the chapters, the scorecard and the book
# (common.smk, chapter_artefacts): a study computed where no kernel or browser runs, e.g. on a
# cluster's nodes, its pages made later with `all`.
rule artefacts:
    input:
        chapter_artefacts,
