"""Where the virtual cell chatters below every linear limit: one cut of a configuration over a
range of feeds (so of chip thickness), cut as it is and without the arm's own excitation,
beside the arm's vibration along the same path without material.

The planner's regenerative model is linear: every tooth stays in the cut, so its limit does not
depend on the feed [Altintas & Budak 1995]. The cell's cut is a closed loop in which a tooth
whose chip offset exceeds the chip leaves the cut; where the arm's own excitation (servos,
motors: ``synth.process.servo_force_N``) moves the tool by more than the chip, the cut can
leave the linear model's reach at a depth far below its limit. This benchmark measures, for one
cut (``--cut``, an id of the configuration's cuts) at each feed of ``--feeds-mm-s``:

* the feed per tooth c [µm] and the arm's vibration in the cut plane along the same path
  without material (:func:`robomill.synth.process.simulate_cut` with ``cutting=False``: the
  air pass) [µm rms, second half of the path], and their ratio;
* the cell's cut as it is and with ``servo_force_N = 0`` (``quiet``): the share of deep tooth
  passages whose chip vanished (``teeth_out``), the tool's vibration in the cut plane about its
  mean [µm rms, second half] and its strongest line [Hz], and the verdict of the cut's own
  force by :func:`robomill.chatter.verdicts.judge` (the force on the tool, no instrument);
* the cell's own linear limit at the cut (its modes at the cut's middle; zero-order lobes and
  semi-discretization, ``benchmarks/edge_switching.py``'s :func:`limits` without the edge term).

    .venv/bin/python benchmarks/thin_chip.py --config .test/config.yaml \\
        examples/other_cell/config.yaml --cut n24k_d45_v2 --out results/benchmarks

(overlays merged over ``config.yaml`` in order, as Snakemake merges them in a folder that
holds ``config.yaml``, the repository's root; in a folder without one, as the tests' runs,
Snakemake takes the ``--configfile`` files alone, and a key that only ``config.yaml`` sets
then has its schema default). Writes ``<out>/thin_chip.csv``.

Altintas & Budak 1995: Altintas, Y.; Budak, E. Analytical prediction of stability lobes in
milling. *CIRP Annals* **44**(1), 357–362, 1995.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
from pathlib import Path

import numpy as np
import pandas as pd
from edge_switching import limits, merged_config, strongest_line_hz

from robomill.chatter.verdicts import default_settings, judge
from robomill.experiment import cut_process
from robomill.io.synthetic_layout import synthetic_cuts
from robomill.synth.cell import cell_from_config
from robomill.synth.process import simulate_cut


def plane_motion_m(sim) -> np.ndarray:
    """The tool's motion in the cut plane about its mean over the second half ``(n, 2)`` [m]."""
    d = sim.deflection_m[sim.deflection_m.shape[0] // 2:, :2]
    return d - d.mean(axis=0)


def plane_rms_um(sim) -> float:
    """The tool's vibration in the cut plane about its mean over the second half [µm rms]."""
    return 1e6 * float(np.sqrt(np.mean(np.sum(plane_motion_m(sim) ** 2, axis=1))))


def state(cell, cut, config, rpm: float, flutes: int) -> dict:
    """The cut on the cell: teeth out, in-plane vibration, its line, the force's verdict."""
    sim = simulate_cut(cell, cut, config)
    v = judge(sim.force_N, sim.fs_hz, default_settings(), spindle_rpm=rpm, flutes=flutes)
    return {"teeth_out": float(sim.teeth_out), "vibration_um_rms": plane_rms_um(sim),
            "line_hz": strongest_line_hz(plane_motion_m(sim), sim.fs_hz),
            "verdict": v.verdict}


def main(argv: list[str] | None = None) -> pd.DataFrame:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--config", nargs="*", default=[], help="overlays over config.yaml")
    ap.add_argument("--cut", required=True, help="a cut id of the configuration")
    ap.add_argument("--feeds-mm-s", default="1,2,3,4,6,10")
    ap.add_argument("--out", default="results/benchmarks")
    args = ap.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    config = merged_config(args.config)
    quiet = copy.deepcopy(config)
    quiet["synth"]["process"]["servo_force_N"] = 0.0
    cell, cell_quiet = cell_from_config(config), cell_from_config(quiet)
    base = next((c for c in synthetic_cuts(config) if c.id == args.cut), None)
    if base is None:
        ap.error(f"--cut {args.cut}: no cut of that id in the configuration's cuts (expected "
                 "one of " + ", ".join(c.id for c in synthetic_cuts(config)) + ")")
    linear = limits(cell, base, [0.0])
    rows = []
    for feed in (float(x) for x in args.feeds_mm_s.split(",")):
        cut = dataclasses.replace(base, feed_mm_s=feed)
        proc = cut_process(cut, cell.experiment)
        rpm, flutes = float(proc["spindle_rpm"]), int(proc["flutes"])
        air = simulate_cut(cell, cut, config, cutting=False)
        chip_um = 1e3 * float(proc["feed_per_tooth_mm"])
        row = {"cut": cut.id, "depth_mm": float(cut.depth_mm), "feed_mm_s": feed,
               "chip_um": chip_um, "air_vibration_um_rms": plane_rms_um(air),
               "linear_limit_zoa_mm": linear["zoa_mm_g0.0"],
               "linear_limit_sdm_mm": linear["sdm_mm_g0.0"]}
        row["air_over_chip"] = row["air_vibration_um_rms"] / chip_um
        row.update({f"as_is_{k}": v for k, v in state(cell, cut, config, rpm, flutes).items()})
        row.update({f"quiet_{k}": v
                    for k, v in state(cell_quiet, cut, quiet, rpm, flutes).items()})
        rows.append(row)
        print(pd.DataFrame([row]).round(3).to_string(index=False, header=len(rows) == 1),
              flush=True)
    table = pd.DataFrame(rows)
    table.to_csv(out / "thin_chip.csv", index=False)
    return table


if __name__ == "__main__":
    main()
