"""The axial force's regeneration: how far the planar stability model (the planner's and
chapter 4's) stands from the virtual cell's own onset of chatter, and which term of the cell
puts it there.

The cell's axial cutting force, F_a = K_ac a h per engaged tooth, carries the regenerative chip
h as the tangential and radial forces do, and drives every mode with an axial shape component
(the robot's modes along the tool axis). The planar model drops it: its modal forces are the
in-plane ones. With it, the chip's feedback is F = a W̄₃ Δ with the 3 × 2 mean directional
matrix

.. math:: \\bar W_3 = \\begin{pmatrix} \\bar W \\\\ \\frac{N K_{ac}}{2π}
          \\left(\\cos φ_{st} − \\cos φ_{ex},\\ \\sin φ_{ex} − \\sin φ_{st}\\right)\\end{pmatrix}

(the axial row: the average of K_ac (sin φ, cos φ) over the engaged arc, h = Δx sin φ + Δy
cos φ as in :class:`robomill.chatter.model.CuttingModel`), and the zero-order eigenvalue problem
[Altintas & Budak 1995] takes the oriented receptance G₂₃ W̄₃ (2 × 2) in place of W̄ G:
G₂₃ = Σ_r φ_r,xy φ_r,xyzᵀ / (k_r (1 − ρ² + 2jζ_r ρ)), the in-plane response to a force in
all three axes. Both are solved by the one zero-order routine
(:func:`robomill.chatter.lobes_zoa.zoa_envelope`) on the cell's own modes at each cut's middle
and its planted coefficients, beside the semi-discretization of the planar model
(``benchmarks/edge_switching.py``'s :func:`limits`).

``--sweep CUT:F1,F2,…`` also simulates the cell at those fractions of the planar
semi-discretization's limit, without its excitation and edge force (so that nothing but the
linear regeneration acts at the onset), with and without the axial force (K_ac = K_ae = 0):
per run the regenerative vibration's rms in the first and last eighth of the cut [µm], its
line and the share of deep tooth passages out of the cut.

    .venv/bin/python benchmarks/axial_regeneration.py --config OVERLAY... --cuts CUTS \\
        [--without-config-yaml] [--sweep CUT:0.6,0.62,0.7,0.8] [--out DIR]
    .venv/bin/python benchmarks/axial_regeneration.py --set STUDY --study-config FILE... \\
        [--factors 0.5,1.8] [--out DIR]

``--set``: what the planar and the axial form would score on the predict-then-cut set
(``benchmarks/predict_then_cut.py``'s layout on ``STUDY``'s request, its three speeds and two
feed directions), each form standing in for the planner with the cell's own modes and
coefficients (under the planted law the planner's modes at a cut agree with the cell's
within 0.1 % in frequency and 1 % in stiffness, ``benchmarks/modes_at_cuts.py``): the cuts at
``--factors`` times each form's zero-order limit, cut on the study's own cell (its
``--study-config`` files, in order, and its next run's experiment) and judged from their
files; per cut the limit, the verdict and whether the form got it right, and the tally.

Altintas & Budak 1995: Altintas, Y.; Budak, E. Analytical prediction of stability lobes in
milling. *CIRP Annals* **44**(1), 357–362, 1995.
"""

from __future__ import annotations

import argparse
import copy
from pathlib import Path

import numpy as np
import pandas as pd
from edge_switching import (
    add_cell_arguments,
    cell_of_arguments,
    limits,
    merged_config,
    no_edge,
    quiet,
    regenerative,
)
from predict_then_cut import positive_floats


def zoa_planar_and_axial_m(modes, frame, cut_model, Kac_N_m2, rpm) -> tuple[float, float]:
    """The zero-order critical depth [m] of the planar model and with the axial force's
    regeneration, on ``modes`` (each with ``f_hz, zeta, k_N_m, shape`` in the base frame), both
    by the planner's own routine (:func:`robomill.plan.lobes.batch_zoa_lobes`): the planar one
    on the in-plane shapes, the axial one on the shapes with their axial component and the
    cutting model with K_a = K_ac/K_t (the oriented receptance G₂₃ W̄₃,
    :mod:`robomill.chatter.model`)."""
    from dataclasses import replace

    from robomill.plan.lobes import batch_zoa_lobes, frequency_grid

    fn = np.array([m.f_hz for m in modes])
    ze = np.array([m.zeta for m in modes])
    kk = np.array([m.k_N_m for m in modes])
    sh = np.array([np.asarray(m.shape, float) @ frame for m in modes])
    f = frequency_grid(fn[None])
    rpm = np.atleast_1d(float(rpm))
    planar = batch_zoa_lobes(fn[None], ze, kk[None], sh[None, :, :2],
                             replace(cut_model, Ka=None), rpm, f_hz=f)
    axial = batch_zoa_lobes(fn[None], ze, kk[None], sh[None],
                            replace(cut_model, Ka=Kac_N_m2 / cut_model.Kt_N_m2), rpm, f_hz=f)
    return float(planar[0, 0]), float(axial[0, 0])


def cut_row(cell, cut) -> dict:
    """The cell's own limits at ``cut``'s middle [mm]: planar (zero-order, semi-discretization)
    and zero-order with the axial regeneration."""
    from robomill.chatter.model import CuttingModel
    from robomill.experiment import cut_process, feed_direction
    from robomill.forces.model import cut_frame, engagement_angles_rad
    from robomill.synth.structure import modes_at

    proc = cut_process(cut, cell.experiment)
    q = cell.joint_path_rad(cut, np.array([0.5 * float(cell.experiment["cut_length_mm"])]))[0]
    k = cell.cutting
    st, ex = engagement_angles_rad(proc["radial_immersion"], proc["milling"])
    model = CuttingModel(int(proc["flutes"]), k["Ktc_N_mm2"] * 1e6,
                         k["Krc_N_mm2"] / k["Ktc_N_mm2"], st, ex)
    planar, axial = zoa_planar_and_axial_m(modes_at(cell, q), cut_frame(feed_direction(cut)),
                                           model, k["Kac_N_mm2"] * 1e6, proc["spindle_rpm"])
    lim = limits(cell, cut, [0.0])
    return {"cut": cut.id, "depth_mm": float(cut.depth_mm),
            "zoa_planar_mm": 1e3 * planar, "sdm_planar_mm": lim["sdm_mm_g0.0"],
            "zoa_axial_mm": 1e3 * axial, "axial_over_planar": axial / planar}


def _at_depth(cut: dict, cid: str, depth_mm: float) -> dict:
    """``cut`` at another depth, its start lowered with it (the top face stays where it is)."""
    out = copy.deepcopy(cut)
    depth = round(float(depth_mm), 3)
    if out.get("start_mm") is not None:
        out["start_mm"][2] = float(out["start_mm"][2]) + float(cut["depth_mm"]) - depth
    return dict(out, id=cid, depth_mm=depth)


def sweep(config: dict, cut_id: str, fractions: list[float], sdm_mm: float) -> pd.DataFrame:
    """The cell's own cut at ``fractions`` of ``sdm_mm``, quiet and without edge force, with
    and without the axial force (module docstring)."""
    from robomill.io.synthetic_layout import synthetic_cuts
    from robomill.synth.cell import cell_from_config
    from robomill.synth.process import simulate_cut

    base = next(c for c in config["experiment"]["cuts"] if c["id"] == cut_id)
    rows = []
    for axial in (True, False):
        c = no_edge(quiet(copy.deepcopy(config)))
        if not axial:
            c["synth"]["cutting"].update(Kac_N_mm2=0.0, Kae_N_mm=0.0)
        c["experiment"]["cuts"] = [_at_depth(base, f"{cut_id}_f{i}", f * sdm_mm)
                                   for i, f in enumerate(fractions)]
        cell = cell_from_config(c)
        for f, cut in zip(fractions, synthetic_cuts(c), strict=True):
            sim = simulate_cut(cell, cut, c)
            delta, line = regenerative(sim)
            parts = np.array_split(delta, 8)
            rms = [1e6 * float(np.sqrt(np.mean(np.sum(p**2, axis=1)))) for p in parts]
            rows.append({"axial_force": axial, "fraction": f, "depth_mm": float(cut.depth_mm),
                         "first_eighth_um": rms[0], "last_eighth_um": rms[-1],
                         "line_hz": line, "teeth_out": float(sim.teeth_out)})
            print(pd.DataFrame([rows[-1]]).round(3).to_string(index=False, header=len(rows) == 1),
                  flush=True)
    return pd.DataFrame(rows)


def proxy_set(study: Path, configfiles: list[Path], factors: list[float], work: Path
              ) -> pd.DataFrame:
    """The planar and the axial form on the predict-then-cut set (module docstring)."""
    import yaml
    from predict_then_cut import (
        DIRECTIONS,
        SPEEDS_RPM,
        cut_on_cell,
        layout_origin_mm,
        placed_cut,
    )

    from robomill.io.synthetic_layout import impact_tcp_mm, synthetic_cuts
    from robomill.synth.cell import cell_from_config

    origin = layout_origin_mm(study)
    pairs = [(n, d) for n in SPEEDS_RPM for d in DIRECTIONS]
    probes = [placed_cut(origin, f"probe_{k}", n, 0.5, d, k) for k, (n, d) in enumerate(pairs)]
    config = merged_config([str(c) for c in configfiles], base=False)
    nxt = yaml.safe_load((study / "results/plan/next/config.yaml").read_text())
    config["experiment"].update({k: v for k, v in nxt["experiment"].items() if k != "cuts"})
    point = ((nxt.get("synth") or {}).get("process") or {}).get("reference_point_mm")
    config["synth"]["process"]["reference_point_mm"] = (point if point is not None
                                                        else impact_tcp_mm(config))
    config["experiment"]["cuts"] = probes
    cell = cell_from_config(config)
    lim = {c.id: cut_row(cell, c) for c in synthetic_cuts(config)}
    rows = []
    for form in ("planar", "axial"):
        cuts, limit = [], {}
        for k, (n, d) in enumerate(pairs):
            a = lim[f"probe_{k}"][f"zoa_{form}_mm"]
            for f in factors:
                cid = f"{form}_{int(n / 1000)}k_{d}_{round(100 * f)}pct"
                cuts.append(placed_cut(origin, cid, n, f * a, d, len(cuts)))
                limit[cid] = a
        stable = cut_on_cell(study, cuts, configfiles, work / form / "run")
        for c in cuts:
            v = float(stable.get(c["id"], np.nan))
            rows.append({"form": form, "cut": c["id"], "depth_mm": c["depth_mm"],
                         "limit_mm": limit[c["id"]], "stable": v,
                         "agree": bool((limit[c["id"]] > c["depth_mm"]) == (v >= 0.5)),
                         "unsafe": bool(limit[c["id"]] > c["depth_mm"] and v < 0.5),
                         "judged": bool(np.isfinite(v))})
    return pd.DataFrame(rows)


def _sweep_option(text: str) -> tuple[str, list[float]]:
    """``--sweep CUT:F1,F2,…`` as (cut, fractions) (one line on anything else)."""
    cut_id, sep, fractions = str(text).partition(":")
    if not sep or not cut_id:
        raise argparse.ArgumentTypeError(f"expected CUT:F1,F2,..., got {text!r}")
    return cut_id, positive_floats(fractions)


def main(argv: list[str] | None = None) -> pd.DataFrame:
    from robomill.io.synthetic_layout import synthetic_cuts

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_cell_arguments(ap)
    ap.add_argument("--sweep", type=_sweep_option,
                    help="CUT:F1,F2,... fractions of its planar SDM limit")
    ap.add_argument("--set", type=Path, help="a study whose plan was made (module docstring)")
    ap.add_argument("--study-config", nargs="+", type=Path, default=[],
                    help="with --set: the study's configuration files, in order")
    ap.add_argument("--factors", type=positive_floats, default=[0.5, 1.8], help="with --set")
    args = ap.parse_args(argv)
    pd.set_option("display.width", 200)
    if args.set:
        missing = [str(c) for c in args.study_config if not c.is_file()]
        if not args.study_config or missing:
            ap.error("--set needs --study-config: the study's configuration files"
                     + (f" (no such file: {', '.join(missing)})" if missing else ""))
        if not (args.set / "results/plan/next/config.yaml").is_file():
            ap.error(f"--set {args.set}: no results/plan/next/config.yaml (make its plan first: "
                     "snakemake -j2 plan)")
        out = Path(args.out)
        out.mkdir(parents=True, exist_ok=True)
        t = proxy_set(args.set.resolve(), [c.resolve() for c in args.study_config],
                      args.factors, out / "axial_set_work")
        t.to_csv(out / "axial_regeneration_set.csv", index=False)
        print(t.round(3).to_string(index=False))
        for form, g in t[t["judged"]].groupby("form", sort=False):
            print(f"{form}: {int(g['agree'].sum())} of {len(g)} judged cuts right, "
                  f"{int(g['unsafe'].sum())} predicted stable and judged chatter")
        return t
    out, config, cell = cell_of_arguments(args)
    table = pd.DataFrame([cut_row(cell, cut) for cut in synthetic_cuts(config)])
    print(table.round(3).to_string(index=False))
    table.to_csv(out / "axial_regeneration.csv", index=False)
    if args.sweep:
        cut_id, fractions = args.sweep
        if cut_id not in set(table["cut"]):
            ap.error(f"--sweep: no cut {cut_id!r} among {', '.join(table['cut'])}")
        sdm = float(table.set_index("cut").loc[cut_id, "sdm_planar_mm"])
        s = sweep(config, cut_id, fractions, sdm)
        s.to_csv(out / "axial_regeneration_sweep.csv", index=False)
    return table


if __name__ == "__main__":
    main()
