"""The planner's robot modes at each cut's pose against the virtual cell's own, and the linear
critical depth each gives, with and without the edge force's switching term.

The planner moves the impact test's robot modes to a cut's pose with its identified joint
stiffness (:func:`robomill.plan.tooltip.mode_scalings`: each mode's stiffness scaled by the
joints' tool-tip compliance along its shape, the modal mass held, so its frequency scales with
the square root of the stiffness), and :func:`robomill.plan.stability.member_modes` hands them
to the lobes. The cell moves its planted modes with the planted joint stiffness *and* the arm's
mass matrix at the pose (:mod:`robomill.synth.structure`): what the planner holds, the cell
moves. This benchmark puts the two side by side at each cut's middle and solves the linear
limit of both (semi-discretization [Insperger & Stépán 2004], 40 steps per tooth period) on
the planner's nominal cutting and edge coefficients, and a third set, ``Hm``: the planner's
modes (stiffness, damping, shape) at the cell's frequencies (what a mass model would add),
each with γ = 0 (no edge term) and γ = ½ (``benchmarks/edge_switching.py``'s
:func:`edge_switching_cut`). All three are planar (the modes' in-plane shapes, no axial force);
``Pa``: the planner's modes with their axial components and the axial row K_ac (the form of
``robomill predict``'s ``a_crit_mm``, here by semi-discretization), with the axial edge force
switching too at γ = ½. ``*_two_regime_mm``: the larger of the limits without and with the
term, the two-regime reading of the linearisation (a vibration the term alone destabilizes
saturates at the chip's size, |gᵀΔ| ~ c, where the switch saturates; one the plain
regenerative loop drives grows past it unless the term holds it at small amplitude).
Agreement with the cuts' judged verdicts is printed per column.

    .venv/bin/python benchmarks/modes_at_cuts.py STUDY --cuts CUTS \\
        --verdicts RUN/results/chatter/verdicts.csv --config CONFIG... [--hold-mass] [--out FILE]

``STUDY``: a study folder with its plan (as ``robomill predict`` reads it); ``--cuts`` and
``--verdicts``: a cut list and the run that cut it (without them: the study's own judged
cuts); ``--config``: the cell's configuration files, in order (``merged_config`` of
``benchmarks/edge_switching.py``; the cell's modes stay planted where the study's impact test
was made); ``--hold-mass``: the planner's modes with their modal mass held, as before it moved
it. The cell's truth enters here only to be compared with, never the planner.

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
import yaml

ROBOT_BAND_HZ = 500.0
"""The robot's modes lie below (the planted 20–72 Hz, the impact test's band); the spindle's
above. Below it the identified modes and the cell's are matched in order (the impact test
identifies the planted modes in order of frequency at its pose)."""

def main(argv=None) -> int:
    from edge_switching import merged_config
    from time_domain_verdicts import (
        edge_term_limit_mm,
        member_axial,
        member_modal_cut,
        study_verdicts,
    )

    from robomill.errors import RawDataError
    from robomill.experiment import feed_direction
    from robomill.forces.model import cut_frame
    from robomill.io.synthetic_layout import impact_tcp_mm, synthetic_cuts
    from robomill.plan.inputs import load_recorded
    from robomill.plan.make import verdict_conditioned
    from robomill.synth.cell import cell_from_config
    from robomill.synth.structure import modes_at

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("study", type=Path)
    ap.add_argument("--cuts", type=Path)
    ap.add_argument("--verdicts", type=Path)
    ap.add_argument("--config", nargs="+", type=Path, required=True)
    ap.add_argument("--hold-mass", action="store_true",
                    help="the planner's robot modes with their modal mass held at the impact "
                    "test's (f proportional to the square root of the stiffness), as before "
                    "the planner moved it")
    ap.add_argument("--planner-only", action="store_true",
                    help="only the planner's own model (the Pa columns: its axial form "
                    "without and with the edge term, and the two-regime limit), not the "
                    "planar comparisons with the cell's modes")
    ap.add_argument("--out", type=Path)
    args = ap.parse_args(argv)
    for name, path in (("--cuts", args.cuts), ("--verdicts", args.verdicts),
                       *(("--config", c) for c in args.config)):
        if path is not None and not path.is_file():
            ap.error(f"{name} {path}: no such file")
    if (args.cuts is None) != (args.verdicts is None):
        ap.error("--cuts and --verdicts go together (the run that cut them)")
    try:
        inputs = load_recorded(args.study)
        cuts, judged = study_verdicts(inputs, args.cuts, args.verdicts)
    except RawDataError as exc:
        print(f"modes_at_cuts: {exc}", file=sys.stderr)
        return 1
    measured = verdict_conditioned(inputs.measured, inputs.req, inputs.cell, inputs.study_cuts,
                                   inputs.experiment, inputs.stability)[0]
    config = merged_config([str(c) for c in args.config], base=False)
    config["synth"]["process"]["reference_point_mm"] = impact_tcp_mm(config)
    if args.cuts is not None:
        config["experiment"]["cuts"] = yaml.safe_load(args.cuts.read_text())
    cell = cell_from_config(config)
    truth_cuts = {c.id: c for c in synthetic_cuts(config)}
    rows = []
    for cut in cuts:
        mc = member_modal_cut(inputs, measured, cut, hold_mass=args.hold_mass)
        planner = [(float(f), float(z), float(k), (float(s[0]), float(s[1])))
                   for f, z, k, s in zip(mc.f_hz, mc.zeta, mc.k_N_m, mc.shape_xy, strict=True)]
        row = {"cut": cut.id, "depth_mm": float(cut.depth_mm), "verdict": judged[cut.id]}
        if not args.planner_only:
            tc = truth_cuts[cut.id]
            q = cell.joint_path_rad(tc, np.array([0.5 * float(cell.experiment["cut_length_mm"])
                                                  ]))[0]
            frame = cut_frame(feed_direction(tc))
            own = [(m.f_hz, m.zeta, m.k_N_m,
                    tuple(float(v) for v in (np.array(m.shape) @ frame)[:2]))
                   for m in modes_at(cell, q)]
            robot = [i for i, m in enumerate(planner) if m[0] < ROBOT_BAND_HZ]
            if len(robot) != sum(m[0] < ROBOT_BAND_HZ for m in own):
                print(f"modes_at_cuts: {cut.id}: {len(robot)} identified robot modes against "
                      f"the cell's {sum(m[0] < ROBOT_BAND_HZ for m in own)}: left out",
                      file=sys.stderr)
                continue
            hybrid = [(own[i][0], *m[1:]) if i in robot else m for i, m in enumerate(planner)]
            row.update({
                "f1_planner_hz": planner[0][0], "f1_cell_hz": own[0][0],
                "f_ratio_median": float(np.median([planner[i][0] / own[i][0] for i in robot])),
                "k_ratio_median": float(np.median([planner[i][2] / own[i][2] for i in robot]))})
            for name, modes in (("Pm", planner), ("Hm", hybrid), ("Cm", own)):
                for g in (0.0, 0.5):
                    row[f"{name}_g{g:g}_mm"] = edge_term_limit_mm(mc, g, modes)
            row["Pm_two_regime_mm"] = two_regime_mm(row["Pm_g0_mm"], row["Pm_g0.5_mm"])
        axial = member_axial(inputs, measured, cut, hold_mass=args.hold_mass)
        for g in (0.0, 0.5):
            row[f"Pa_g{g:g}_mm"] = edge_term_limit_mm(mc, g, planner, axial=axial)
        row["Pa_two_regime_mm"] = two_regime_mm(row["Pa_g0_mm"], row["Pa_g0.5_mm"])
        rows.append(row)
        print(pd.DataFrame([row]).round(3).to_string(index=False, header=len(rows) == 1),
              flush=True)
    t = pd.DataFrame(rows)
    if args.out is not None:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        t.to_csv(args.out, index=False)
    for col in [c for c in t.columns if c.endswith("_mm") and c != "depth_mm"]:
        n_agree, n_unsafe = tally(t, col)
        print(f"{col}: {n_agree} of {len(t)} agree, {n_unsafe} predicted stable judged chatter")
    return 0


def two_regime_mm(plain_mm: float, edge_mm: float) -> float:
    """The two-regime limit (module docstring): chatter needs both the small-amplitude loop
    (with the edge term) and the large-amplitude one (without it, the switch saturated)
    unstable, so the larger of the two critical depths."""
    return max(plain_mm, edge_mm)


def tally(t: pd.DataFrame, col: str) -> tuple[int, int]:
    """(cuts whose verdict the limit ``col`` predicts, cuts it predicts stable that were judged
    chatter) over ``t`` (columns ``depth_mm``, ``verdict`` stable/chatter and ``col``)."""
    pred = np.where(t[col] > t["depth_mm"], "stable", "chatter")
    return (int((pred == t["verdict"]).sum()),
            int(((pred == "stable") & (t["verdict"] == "chatter")).sum()))


if __name__ == "__main__":
    raise SystemExit(main())
