"""``robomill plan``: a bad request stops with one line before any pipeline runs; the command
it runs targets ``plan`` with the request and the raw folder."""

import json
from pathlib import Path

from robomill.cli import main
from robomill.cli.plan import last_reason, plan_command


def test_bad_request_is_one_line(tmp_path, capsys):
    req = tmp_path / "plan.yaml"
    req.write_text("kind: plan\noperation: {length_mm: 40}\n")
    assert main(["plan", str(tmp_path), "--request", str(req)]) == 1
    out = capsys.readouterr().out.strip()
    assert out == f"{req}: tool: missing (a required field)"


def test_folder_must_be_raw_or_project(tmp_path, capsys):
    assert main(["plan", str(tmp_path), "--request", "plan.yaml"]) == 1
    assert "neither a raw folder (manifest.yaml) nor a project folder" in capsys.readouterr().out


def test_command_for_a_raw_folder(tmp_path):
    (tmp_path / "manifest.yaml").write_text("experiment: {}\ncuts: []\nfiles: []\n")
    cmd, root = plan_command(tmp_path, Path("plan.yaml"), cores=3, cwd=Path.cwd())
    assert (root / "Snakefile").exists()
    assert cmd[-2:] == ["--", "plan"] and "-j3" in cmd
    assert f"data={tmp_path.resolve()}" in cmd
    plan_cfg = next(a for a in cmd if a.startswith("plan="))
    assert json.loads(plan_cfg[5:]) == {"request": str(Path("plan.yaml").resolve())}


def test_refusal_line_is_found_in_the_rule_log(tmp_path):
    log = tmp_path / "make.log"
    log.write_text("Traceback ...\nrobomill.plan.choose.PlanInfeasible: no reachable "
                   "placement: none of the 2 placements\n")
    assert last_reason(log) == "no reachable placement: none of the 2 placements"
    assert last_reason(tmp_path / "none.log") is None
