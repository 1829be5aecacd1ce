"""The workflow profile that every Snakemake run of this repository picks up by itself."""

import os
from pathlib import Path

from snakemake.cli import parse_args

REPO = Path(__file__).resolve().parents[1]


def _args(tmp_path, *extra):
    cwd = os.getcwd()
    os.chdir(tmp_path)  # a user's folder elsewhere: the profile is found next to the Snakefile
    try:
        return parse_args(["-s", str(REPO / "Snakefile"), "-n", *extra, "all"])[1]
    finally:
        os.chdir(cwd)


def test_default_profile_sets_the_greedy_scheduler_and_a_2s_rate_window(tmp_path):
    args = _args(tmp_path)
    assert args.scheduler == "greedy"
    assert args.max_jobs_per_timespan.timespan == 2.0
    assert args.max_jobs_per_timespan.max_jobs == 1000


def test_default_profile_adds_to_the_slurm_profile(tmp_path):
    args = _args(tmp_path, "--profile", str(REPO / "workflow/profiles/slurm"))
    assert args.executor == "slurm" and args.scheduler == "greedy"


def test_one_profiles_folder_found_through_the_link_next_to_the_snakefile(tmp_path):
    link = REPO / "profiles"
    assert link.is_symlink() and link.resolve() == (REPO / "workflow" / "profiles").resolve()
    assert sorted(p.name for p in (REPO / "workflow" / "profiles").iterdir()) == [
        "default", "local", "slurm"]
    assert _args(tmp_path, "--profile", str(link / "local")).cores == 2


def test_command_line_still_wins(tmp_path):
    args = _args(tmp_path, "--scheduler", "ilp", "--max-jobs-per-timespan", "100/1s")
    assert args.scheduler == "ilp" and args.max_jobs_per_timespan.timespan == 1.0
