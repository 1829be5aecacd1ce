"""Which edits rerun what: a chapter notebook edit reruns that chapter only; a library module
edit reruns the rules that use it (and what depends on them), nothing else."""

import shutil

import pytest
from conftest import REPO, SNAKEMAKE, raw_copy_of_run

from robomill.pipeline.why import parse_dry_run

pytestmark = [pytest.mark.pipeline, pytest.mark.whole_study]


def _copy_repo(dst):
    shutil.copytree(REPO, dst, ignore=shutil.ignore_patterns(
        ".venv", "results", ".snakemake", ".git", "__pycache__", "*.egg-info", ".pytest_cache",
        ".ruff_cache"))
    return dst


def _snakemake(repo, work, *args):
    """Snakemake on the copy with the copy's package first (PYTHONPATH): its rules run, and
    track as their code inputs, the copy's library, as a checkout's rules run its own."""
    import os
    import subprocess

    env = {**os.environ, "PYTHONPATH": str(repo / "src")}
    return subprocess.run([SNAKEMAKE, "-s", str(repo / "Snakefile"), "--directory", str(work),
                           "--configfile", str(work / "config.yaml"), *args],
                          capture_output=True, text=True, timeout=900, env=env)


def _planned(repo, work, target):
    proc = _snakemake(repo, work, "-n", target)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return {j.rule: j for j in parse_dry_run(proc.stdout + proc.stderr)}


def test_edits_rerun_only_what_uses_them(tiny_run, tmp_path):

    repo = _copy_repo(tmp_path / "repo")
    work = tmp_path / "work"
    work.mkdir()
    # the tiny run's synthetic raw files serve as a raw data set (no simulators to rerun)
    raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=work / "config.yaml")
    proc = _snakemake(repo, work, "-j2", "ch0")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert _planned(repo, work, "ch0") == {}

    nb = repo / "notebooks" / "ch0.ipynb"
    nb.write_text(nb.read_text() + "\n")
    jobs = _planned(repo, work, "ch0")
    assert set(jobs) == {"ch0"}
    assert jobs["ch0"].categories == ["input changed"]

    nb.write_text(nb.read_text().rstrip("\n") + "\n")
    proc = _snakemake(repo, work, "-j2", "ch0")
    assert proc.returncode == 0, proc.stderr[-3000:]
    module = repo / "src" / "robomill" / "experiment.py"
    module.write_text(module.read_text() + "\n# an edit\n")
    jobs = _planned(repo, work, "ch0")
    # chapter 0's findings (robomill.experiment_findings) import experiment.py too
    assert set(jobs) == {"ingest_manifest", "ingest_findings", "ch0"}
    assert "input changed" in jobs["ingest_manifest"].categories
    # ingest_findings is planned for both reasons; Snakemake names the upstream rerun first
    assert set(jobs["ingest_findings"].categories) & {"input changed", "upstream job reruns"}

    # issue 31: an edit of the LSCF estimator reruns the modal identification that imports it,
    # not the FRF estimation before it (modal/frf.py does not import modal/lscf.py)
    module.write_text(module.read_text().removesuffix("\n# an edit\n"))
    target = "results/modal/modes.csv"
    proc = _snakemake(repo, work, "-j2", target)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert _planned(repo, work, target) == {}
    lscf = repo / "src" / "robomill" / "modal" / "lscf.py"
    lscf.write_text(lscf.read_text() + "\n# an edit\n")
    jobs = _planned(repo, work, target)
    assert set(jobs) == {"modal_identify"}, jobs
    assert jobs["modal_identify"].categories == ["input changed"]


def _inputs_of(repo, work, rule, target):
    """The input files Snakemake lists for ``rule`` in a dry run of ``target`` (forced)."""
    proc = _snakemake(repo, work, "-n", "--forceall", target)
    assert proc.returncode == 0, proc.stderr[-3000:]
    block = (proc.stdout + proc.stderr).split(f"rule {rule}:", 1)[1]
    return [i.strip() for i in block.split("input:", 1)[1].split("\n", 1)[0].split(", ")]


def test_editing_any_module_a_rule_imports_makes_why_list_it(tiny_run, tmp_path):
    """Every library file that ch0's script (render_chapter.py) and notebook import, through
    the import graph (robomill.pipeline.codedeps), is an input of ch0 (one forced dry run
    lists them all), and editing one makes `make why` list ch0 ("input changed"): shown for
    the package's root, a module the notebook reaches through two imports, and the rule's own
    job module. Likewise stiffness/poses.py for stiffness_optimal, whose hand-kept code() list
    was empty. (Content edits: Snakemake ignores a newer mtime when the checksum of a small
    input is unchanged.)"""
    import os

    from robomill.pipeline.codedeps import code_files
    from robomill.pipeline.why import format_table

    repo = _copy_repo(tmp_path / "repo")
    work = tmp_path / "work"
    work.mkdir()
    raw_copy_of_run(tiny_run, tmp_path / "raw", config_path=work / "config.yaml")
    proc = _snakemake(repo, work, "-j2", "ch0")
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert _planned(repo, work, "ch0") == {}
    modules = code_files([repo / "workflow/scripts/render_chapter.py",
                          repo / "notebooks/ch0.ipynb"], repo / "src")
    names = {os.path.relpath(m, repo / "src") for m in modules}
    edited = ("robomill/__init__.py", "robomill/forces/model.py",
              "robomill/pipeline/jobs/render_chapter.py")
    assert {"robomill/pipeline/chapters.py", "robomill/plotting.py",
            "robomill/pipeline/captions.py", "robomill/pipeline/runlog.py", *edited} <= names, names
    inputs = set(_inputs_of(repo, work, "ch0", "ch0"))
    assert not {str(m) for m in modules} - inputs, sorted({str(m) for m in modules} - inputs)
    for name in edited:
        module = repo / "src" / name
        text = module.read_text()
        module.write_text(text + "\n# an edit\n")  # content: an mtime alone is not enough
        try:
            jobs = _planned(repo, work, "ch0")
        finally:
            module.write_text(text)
        assert "ch0" in jobs, (module, format_table(list(jobs.values())))
        # directly, or through ingest_manifest when that imports the module too
        assert set(jobs["ch0"].categories) & {"input changed", "upstream job reruns"}, \
            (module, jobs["ch0"].categories)
    assert _planned(repo, work, "ch0") == {}
    # a rule whose hand-kept list was empty, checked on the DAG without building it
    assert str(repo / "src" / "robomill" / "stiffness" / "poses.py") in \
        _inputs_of(repo, work, "stiffness_optimal", "stiffness_optimal")
