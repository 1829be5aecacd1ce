"""Merged gear lines end to end: the examples/other_cell PUMA with 16 instead of 22
pinion teeth on joint 3 puts the joint-2 and joint-3 mesh lines of its 28 mm tracker runs
1.03 bins apart. The analysis flags the one peak they make as merged, listing both, and the
truth check counts joint 3 merged, not missed."""

import pandas as pd
import pytest
import yaml
from conftest import REPO, SNAKEMAKE, chapter_outputs

pytestmark = pytest.mark.pipeline


def test_coinciding_mesh_lines_of_the_example_are_flagged_merged(tmp_path):
    import os
    import subprocess

    overlay = REPO / "examples" / "other_cell" / "config.yaml"
    trans = yaml.safe_load(overlay.read_text())["cell"]["transmissions"]
    assert trans[2]["joint"] == 3 and trans[2]["teeth"] == 22
    trans[2]["teeth"] = 16
    sixteen = tmp_path / "sixteen.yaml"
    sixteen.write_text(yaml.safe_dump({"cell": {"transmissions": trans}}))
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--directory", str(tmp_path),
           "--configfile", str(REPO / ".test" / "config.yaml"), str(overlay), str(sixteen),
           "-j2", "results/straightness/truth_check.csv",
           "results/chapters/ch3_straightness.html"]
    proc = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=900,
                          env={**os.environ, "PYTHONHASHSEED": "0"})
    assert proc.returncode == 0, proc.stderr[-6000:]
    peaks = pd.read_csv(tmp_path / "results/straightness/peaks.csv")
    gear = peaks[peaks["mechanism"] == "gear"]
    mesh23 = gear[gear["joint"].isin([2, 3]) & (gear["order"] == "mesh")]
    assert len(mesh23) == 2  # one peak per feed (2 and 6 mm/s), not two
    assert mesh23["merged"].all()
    assert set(mesh23["candidates"]) == {"2:motor:mesh;3:motor:mesh"}
    assert not gear.loc[~gear.index.isin(mesh23.index), "merged"].any()
    tc = pd.read_csv(tmp_path / "results/straightness/truth_check.csv")
    j3 = tc[(tc["joint"] == 3) & (tc["order"] == "mesh")]
    assert (j3["class"] == "above_noise").all() and len(j3) == 2
    assert j3["merged"].all() and not j3["found"].any()
    # chapter 3.2 shows the merged peak with its candidates, and where joint 3 went
    text = chapter_outputs(tmp_path, "ch3_straightness")
    found = yaml.safe_load((tmp_path / "results/straightness/findings.yaml").read_text())
    values = {f["key"]: f["value"] for f in found["findings"]}
    assert values["n_merged"] == 2 and values["truth_merged"] == 2
    assert "2 gear peak(s) are **merged**" in text
    assert text.count("mm⁻¹: 2:motor:mesh, 3:motor:mesh") == 2
    assert "3:motor:mesh (−X, 2 mm/s) → 2:motor:mesh" in text
    assert set(j3["merged_into"]) == {"2:motor:mesh"}
    above = tc[tc["class"] == "above_noise"]
    assert (above["found"] | above["merged"]).all()  # nothing above the noise is missed
