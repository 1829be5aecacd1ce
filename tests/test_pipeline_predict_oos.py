"""Out of sample: cuts the study never made, predicted with `robomill predict` from the tiny
study's plan and then cut on the virtual cell as their own study (a configuration overlay with
those cuts in their own folder). A set spanning three speeds, both feed directions and depths
on both sides of each predicted boundary; the cell's chatter verdicts are read from that run's
files. No cut the nominal prediction calls stable may chatter (the plan's safe side, checked
strictly), and the nominal prediction should agree with at least 90 % of the judged cuts, with
both verdicts among them (the planner's target, not reached yet: expected to fail).

The cell that cuts them is the study's: the next run's configuration that the plan writes
pins where the study's impact test was made (``synth.process.reference_point_mm``), which the
tiny study leaves to the cell's default, the centre of the run's own cuts; without it the
cell's arm would be planted anew around these cuts. The same set is also run on a tiny study
whose arm follows the cell's richer law (``synth.process.robot_modes: eigen``), built and
planned for the purpose."""

import shutil
import sys

import numpy as np
import pandas as pd
import pytest
from conftest import NO_BOOK_PDF, REPO, run_snakemake

sys.path.insert(0, str(REPO / "benchmarks"))
from predict_then_cut import boundary_set, cut_on_cell  # noqa: E402

# minutes of simulation: `make plan-check` runs it, `make test` does not (docs/usage.md)
pytestmark = [pytest.mark.pipeline, pytest.mark.predict_cut]
REQUEST = f"plan={{request: {REPO / '.test' / 'plan.yaml'}}}"


@pytest.fixture(scope="module")
def outcomes(tiny_run, tmp_path_factory) -> pd.DataFrame:
    """The set predicted, cut on the cell as its own study and judged
    (``benchmarks/predict_then_cut.py``: three speeds, both feed directions, a cut at 0.5 and
    at 1.8 times each predicted critical depth): per judged cut its depth, the predicted
    critical depth and ``p_stable``, and the verdict (1 stable, 0 chatter)."""
    tmp_path = tmp_path_factory.mktemp("oos")
    study = tmp_path / "study"
    shutil.copytree(tiny_run, study, symlinks=True)
    proc = run_snakemake(study, "-j2", "plan", "--config", NO_BOOK_PDF, REQUEST)
    assert proc.returncode == 0, proc.stderr[-4000:]
    return _predicted_then_cut(study, tmp_path, REPO / ".test" / "config.yaml")


@pytest.fixture(scope="module")
def eigen_outcomes(tmp_path_factory) -> pd.DataFrame:
    """The same set on a tiny study whose arm follows the cell's richer law
    (``synth.process.robot_modes: eigen``: the modes of the joints' eigenproblem at every pose,
    shapes turning and mixing, where the planner moves the impact test's fixed shapes): the
    study built, planned, the set predicted, cut on the same arm and judged."""
    import yaml

    tmp_path = tmp_path_factory.mktemp("oos_eigen")
    config = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    config.setdefault("synth", {}).setdefault("process", {})["robot_modes"] = "eigen"
    cfg = tmp_path / "config_eigen.yaml"
    cfg.write_text(yaml.safe_dump(config))
    study = tmp_path / "study"
    study.mkdir()
    for args in (("all",), ("plan", REQUEST)):
        proc = run_snakemake(study, "-j2", args[0], "--config", NO_BOOK_PDF, *args[1:],
                             configfile=cfg)
        assert proc.returncode == 0, proc.stderr[-4000:]
    return _predicted_then_cut(study, tmp_path, cfg)


def _predicted_then_cut(study, work, config) -> pd.DataFrame:
    """``benchmarks/predict_then_cut.py``'s set on ``study``'s plan, cut by its cell
    (configuration ``config``) and judged: per judged cut its depth, the predicted critical
    depth and ``p_stable``, the verdict (1 stable, 0 chatter) and the cell's own state."""
    cuts, pred = boundary_set(study, work)
    stable = cut_on_cell(study, cuts, [config], study / "oos/run")
    judged = stable.dropna()
    return pd.DataFrame({"depth_mm": pred.loc[judged.index, "depth_mm"],
                         "a_crit_mm": pred.loc[judged.index, "a_crit_mm"],
                         "p_stable": pred.loc[judged.index, "p_stable"],
                         "stable": judged, "n_cuts": len(cuts),
                         **_cell_state(study / "oos/run", judged.index)})


def _cell_state(run, cuts) -> dict[str, list[float]]:
    """What the cell did, from its truth files (never seen by the planner or the judge): the
    share of tooth passes out of the cut and the tool's vibration about its mean path [µm
    rms, second half of the cut], to read a disagreement by."""
    from robomill.io import open_artefact

    out = {"teeth_out": [], "vibration_um_rms": []}
    for cut in cuts:
        truth = open_artefact(run / f"results/synthetic/truth/cuts/{cut}.nc")
        d = truth["deflection_m"].isel({"pass": 0}).to_numpy()
        d = d[d.shape[0] // 2:] - d[d.shape[0] // 2:].mean(axis=0)
        out["teeth_out"].append(float(truth["teeth_out"].isel({"pass": 0})))
        out["vibration_um_rms"].append(1e6 * float(np.sqrt(np.mean(np.sum(d**2, axis=1)))))
    return out


def test_no_cut_predicted_stable_chatters_on_the_cell(outcomes):
    """The side of the plan a machinist relies on: a cut the nominal prediction calls stable
    (predicted critical depth above its depth) never chatters on the cell; the set is judged
    (at least 80 % of its cuts) and holds both verdicts, so that the check can fail. `make
    plan-check` runs the same set on the default study and on examples/other_cell
    (`predict_then_cut.csv`)."""
    o = outcomes
    assert len(o) >= 0.8 * int(o["n_cuts"].iloc[0])
    assert 0 < o["stable"].sum() < len(o)          # both verdicts among the judged cuts
    unsafe = o[(o["a_crit_mm"] > o["depth_mm"]) & (o["stable"] < 0.5)]
    assert unsafe.empty, unsafe.to_string()


@pytest.mark.xfail(strict=False, reason=(
    "the out-of-sample target (90 % of verdicts predicted) is not reached: 9 of 12 on the tiny "
    "study (the planar model and, since 2026-12-07, the model with the axial force alike), "
    "every miss on the safe side (cuts at 1.8 times the predicted limit judged stable). "
    "At 12 000 rpm px the cell holds the cut at 3.5 µm with every tooth in (its edge forces; "
    "the model has none); at 20 000 rpm px it chatters at 69-74 Hz only from about 1.4 s on, "
    "after the study's 4 mm force record (0.8 s) has ended; at 20 000 rpm py it holds a "
    "15-26 µm motion with about a quarter of the tooth passes out whose force record shows no "
    "line and less than half its power off the spindle's harmonics. With the modal mass held "
    "at the impact test's value (before 2026-12-07) the set read 11 of 12 with one cut "
    "predicted stable that chattered, its limits 1.2-1.7 times the cell's own "
    "(benchmarks/modes_at_cuts.py). The assertion's table gives the cell's own state per cut "
    "over its whole simulated span, longer than the record"))
def test_nine_in_ten_verdicts_predicted_right(outcomes):
    """The out-of-sample target: the nominal prediction agrees with at least 90 % of the
    judged cuts' verdicts, both verdicts among them."""
    o = outcomes
    assert len(o) >= 0.8 * int(o["n_cuts"].iloc[0])
    assert 0 < o["stable"].sum() < len(o)
    predicted = o["a_crit_mm"] > o["depth_mm"]
    agree = predicted.to_numpy() == (o["stable"].to_numpy() >= 0.5)
    assert agree.mean() >= 0.9, o.assign(predicted_stable=predicted).to_string()


def test_on_an_arm_whose_modes_turn_the_set_is_predicted(eigen_outcomes):
    """Against a truth richer than the planner's transfer of the modes to a pose (the eigen
    law), the set holds both verdicts, no cut predicted stable chatters, and at least 90 % of
    the verdicts are predicted right (12 of 12 when written, 2026-12-07)."""
    o = eigen_outcomes
    assert len(o) >= 0.8 * int(o["n_cuts"].iloc[0])
    assert 0 < o["stable"].sum() < len(o)
    predicted = o["a_crit_mm"] > o["depth_mm"]
    unsafe = o[predicted & (o["stable"] < 0.5)]
    assert unsafe.empty, unsafe.to_string()
    agree = predicted.to_numpy() == (o["stable"].to_numpy() >= 0.5)
    assert agree.mean() >= 0.9, o.assign(predicted_stable=predicted).to_string()
