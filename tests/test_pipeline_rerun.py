"""A chapter rerun and the plan, in a copy of the tiny study (the shared run stays as other
test modules read it): a chapter rerun draws its figures again, the same bytes, and gives the
same page; `plan` builds chapter 7 (in the shared copy with the plan made,
conftest.planned_run)."""

import shutil

import pytest
from conftest import TINY_PLAN_REQUEST, run_snakemake

pytestmark = pytest.mark.pipeline


@pytest.fixture(scope="module")
def study(tiny_run, tmp_path_factory):
    copy = tmp_path_factory.mktemp("rerun") / "study"
    shutil.copytree(tiny_run, copy, symlinks=True,
                    ignore=shutil.ignore_patterns(".chromium-profile", "locks"))
    return copy


def test_a_chapter_rerun_gives_the_same_figures_and_page(study):
    figures = study / "results/figures/ch3_modal"
    before = {p.name: p.read_bytes() for p in figures.glob("*.png")}
    page = (study / "results/chapters/ch3_modal.html").read_text()
    assert len(before) >= 5
    proc = run_snakemake(study, "-j2", "ch3_modal", "--forcerun", "ch3_modal", timeout=300)
    assert proc.returncode == 0, proc.stderr[-3000:]
    assert {p.name: p.read_bytes() for p in figures.glob("*.png")} == before
    assert (study / "results/chapters/ch3_modal.html").read_text() == page


def test_the_plan_builds_chapter_7(planned_run):
    """`snakemake plan` (the tiny study with its request, plan.yaml, in its folder:
    conftest.planned_run): the plan and its chapter, every figure and table shown and referred
    to (the chapter's last cell checks it)."""
    study = planned_run
    assert (study / "plan.yaml").read_bytes() == TINY_PLAN_REQUEST.read_bytes()
    page = (study / "results/chapters/ch7.html").read_text()
    for ref in ("Figure 7.1 sets", "Figure 7.2 maps", "Table 7.1 lists", "Table 7.3 sets"):
        assert ref in page
    assert "being drawn" not in page
    # the Pareto front, p_stable over speed x depth before and after the verdicts, the pose
    # map, the best cut's path over station x rotation, and the program's moves and joints
    assert sorted(p.name for p in (study / "results/figures/ch7").glob("*.png")) == [
        "fig7_1_pareto.png", "fig7_2_p_stable.png", "fig7_3_pose_map.png", "fig7_4_path.png",
        "fig7_5_program_path.png", "fig7_6_program_joints.png"]
