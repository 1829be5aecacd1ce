"""Two stability limits of the identified modes on a study's own cuts, and what the cell said:
why the planner's stability model (:mod:`robomill.plan.stability`) is the regenerative model
alone and the delay-free mode-coupling depth only chapter 4's diagnostic (the planner once
took the lower of the two, and called most of the default study's cuts unstable, which its
files call stable).

The two limits of the identified tool-tip modes and the calibrated coefficients: the
zero-order lobes at the cut's
spindle speed (regenerative chip, d(t) − d(t − τ); Altintas & Budak 1995) and the delay-free
mode-coupling depth (the oriented cutting stiffness acting on d(t) itself; Tlusty's mode
coupling, the thesis' §3.3). This script evaluates both with the planner's own routines
(:func:`robomill.plan.lobes.batch_zoa_lobes`, :func:`robomill.chatter.coupling.coupling_depth`)
on a finished study's artefacts — ``results/modal/modes.csv``,
``results/forces/cutting_coefficients.csv``, ``results/ingest/cuts.csv``,
``results/chatter/verdicts.csv`` — for each cut's feed direction (shapes turned into its cut
frame; the named directions px, py, my, mx of the thesis' design table), at the modes of the
impact test's pose (the planner also moves them with the pose).
Writes ``<out>/coupling_vs_lobes.csv`` (``cut, direction, depth_mm, spindle_rpm,
a_zoa_mm, a_coupling_mm, binding, verdict``) and prints how many cuts each limit calls
unstable against the verdicts.

    .venv/bin/python benchmarks/coupling_vs_lobes.py --study . --out results/benchmarks

Altintas & Budak 1995: Altintas, Y.; Budak, E. Analytical prediction of stability lobes in
milling. *CIRP Annals* 44(1), 357–362, 1995.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd

from robomill.chatter.coupling import coupling_depth
from robomill.chatter.model import CuttingModel
from robomill.experiment import DIRECTION_VECTORS
from robomill.forces.model import cut_frame, engagement_angles_rad
from robomill.plan.lobes import batch_zoa_lobes
from robomill.plan.tooltip import modes_arrays


def limits(study: Path, radial_immersion: float, milling: str) -> pd.DataFrame:
    """One row per cut of the study with a force verdict (module docstring)."""
    res = study / "results"
    needed = ("modal/modes.csv", "forces/cutting_coefficients.csv", "ingest/cuts.csv",
              "chatter/verdicts.csv")
    missing = [f for f in needed if not (res / f).is_file()]
    if missing:
        raise SystemExit(f"{res}: no {', '.join(missing)} (expected a finished study: run "
                         "`snakemake -j2 all` in it first)")
    fn, zeta, k, shapes = modes_arrays(pd.read_csv(res / "modal/modes.csv"))
    coef = pd.read_csv(res / "forces/cutting_coefficients.csv").set_index("name")["value"]
    cuts = pd.read_csv(res / "ingest/cuts.csv").set_index("cut")
    verdicts = pd.read_csv(res / "chatter/verdicts.csv")
    verdicts = verdicts[verdicts["kind"] == "force"].set_index("cut")
    entry, exit_ = engagement_angles_rad(radial_immersion, milling)
    rows = []
    for cut, v in verdicts.iterrows():
        direction = str(cuts.loc[cut, "direction"])
        if direction not in DIRECTION_VECTORS:
            continue
        frame = cut_frame(DIRECTION_VECTORS[direction])
        inplane = np.einsum("mi,id->md", shapes, frame[:, :2])[None]
        model = CuttingModel(int(v["flutes"]), float(coef["Ktc"]) * 1e6,
                             float(coef["Krc"]) / float(coef["Ktc"]), entry, exit_)
        rpm = float(v["spindle_rpm"])
        a_mc = 1e3 * float(coupling_depth(fn[None], zeta, k[None], inplane, model)[0])
        a_zoa = 1e3 * float(batch_zoa_lobes(fn[None], zeta, k[None], inplane, model,
                                            np.array([rpm]))[0, 0])
        rows.append({"cut": cut, "direction": direction,
                     "depth_mm": float(cuts.loc[cut, "depth_mm"]), "spindle_rpm": rpm,
                     "a_zoa_mm": a_zoa, "a_coupling_mm": a_mc,
                     "binding": "coupling" if a_mc < a_zoa else "lobes",
                     "verdict": v["verdict"]})
    return pd.DataFrame(rows)


def main(argv: list[str] | None = None) -> pd.DataFrame:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--study", default=".", help="a study's folder (holding results/)")
    ap.add_argument("--out", default="results/benchmarks")
    ap.add_argument("--radial-immersion", type=float, default=1.0)
    ap.add_argument("--milling", default="slot")
    args = ap.parse_args(argv)
    table = limits(Path(args.study), args.radial_immersion, args.milling)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    table.to_csv(out / "coupling_vs_lobes.csv", index=False)
    stable = table["verdict"] == "stable"
    for name, col in (("zero-order lobes", "a_zoa_mm"), ("mode coupling", "a_coupling_mm")):
        over = table["depth_mm"] > table[col]
        print(f"{name}: {int(over.sum())} of {len(table)} cuts deeper than the limit "
              f"({int((over & stable).sum())} of them judged stable); limit "
              f"{table[col].min():.3g}–{table[col].max():.3g} mm")
    print(f"binding: {table['binding'].value_counts().to_dict()}; verdicts: "
          f"{table['verdict'].value_counts().to_dict()}")
    return table


if __name__ == "__main__":
    main()
