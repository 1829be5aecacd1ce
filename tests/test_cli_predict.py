"""``robomill predict STUDY CUTS``: cut lists read with the manifest's rules (one line naming
the file, the cut and the key for a bad entry), and, on a built study, the same predictions as
the plan's own table of the study's cuts (the same code), for CSV and YAML alike."""


import pandas as pd
import pytest
import yaml

from robomill.cli import main
from robomill.errors import RawDataError
from robomill.io.cutlist import parse_cuts, read_cut_entries
from robomill.plan.cutlist import PREDICT_COLUMNS


def _parse(tmp_path, text, suffix=".yaml"):
    p = tmp_path / f"cuts{suffix}"
    p.write_text(text)
    return parse_cuts(p, read_cut_entries(p))


def test_yaml_and_csv_lists_give_the_same_cuts(tmp_path):
    y = _parse(tmp_path, "- {id: a, spindle_rpm: 20000, depth_mm: 0.3, feed_mm_s: 10, "
                         "direction: px, start_mm: [700, 60, 199.7], redundancy_deg: 5}\n"
                         "- {id: b, depth_mm: 1, feed_mm_s: 2, direction_deg: 45, "
                         "start_mm: [700, 80, 199], milling: down, radial_immersion: 0.5}\n")
    c = _parse(tmp_path, "id,spindle_rpm,depth_mm,feed_mm_s,direction,direction_deg,start_mm,"
                         "redundancy_deg,milling,radial_immersion\n"
                         "a,20000,0.3,10,px,,700 60 199.7,5,,\n"
                         "b,,1,2,,45,\"[700, 80, 199]\",,down,0.5\n", ".csv")
    assert y == c
    assert c[0].start_mm == (700.0, 60.0, 199.7) and c[1].spindle_rpm is None
    assert c[1].milling == "down" and c[0].redundancy_deg == 5.0


@pytest.mark.parametrize("text, suffix, names", [
    ("id,depth_mm,feed_mm_s,direction\nk1,0.3,fast,px\n", ".csv", ("cut k1", "feed_mm_s")),
    ("id,depth_mm,direction\nk2,0.3,px\n", ".csv", ("cut k2", "feed_mm_s")),
    ("- {id: k3, depth_mm: 0.3, feed_mm_s: 1, direction: up}\n", ".yaml",
     ("cut k3", "direction")),
    ("- {id: k4, depth_mm: 0.3, feed_mm_s: 1, direction: px, milling: climb}\n", ".yaml",
     ("cut k4", "milling")),
    ("- {id: k5, depth_mm: 0.3, feed_mm_s: 1, direction: px, start_mm: [1, 2]}\n", ".yaml",
     ("cut k5", "start_mm")),
    ("cuts: 3\n", ".yaml", ("cuts",)),
])
def test_a_bad_entry_is_one_line_naming_the_cut_and_the_key(tmp_path, text, suffix, names):
    with pytest.raises(RawDataError) as e:
        _parse(tmp_path, text, suffix)
    msg = str(e.value)
    assert "\n" not in msg and all(n in msg for n in names)


def test_the_command_says_in_one_line_when_the_study_has_no_plan(tmp_path, capsys):
    cuts = tmp_path / "cuts.yaml"
    cuts.write_text("- {id: a, depth_mm: 0.3, feed_mm_s: 1, direction: px, "
                    "start_mm: [700, 60, 199.7]}\n")
    assert main(["predict", str(tmp_path), str(cuts)]) == 1
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "model.yaml" in err and "Traceback" not in err
    bad = tmp_path / "bad.csv"
    bad.write_text("id,depth_mm,feed_mm_s,direction\nz9,-1,1,px\n")
    assert main(["predict", str(tmp_path), str(bad)]) == 1
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "cut z9" in err


@pytest.mark.pipeline
def test_the_study_cuts_predicted_as_the_plan_predicts_them(planned_run, tmp_path):
    """The study's own cuts through the command: the plan's study_cuts.csv row for row (the
    tiny study with its plan made, shared: conftest.planned_run)."""
    study = planned_run
    manifest = yaml.safe_load((study / "results/ingest/study.yaml").read_text())
    cuts = [{k: v for k, v in c.items() if k != "process"} for c in manifest["cuts"]][:4]
    (tmp_path / "cuts.yaml").write_text(yaml.safe_dump(cuts))
    out = tmp_path / "pred.csv"
    assert main(["predict", str(study), str(tmp_path / "cuts.yaml"), "--out", str(out)]) == 0
    got = pd.read_csv(out)
    assert list(got.columns) == list(PREDICT_COLUMNS)
    ref = pd.read_csv(study / "results/plan/study_cuts.csv").set_index("cut").loc[got["cut"]]
    for col in ("p_stable", "a_crit_mm", "a_crit_low_mm", "a_crit_high_mm", "force_N",
                "force_high_N", "deflection_normal_um", "deflection_normal_high_um",
                "waviness_um", "waviness_high_um"):
        assert got[col].to_numpy() == pytest.approx(ref[col].to_numpy(), rel=1e-5,
                                                    nan_ok=True), col  # 6 digits
    assert got["p_stable"].between(0, 1).all()
