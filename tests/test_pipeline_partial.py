"""Partial studies: a raw folder with one kind of data builds the chapters it has data for;
`all` skips the rest with one line each and the book says what was skipped and why."""

import shutil
from pathlib import Path

import pytest
import yaml
from conftest import NO_BOOK_PDF, REPO, run_snakemake

from robomill.io.manifest import build_manifest, load_manifest, write_manifest

pytestmark = [pytest.mark.pipeline, pytest.mark.whole_study]


def _partial_folder(tiny_run: Path, dst: Path, kinds: set[str], with_cuts: bool) -> Path:
    """A raw folder with only the `kinds` files of the tiny run (and its cuts if asked), and
    the tiny config pointing at it (``dst/config.yaml``)."""
    src = tiny_run / "results/synthetic/raw"
    m = load_manifest(src / "manifest.yaml")
    raw = dst / "raw"
    files = [f for f in m.files if f["kind"] in kinds]
    for f in files:
        (raw / f["path"]).parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(src / f["path"], raw / f["path"])
    meta = [{k: v for k, v in f.items() if k != "sha256"} for f in files]
    write_manifest(build_manifest(m.experiment, m.cuts if with_cuts else [], meta, raw),
                   raw / "manifest.yaml")
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    cfg["data"] = {"source": "raw", "raw_dir": str(raw)}
    (dst / "config.yaml").write_text(yaml.safe_dump(cfg, sort_keys=False))
    return dst


CASES = {
    "forces_only": ({"force"}, True, ["ch0", "ch3_forces", "ch6_chatter",
                                   "ch6_hexapod"],
                    ["chapter 1: no ctrack files in manifest.yaml",
                     "chapter 2: no profile or areal files in manifest.yaml",
                     "chapter 3.3: no impact files in manifest.yaml",
                     "chapter 4: no impact files in manifest.yaml",
                     "chapter 5: no robot files and no stiffness files in manifest.yaml",
                     "chapter 6.2: no robot files and no stiffness files in manifest.yaml"]),
    "impact_only": ({"impact"}, False, ["ch3_modal", "ch6_chatter", "ch6_hexapod"],
                    ["chapter 0: no cuts in manifest.yaml",
                     "chapter 3.1: no force files in manifest.yaml",
                     "chapter 3.2: no tracker files and no profile files in manifest.yaml",
                     "chapter 4: no force files in manifest.yaml"]),
}


@pytest.mark.parametrize("case", list(CASES))
def test_a_partial_raw_folder_builds_what_it_has_data_for(tiny_run, tmp_path, case):
    kinds, with_cuts, built, skipped = CASES[case]
    work = _partial_folder(tiny_run, tmp_path / case, kinds, with_cuts)
    proc = run_snakemake(work, "-j2", "all", "--config", NO_BOOK_PDF,
                         configfile=work / "config.yaml")
    assert proc.returncode == 0, proc.stderr[-6000:]
    for line in skipped:  # one line per skipped chapter, before the run
        assert proc.stderr.count(line) == 1, line
    chapters = sorted(p.stem for p in (work / "results/chapters").glob("*.html"))
    assert chapters == sorted(built)
    index = (work / "results/thesis/index.html").read_text()
    assert "Not built from this data" in index
    for line in skipped:
        assert f"<li>{line}</li>" in index
