"""The stability model learned from observed verdicts (robomill.plan.conditioning,
robomill.plan.stability): on a planted one-mode structure whose true limit is computed here in
closed form, a stable cut below and a chattering cut above the limit narrow the critical-depth
interval at their speed and keep the truth inside, and move p_stable the right way; verdicts
no member can agree with change no weight and are named in one line."""

import io

import numpy as np
import pandas as pd
import pytest
import yaml
from scipy.optimize import brentq

from robomill.kinematics import robot_from_mapping
from robomill.plan.conditioning import evidence_values, study_evidence
from robomill.plan.evidence import identified_cuts, in_sample
from robomill.plan.measured import Measured
from robomill.plan.poses import cut_frames
from robomill.plan.predict import Cell, critical_depth_m
from robomill.plan.request import parse_request
from robomill.plan.stability import p_stable, verdict_weights

FN_HZ, ZETA, K_N_M = 40.0, 0.04, 1.0e6           # the planted mode, along the wall normal
KTC, KRC = 800.0, 240.0                           # N/mm²
FLUTES = 2
SPEED_RPM = 2000.0
ERROR = 0.05


def true_limit_m(n_rpm: float) -> float:
    """The planted structure's critical depth at ``n_rpm`` in a slot, by hand: one mode along
    the wall normal y; the average directional factor of a full slot α_yy = −π K_r, so the
    regenerative force is F_y = −K_f a (y − y_T) with K_f = N K_t K_r / 4 = N K_rc / 4, and
    the one-degree-of-freedom limit a = −1 / (2 K_f Re G(ω_c)) [Altintas 2012, ch. 4] at the
    chatter frequencies ω_c > ω_n whose phase ψ = arg G meets ω_c T = 3π + 2ψ + 2πj
    (T = 60/(N n)); the lowest over the lobes j."""
    kf = FLUTES * KRC * 1e6 / 4
    T = 60.0 / (FLUTES * n_rpm)
    wn = 2 * np.pi * FN_HZ

    def G(w):
        r = w / wn
        return 1.0 / (K_N_M * (1 - r**2 + 2j * ZETA * r))

    best = np.inf
    for j in range(60):
        def g(w, j=j):
            return w * T - (3 * np.pi + 2 * np.angle(G(w))) - 2 * np.pi * j
        lo, hi = wn * (1 + 1e-9), wn * 50
        if g(lo) >= 0 or g(hi) <= 0:
            continue
        w = brentq(g, lo, hi, xtol=1e-13)
        best = min(best, -1.0 / (2 * kf * G(w).real))
    return best


@pytest.fixture(scope="module")
def planted():
    cfg = yaml.safe_load(open("config.yaml"))["cell"]
    cell = Cell(robot_from_mapping(cfg["robot"]), np.asarray(cfg["tool_rotation"], float),
                np.deg2rad(cfg["q_home_deg"]), np.array([650.0, 0.0, 200.0]))
    frames = cut_frames(np.array([90.0]))                   # a py cut: feed y, normal -x
    shape = frames[0][:, 1]
    modes = pd.DataFrame({"f_n_hz": [FN_HZ], "zeta": [ZETA], "k_modal_N_m": [K_N_M],
                          "shape_x": [shape[0]], "shape_y": [shape[1]], "shape_z": [shape[2]]})
    for name, rel in {"f_n_hz": 0.01, "zeta": 0.3, "k_modal_N_m": 0.3}.items():  # wide prior
        modes[f"{name}_low"] = modes[name] * (1 - rel)
        modes[f"{name}_high"] = modes[name] * (1 + rel)
    names = ["Ktc", "Krc", "Kac", "Kte", "Kre", "Kae"]
    vals = np.array([KTC, KRC, 200.0, 25.0, 30.0, 6.0])
    coeffs = pd.DataFrame({"name": names, "value": vals, "ci_low": vals * 0.85,
                           "ci_high": vals * 1.15})
    req = parse_request({"kind": "plan", "operation": {"length_mm": 20, "directions": ["py"]},
                         "tool": {"diameter_mm": 6, "flutes": FLUTES},
                         "placement": {"points_mm": [[650, 0, 200]]},
                         "spindle_rpm": {"min": 1200, "max": 2900, "n": 35},
                         "depth_mm": [1.0], "feed_mm_s": [1],
                         "stability": {"members": 96, "verdict_error": ERROR}})
    m = Measured(modes=modes, coefficients=coeffs)
    q = np.asarray(cell.q_seed_rad, float)[None]             # unused without joint stiffness
    return cell, req, m, q, frames


def depth(m, planted, rpm, **kw):
    cell, req, _, q, frames = planted
    return critical_depth_m(m, cell, req, q, frames, np.atleast_1d(rpm), **kw)


def evidence(planted, cuts):
    """The weights from ``cuts`` ``[(cut, verdict, depth_m)]``, all at SPEED_RPM and the
    pose."""
    _, _, m, _, _ = planted
    a = depth(m, planted, SPEED_RPM, members=True)
    rows = [{"cut": c, "verdict": v, "spindle_rpm": SPEED_RPM, "depth_mm": d * 1e3}
            for c, v, d in cuts]
    mem = np.repeat(a["members"][:, 0, :], len(rows), axis=1)
    return study_evidence(rows, mem, 0.95, ERROR, "verdicts.csv")


def with_evidence(m, ev):
    return Measured(modes=m.modes, coefficients=m.coefficients, stability_evidence=ev)


def test_the_planner_nominal_is_the_closed_form_limit(planted):
    a_true = true_limit_m(SPEED_RPM)
    a = depth(planted[2], planted, SPEED_RPM)
    assert np.isfinite(a_true)
    assert a["nominal"][0, 0] == pytest.approx(a_true, rel=2e-3)
    assert a["low"][0, 0] < 0.75 * a_true and a["high"][0, 0] > 1.3 * a_true   # a wide prior


def test_a_bracket_narrows_the_interval_keeps_the_truth_and_moves_p_stable(planted):
    _, req, m, _, _ = planted
    a_true = true_limit_m(SPEED_RPM)
    d_stable, d_chatter = 0.85 * a_true, 1.2 * a_true
    ev = evidence(planted, [("s1", "stable", d_stable), ("s2", "chatter", d_chatter),
                            ("s3", "undetermined", 3 * a_true)])
    assert ev.table["used"].tolist() == [True, True, False]
    assert ev.table["prior_admits"].iloc[:2].tolist() == [True, True]
    assert 1 < ev.effective_members < len(ev.weights)
    prior = depth(m, planted, SPEED_RPM, members=True)
    here = depth(with_evidence(m, ev), planted, SPEED_RPM, members=True)
    lo, hi = here["low"][0, 0], here["high"][0, 0]
    assert lo <= a_true <= hi
    assert hi - lo < 0.7 * (prior["high"][0, 0] - prior["low"][0, 0])
    # p_stable: up below the stable cut's depth, down above the chattering cut's
    for d, up in ((d_stable, True), (d_chatter, False)):
        p0 = float(p_stable(prior["members"][:, 0, 0], prior["weights"], d))
        p1 = float(p_stable(here["members"][:, 0, 0], here["weights"], d))
        assert (p1 > p0) if up else (p1 < p0)
    assert ev.table["p_stable"].iloc[0] > 0.8 and ev.table["p_stable"].iloc[1] < 0.2
    # at every speed the truth stays inside the conditioned interval
    post = depth(with_evidence(m, ev), planted, req.spindle_rpm)
    truth = np.array([true_limit_m(n) for n in req.spindle_rpm])
    assert np.all(post["low"][0] <= truth * (1 + 3e-3))
    assert np.all(truth * (1 - 3e-3) <= post["high"][0])


def test_contradicting_verdicts_change_no_weight_and_are_named(planted):
    _, _, m, _, _ = planted
    prior = depth(m, planted, SPEED_RPM)
    ev = evidence(planted, [("deep", "stable", 2.0 * prior["high"][0, 0])])
    assert ev.table["prior_admits"].tolist() == [False]
    assert ev.effective_members == pytest.approx(len(ev.weights))
    post = depth(with_evidence(m, ev), planted, SPEED_RPM)
    for key in ("nominal", "low", "high"):
        assert post[key][0, 0] == prior[key][0, 0]
    from robomill.plan.conditioning import contradiction_note

    note = contradiction_note(ev.table)
    assert "\n" not in note and "deep" in note and "outside the prior interval" in note


def test_verdict_weights_by_hand():
    # members 1 and 2 mm deep; a stable verdict at 1.5 mm: member 1 disagrees
    a = np.array([[1.0], [2.0]])
    w = verdict_weights(a, np.array([1.5]), np.array([True]), 0.1)
    assert w == pytest.approx([0.1 / 1.0, 0.9 / 1.0])
    # and a chatter verdict at 1.8 mm: member 2 disagrees there: both now equally likely
    a2 = np.array([[1.0, 1.0], [2.0, 2.0]])
    w = verdict_weights(a2, np.array([1.5, 1.8]), np.array([True, False]), 0.1)
    assert w == pytest.approx([0.5, 0.5])
    assert p_stable(np.array([1.0, 2.0]), np.array([0.1, 0.9]), 1.5) == pytest.approx(0.9)


def test_evidence_cuts_are_in_sample_and_counted(planted):
    a_true = true_limit_m(SPEED_RPM)
    ev = evidence(planted, [("plan_01", "stable", 0.85 * a_true),
                            ("plan_02", "chatter", 1.2 * a_true),
                            ("plan_03", "undetermined", a_true)])
    table = pd.read_csv(io.StringIO(ev.table.to_csv(index=False)))  # as read back
    ident = identified_cuts(["s1"], table)
    assert ident == {"s1", "plan_01", "plan_02"}
    assert in_sample(["s1", "plan_01", "plan_03", "plan_04"], ident).tolist() == [
        True, True, False, False]
    attrs = {"stability_members": len(ev.weights),
             "stability_members_kept": round(ev.effective_members),
             "stability_verdict_error": ERROR}
    v = evidence_values(table, attrs)
    assert (v["n_used"], v["n_stable"], v["n_chatter"], v["n_left_out"]) == (2, 1, 1, 1)
    assert v["evidence_case"] == "conditioned" and v["n_contradicting"] == 0
    bad = evidence(planted, [("deep", "stable", 5 * a_true)])
    v = evidence_values(bad.table, attrs)
    assert v["evidence_case"] == "contradicted" and v["worst"].startswith("deep stable at")
    prior_high = bad.table["a_crit_high_mm"].iloc[0]
    assert v["model_error_factor"] == pytest.approx(5 * a_true * 1e3 / prior_high)


def test_chapter_states_the_update_or_the_contradiction(planted):
    from pathlib import Path

    from robomill.pipeline.prose import Prose, load_templates

    templates = load_templates("ch7", Path("src/robomill/data/templates/ch7.yaml"))
    a_true = true_limit_m(SPEED_RPM)
    ok = evidence(planted, [("s1", "stable", 0.85 * a_true), ("s2", "chatter", 1.2 * a_true)])
    attrs = {"stability_members": len(ok.weights),
             "stability_members_kept": round(ok.effective_members),
             "stability_verdict_error": ERROR}
    text = Prose(templates, evidence_values(ok.table, attrs))("stability_evidence")
    assert f"count as {round(ok.effective_members)} equal ones" in text
    assert "1 stable, 1 chatter" in text and "wrong with probability 5 %" in text
    bad = evidence(planted, [("deep", "stable", 5 * a_true)])
    text = Prose(templates, evidence_values(bad.table, attrs))("stability_evidence")
    assert "**1 of the 1 verdicts lie outside the prior interval" in text
    assert "deep stable at" in text
