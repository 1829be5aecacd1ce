"""The plan checked only through files, end to end on the tiny study: `plan`, then the planned
cuts cut in their own run (`--configfile results/plan/next/config.yaml`, each planned path
tracked loaded and in the air), then `plan` again: every planned cut's stability, force,
deflection and waviness row names a file of that run, and the rows say what kind of evidence
they are."""

import shutil
import subprocess

import pandas as pd
import pytest
from conftest import NO_BOOK_PDF, REPO, SNAKEMAKE, run_snakemake

from robomill.plan import NEXT_RUN_DIR

# whole_study: it cuts the planned cuts as their own run, and it is the first module to need
# the shared plan (conftest.planned_run), so `make test` hands it out among the first and the
# plan's other readers find the plan made
pytestmark = [pytest.mark.pipeline, pytest.mark.whole_study]

# what plan_check reads of the planned cuts' run (`all` builds these and the chapters)
NEXT_OUTCOMES = ["results/forces/mean_forces.csv", "results/forces/peaks.csv",
                 "results/straightness/deflection.csv", "results/straightness/gears.csv",
                 "results/straightness/profiles.nc"]


@pytest.fixture(scope="module")
def checked_study(planned_run, tmp_path_factory):
    # the tiny study with its request (plan.yaml) and plan made (conftest.planned_run),
    # copied: the shared study stays as it is
    study = tmp_path_factory.mktemp("plan_check") / "study"
    shutil.copytree(planned_run, study, symlinks=True)
    before = pd.read_csv(study / "results/plan/check.csv")
    nxt = study / "results/plan/next/config.yaml"
    # as docs/usage.md says, from the study's folder (the configuration names the run's own)
    cmd = [SNAKEMAKE, "-s", str(REPO / "Snakefile"), "--configfile",
           str(REPO / ".test" / "config.yaml"), str(nxt), "-j2"]
    dry = subprocess.run([*cmd, "-n", "all", "--config", NO_BOOK_PDF], cwd=study,
                         capture_output=True, text=True, timeout=600)
    assert dry.returncode == 0, dry.stderr[-4000:]
    run = subprocess.run([*cmd, *NEXT_OUTCOMES], cwd=study, capture_output=True, text=True,
                         timeout=900)
    assert run.returncode == 0, run.stderr[-4000:]
    proc = run_snakemake(study, "-j2", "plan", "--config", NO_BOOK_PDF)
    assert proc.returncode == 0, proc.stderr[-4000:]
    return study, before, dry.stdout


def test_the_next_runs_all_tracks_each_planned_path_loaded_and_in_the_air(checked_study):
    study, _, dry = checked_study
    planned = pd.read_csv(study / "results/plan/plan.csv")["cut"].tolist()
    assert "rule straightness_deflection" in dry          # `all` of the next run builds it
    for cut in planned:
        assert f"results/synthetic/raw/tracker/{cut}_air.csv" in dry
    d = pd.read_csv(study / NEXT_RUN_DIR / "results/straightness/deflection.csv")
    assert d["cut"].tolist() == planned and (d["air_run"] == d["cut"] + "_air").all()


def test_every_planned_cut_is_checked_through_its_own_runs_files(checked_study):
    study, before, _ = checked_study
    planned = pd.read_csv(study / "results/plan/plan.csv")["cut"].astype(str).tolist()
    assert not before["cut"].isin(planned).any()         # before the run: no planned outcome
    check = pd.read_csv(study / "results/plan/check.csv")
    rows = check[check["cut"].isin(planned)]
    expect = {"stability", "force", "deflection_normal", "deflection_axial", "waviness"}
    for cut in planned:
        got = rows[rows["cut"] == cut]
        assert set(got["quantity"]) == expect, cut
        assert got["source"].str.startswith(f"{NEXT_RUN_DIR}/").all(), got["source"].tolist()
    assert not rows["in_sample"].any()
    study_rows = check[~check["cut"].isin(planned)]
    assert len(study_rows) and study_rows["in_sample"].all()
    assert not study_rows["source"].str.startswith("results/plan/").any()
    # every planned cut's deflection is measured (loaded minus air, the virtual cell's
    # closed-loop cut: its magnitude is the cell's, not the planner's model), and a row holds
    # exactly when its outcome lies inside the stated interval
    d = rows[rows["quantity"].str.startswith("deflection")]
    assert len(d) == 2 * len(planned) and (d["outcome"].abs() > 0).all()
    inside = (d["outcome"] >= d["low"]) & (d["outcome"] <= d["high"])
    assert (d["held"].astype(bool) == inside).all()
    s = pd.read_csv(study / "results/plan/check_summary.csv").set_index("key")["value"]
    assert s["n_oos"] == len(rows) and s["n_in"] == len(study_rows)
    assert s["n_held_oos"] == rows["held"].astype("boolean").fillna(False).sum()
    assert s["nominal_coverage_percent"] == 95.0
    ch7 = (study / "results/chapters/ch7.html").read_text()
    assert f"of {len(rows)} outcomes fell inside their stated" in ch7
