"""Whether the planner's own identified model, run in the time domain with the chip's two
nonlinearities (a tooth whose chip vanishes leaves the cut; the edge force acts only while the
tooth cuts) and with the structure's own excitation, predicts the verdicts that its linear
regenerative model misses.

The linear model (:mod:`robomill.plan.stability`, zero-order lobes) keeps every tooth in the
cut and has no edge force: its critical depth is where a small vibration starts to grow.
A study judges recordings, not eigenvalues: a vibration the edge forces hold small, or one
the arm's own excitation sets off below the linear limit at a thin chip, is judged by its
lines. This benchmark takes member 0 (the nominal) of the planner's model at each cut's own
pose (the impact test's robot modes moved to the pose, the tool modes' prior nominal, the
identified cutting and edge coefficients, all from the study's results folder as
``robomill predict`` reads them; nothing from a virtual cell's truth), simulates the cut on
it for each excitation level of ``--excitation-N``
(:func:`robomill.chatter.modal_timedomain.simulate_modal_cut`: the chip and force law of
Altintas 2012 eq. 2.25 with the tooth leaving the cut, and a white force at the tool of that
standard deviation per in-plane axis, 0–1 kHz) and judges the simulated force with the
study's judge (:func:`robomill.chatter.verdicts.judge`, with the verdict settings of the
study's ``--config`` files, else the schema's),
beside the linear prediction and the study's own verdict. ``--members`` adds, per level, the
share of the members (weighted by the study's verdicts, as the plan weights them) whose
simulated cut is judged stable.

The excitation level is not identified here: the benchmark asks whether any level makes the
model's form agree, which a model that learns it (from air passes, or as a member parameter
weighted by the verdicts) would then have to find.

    .venv/bin/python benchmarks/time_domain_verdicts.py STUDY --excitation-N 0,3,6 \\
        [--cuts CUTS --verdicts VERDICTS] [--members] [--request R] [--out FILE]

``STUDY``: a study folder (or its ``results``) with its plan, as ``robomill predict`` reads
it (``--request``: another request, as ``robomill predict --request``); without ``--cuts``
the study's own judged cuts (in sample); with ``--cuts`` (a cut list in
``robomill predict``'s format) and ``--verdicts`` (``results/chatter/verdicts.csv`` of the run
that cut them) the cuts out of sample. Prints one row per cut and the agreement of each
predictor; ``--out`` writes the table as CSV.

``--edge-term`` adds the nominal member's linear limit with the edge force's switching term
(``benchmarks/edge_switching.py``), solved by semi-discretization.

Altintas 2012: Altintas, Y. *Manufacturing Automation: Metal Cutting Mechanics, Machine Tool
Vibrations, and CNC Design*, 2nd ed. Cambridge University Press, 2012.
Insperger & Stépán 2004: Insperger, T.; Stépán, G. Updated semi-discretization method for
periodic delay-differential equations with discrete delay. *International Journal for
Numerical Methods in Engineering* **61**(1), 117–141, 2004.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np
import pandas as pd

DECIMATED_HZ = 10000.0
"""The simulated force is low-passed and decimated to about this rate before it is judged
(the judge's band lies far below the simulation's rate)."""


def _member_at_cut(inputs, measured, cut, member: int, hold_mass: bool):
    """Member ``member`` of the planner's model at ``cut``'s own pose: the one-cut candidate,
    the members, and the member's modes there (:func:`robomill.plan.stability.member_modes`:
    f, ζ, k ``(M,)`` and shapes ``(M, 3)`` in the cut frame; ``hold_mass``: the robot modes'
    modal mass held at the impact test's, as the planner did before it moved it)."""
    from robomill.plan.candidate import study_candidate
    from robomill.plan.poses import cut_frames
    from robomill.plan.predict import solve_request
    from robomill.plan.stability import draw_members, member_modes
    from robomill.plan.tooltip import mode_scalings

    one = study_candidate(cut, inputs.experiment).grid(inputs.req)
    poses = solve_request(one, inputs.cell)
    q = poses.q_mid_rad.reshape(-1, poses.q_mid_rad.shape[-1])[:1]
    frame = cut_frames(np.asarray(one.direction_deg, float))[:1]
    mem = draw_members(measured, one.stability)
    sc = mode_scalings(measured, inputs.cell, q, mem.f_hz[0] < one.robot_mode_max_hz,
                       mem.shapes)
    if hold_mass:
        sc.pop("mass", None)
    fn, z, k, shape = member_modes(mem, sc, frame, slice(member, member + 1))
    return one, mem, (fn[0, 0], z[0, 0], k[0, 0], shape[0])


def member_modal_cut(inputs, measured, cut, member: int = 0, *, hold_mass: bool = False):
    """Member ``member`` (0: the nominal) of the planner's model at ``cut``'s own pose as a
    :class:`~robomill.chatter.modal_timedomain.ModalCut` (cut frame: feed, normal): its modes
    at the pose (:func:`_member_at_cut`, the modes the linear model solves, their in-plane
    part: the time-domain model has no axial force on the modes, the linear one has since it
    took K_ac's row, so the two differ by that term, :func:`member_axial`), its K_t and K_r,
    the identified axial and edge coefficients."""
    from robomill.chatter.modal_timedomain import ModalCut
    from robomill.plan.measured import coefficient_bounds
    from robomill.plan.predict import engagement

    e = int(member)
    one, mem, (fn, z, k, shape) = _member_at_cut(inputs, measured, cut, e, hold_mass)
    cc = coefficient_bounds(measured.coefficients)["nominal"]
    rpm, teeth = float(one.spindle_rpm[0]), int(one.flutes)
    fz_m = float(one.feed_mm_s[0]) / (teeth * rpm / 60.0) * 1e-3
    ent, ext = engagement(one)
    kt = float(mem.kt_N_mm2[e])
    return ModalCut(fn, z, k, shape[:, :2], rpm, teeth, ent, ext, fz_m,
                    float(one.depth_mm[0]) * 1e-3, kt * 1e6, kt * float(mem.kr[e]) * 1e6,
                    cc.Kac * 1e6, cc.Kte * 1e3, cc.Kre * 1e3, cc.Kae * 1e3)


def member_axial(inputs, measured, cut, member: int = 0, *, hold_mass: bool = False):
    """What the planner's linear model adds to :func:`member_modal_cut`'s modes: their
    components along the tool axis ``(M,)`` and the member's K_ac/K_tc (None: K_ac not
    identified, the planar model)."""
    e = int(member)
    _, mem, (_, _, _, shape) = _member_at_cut(inputs, measured, cut, e, hold_mass)
    return shape[:, 2], (None if mem.ka is None else float(mem.ka[e]))


def edge_term_limit_mm(mc, gain: float = 0.5, modes=None, *, axial=None) -> float:
    """The linear critical depth [mm] of ``mc``'s modes (or ``modes``,
    ``[(f, ζ, k, (sx, sy))]`` in the cut frame) and coefficients with the edge force's
    switching term (gain γ, ``benchmarks/edge_switching.py``'s :func:`edge_switching_cut`; 0:
    without it), solved by semi-discretization [Insperger & Stépán 2004]. ``axial``: the
    modes' axial components and K_ac/K_tc (:func:`member_axial`): the
    planner's axial row, and the axial edge force's switching with it."""
    from edge_switching import DEPTH_MAX_M, SDM_STEPS, edge_switching_cut

    from robomill.chatter.lobes_sdm import critical_depth
    from robomill.chatter.model import ModeXY, tool_from_modes

    if modes is None:
        modes = [(float(f), float(z), float(k), (float(sx), float(sy)))
                 for f, z, k, (sx, sy) in zip(mc.f_hz, mc.zeta, mc.k_N_m, mc.shape_xy,
                                              strict=True)]
    ka = None
    if axial is not None and axial[1] is not None:
        modes = [(f, z, k, (*s, float(sz))) for (f, z, k, s), sz in zip(modes, axial[0],
                                                                       strict=True)]
        ka = axial[1]
    tool = tool_from_modes([ModeXY(*m) for m in modes])
    model = edge_switching_cut(int(mc.teeth), mc.Ktc_N_m2, mc.Krc_N_m2 / mc.Ktc_N_m2,
                               mc.entry_rad, mc.exit_rad, mc.Kte_N_m, mc.Kre_N_m,
                               mc.feed_per_tooth_m, float(gain), Ka=ka, Kae_N_m=mc.Kae_N_m)
    a, _ = critical_depth(tool, model, mc.spindle_rpm, depth_max_m=DEPTH_MAX_M, m=SDM_STEPS,
                          rtol=1e-3)
    return 1e3 * float(a)


def judged_run(mc, settings, *, excitation_N: float, duration_s: float,
               steps_per_tooth: int = 32) -> dict:
    """Simulate ``mc`` and judge its force as a study judges a dynamometer record: the
    verdict, its line, and over the run's last third the rms of the regenerative
    displacement Δ and the share of the teeth deep in the cut whose chip vanished."""
    from scipy.signal import decimate

    from robomill.chatter.modal_timedomain import simulate_modal_cut
    from robomill.chatter.verdicts import judge

    rec = simulate_modal_cut(mc, duration_s=duration_s, steps_per_tooth=steps_per_tooth,
                             excitation_N=excitation_N)
    fs = float(rec["fs_hz"])
    q = max(int(fs // DECIMATED_HZ), 1)
    F = decimate(rec["force_N"], q, axis=0, zero_phase=True) if q > 1 else rec["force_N"]
    v = judge(F, fs / q, settings, spindle_rpm=mc.spindle_rpm, flutes=mc.teeth)
    n = len(rec["delta_m"])
    D = rec["delta_m"][2 * n // 3:]
    deep = rec["teeth_deep"][2 * n // 3:].sum()
    return {"verdict": v.verdict, "line_hz": v.chatter_hz,
            "regen_um": float(np.sqrt(np.mean(np.sum((D - D.mean(0)) ** 2, 1)))) * 1e6,
            "teeth_out": float(rec["teeth_out"][2 * n // 3:].sum() / deep) if deep else np.nan}


def study_verdicts(inputs, cuts_path: Path | None, verdicts_path: Path | None):
    """The cuts to predict and their judged verdicts (``stable``/``chatter``; a cut is
    chatter when any of its records is, :func:`robomill.plan.evidence.verdict_stability`)."""
    from robomill.io.cutlist import parse_cuts, read_cut_entries
    from robomill.plan.evidence import read_verdicts, verdict_stability

    if cuts_path is None:
        stable = inputs.stability
        cuts = inputs.study_cuts
    else:
        cuts = parse_cuts(cuts_path, read_cut_entries(cuts_path))
        stable = (verdict_stability(read_verdicts(verdicts_path)) if verdicts_path
                  else pd.Series(dtype=float))
    judged = {c: ("stable" if v >= 0.5 else "chatter") for c, v in stable.items() if v == v}
    return [c for c in cuts if c.id in judged], judged


def main(argv=None) -> int:
    from robomill.chatter.verdicts import VerdictSettings
    from robomill.errors import RawDataError
    from robomill.plan.compare import predict_study_cut
    from robomill.plan.inputs import load_recorded
    from robomill.plan.make import verdict_conditioned
    from robomill.plan.predict import member_weights
    from robomill.plan.request import PlanRequestError

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("study", type=Path)
    ap.add_argument("--cuts", type=Path)
    ap.add_argument("--verdicts", type=Path)
    ap.add_argument("--request", type=Path,
                    help="another planning request (as robomill predict --request), e.g. a "
                    "tool-mode prior from a tap test")
    ap.add_argument("--excitation-N", default="0",
                    help="comma-separated white-force levels at the tool [N rms per axis]")
    ap.add_argument("--duration-s", type=float, default=1.0)
    ap.add_argument("--members", action="store_true")
    ap.add_argument("--edge-term", action="store_true",
                    help="also the nominal member's linear limit with the edge force's "
                    "switching term (semi-discretization, gain 1/2)")
    ap.add_argument("--config", nargs="*", type=Path, default=[],
                    help="the study's configuration files, in order: its judge's settings "
                    "(chatter.verdicts; default: the schema's)")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args(argv)
    try:
        levels = [float(x) for x in args.excitation_N.split(",")]
    except ValueError:
        ap.error(f"--excitation-N {args.excitation_N}: expected comma-separated numbers [N]")
    if args.cuts is not None and args.verdicts is None:
        ap.error("--cuts needs --verdicts (the run that cut them: results/chatter/verdicts.csv)")
    for name, path in (("--cuts", args.cuts), ("--verdicts", args.verdicts)):
        if path is not None and not path.is_file():
            ap.error(f"{name} {path}: no such file")
    try:
        inputs = load_recorded(args.study, request=args.request)
        cuts, judged = study_verdicts(inputs, args.cuts, args.verdicts)
    except (RawDataError, PlanRequestError) as exc:
        print(f"time_domain_verdicts: {exc}", file=sys.stderr)
        return 1
    measured = verdict_conditioned(inputs.measured, inputs.req, inputs.cell, inputs.study_cuts,
                                   inputs.experiment, inputs.stability)[0]
    missing = [str(c) for c in args.config if not c.is_file()]
    if missing:
        ap.error(f"--config: no such file: {', '.join(missing)}")
    from edge_switching import merged_config

    settings = VerdictSettings.from_mapping(
        merged_config([str(c) for c in args.config], base=False)["chatter"]["verdicts"])
    weights = member_weights(measured, int(inputs.req.stability.members))
    rows = []
    for cut in cuts:
        p = predict_study_cut(cut, inputs.experiment, inputs.req, measured, inputs.cell,
                              inputs.reach)
        if not p["reachable"]:  # no posture to move the modes to: nothing to simulate
            print(f"time_domain_verdicts: {cut.id}: not reachable, left out", file=sys.stderr)
            continue
        mc = member_modal_cut(inputs, measured, cut)
        row = {"cut": cut.id, "depth_mm": p["depth_mm"],
               "feed_per_tooth_um": mc.feed_per_tooth_m * 1e6, "verdict": judged.get(cut.id, ""),
               "a_crit_mm": p["a_crit_mm"], "p_stable": p["p_stable"],
               "linear": "stable" if p["a_crit_mm"] > p["depth_mm"] else "chatter"}
        if args.edge_term:
            row["a_edge_mm"] = edge_term_limit_mm(mc)
            row["edge_term"] = "stable" if row["a_edge_mm"] > p["depth_mm"] else "chatter"
        for s in levels:
            r = judged_run(mc, settings, excitation_N=s, duration_s=args.duration_s)
            row.update({f"td_{s:g}N": r["verdict"], f"td_{s:g}N_line_hz": r["line_hz"],
                        f"td_{s:g}N_regen_um": r["regen_um"],
                        f"td_{s:g}N_teeth_out": r["teeth_out"]})
            if args.members:
                ok = [judged_run(member_modal_cut(inputs, measured, cut, e), settings,
                                 excitation_N=s, duration_s=args.duration_s)["verdict"]
                      == "stable" for e in range(len(weights))]
                row[f"p_stable_td_{s:g}N"] = float(np.sum(weights * np.asarray(ok, float)))
        rows.append(row)
    t = pd.DataFrame(rows)
    with pd.option_context("display.width", 250, "display.max_columns", 60):
        print(t.round(3).to_string(index=False))
    j = t[t["verdict"].isin(["stable", "chatter"])]
    cols = ["linear"] + (["edge_term"] if args.edge_term else []) + [f"td_{s:g}N" for s in levels]
    for col in cols:
        unsafe = int(((j[col] == "stable") & (j["verdict"] == "chatter")).sum())
        print(f"{col}: {int((j[col] == j['verdict']).sum())} of {len(j)} judged cuts agree, "
              f"{unsafe} predicted stable judged chatter")
    if args.members:
        for s in levels:
            pred = np.where(j[f"p_stable_td_{s:g}N"] >= 0.5, "stable", "chatter")
            print(f"members at {s:g} N (p >= 0.5 stable): {int((pred == j['verdict']).sum())} "
                  f"of {len(j)} agree")
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        t.to_csv(args.out, index=False)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
