"""Whether the edge force's switching, linearised, is the term the planner's regenerative model
lacks where the virtual cell cuts stably above its linear limit: the cell's own linear limit at
given cuts with and without the term (zero-order and semi-discretization), against the cell's
own closed-loop cut (what it does with and without its edge forces, with and without its own
excitation), and a one-mode cell where the term's onset can be read off the truth.

**The term.** In the cell (``robomill.synth.process``, the force law of Altintas 2012 eq. 2.25
with its edge terms, only while the tooth cuts) tooth j at cutter angle φ has the chip
h = c sin φ + gᵀΔ, g = (sin φ, cos φ), Δ = d(t) − d(t − τ) (cut frame: x feed, y normal; c the
feed per tooth), and while h > 0 the edge force on the tool per unit depth is

.. math:: e(φ) = (−K_{te}\\cos φ − K_{re}\\sin φ,\\ K_{te}\\sin φ − K_{re}\\cos φ).

The chip vanishes at φ_b = 0 and π (sin φ_b = 0), which are an entry (up milling, slot) or an
exit (down milling, slot) of the engagement. Δ moves the zero of h to φ_b + δφ with
δφ = −gᵀ(φ_b)Δ / (c cos φ_b) to first order, so the edge force's impulse per tooth pass
changes by a e(φ_b) gᵀ(φ_b) Δ / (c |cos φ_b| Ω) (Ω the spindle's angular speed), with the same
sign at an entry and at an exit (more chip, longer contact). As a mean over the tooth period
τ = 2π/(NΩ) this adds to the regenerative model R = a W̄ Δ of the zero-order lobes
[Altintas & Budak 1995] the matrix

.. math:: \\bar W_e = γ\\,\\frac{N}{2π} \\sum_b \\frac{e(φ_b)\\, g(φ_b)^T}{c\\,|\\cos φ_b|}
          \\qquad(\\text{slot: } \\bar W_e = −γ\\frac{N}{π c}
          \\begin{pmatrix}0 & K_{te}\\\\ 0 & K_{re}\\end{pmatrix}),

and to the semi-discretization [Insperger & Stépán 2004] an impulse: γ e gᵀ/(c|cos φ_b|)
divided by the step's angle, in the step that holds φ_b on its cutting side. γ = ½: φ_b is
also the edge of the engagement window, and a tooth pushed into the material there cannot cut
outside the window, so the truth's switch answers a shorter contact only: a kink at the
operating point, whose first harmonic for an oscillating Δ is half the two-sided one at any
amplitude (the describing function of a half-wave switch [Gelb & Vander Velde 1968]; with a
run-out offset ±r between two teeth one tooth's boundary is held and the other's free: also
½ on average). The linearisation holds while |gᵀΔ| ≪ c (δφ small); at |gᵀΔ| ≳ c the switch
saturates (a tooth whose chip offset exceeds c leaves the cut), so it cannot hold a state
whose vibration is of the order of the chip.

**What it prints.** Per cut: the depth, feed per tooth, the cell's own linear limit (its
modes at the cut's middle, :func:`robomill.synth.structure.modes_at`) by zero-order lobes
and by semi-discretization for each γ of ``--gains``, the semi-discretization's critical
multiplier (``flip``: period doubling, a line at half the tooth frequency), and the cell's
cut itself (:func:`robomill.synth.process.simulate_cut`) as it is, without its edge forces,
and without its own excitation (servo force, coefficient scatter and run-out off): the rms of
the regenerative displacement Δ over the cut's second half (zero for a tooth-periodic forced
motion), its strongest line and the share of teeth out. ``--one-mode`` adds the check of the
term against the truth: a cell of one 800 Hz mode along the cut's normal (slot, 2 teeth,
28 000 rpm, 5 mm/s, no excitation, no run-out) over depths, the rms of Δ in each quarter of
the cut beside the semi-discretization's limit with γ = 0, ½ and 1.

    .venv/bin/python benchmarks/edge_switching.py --config .test/config.yaml \\
        --cuts benchmarks/edge_switching_oos_cuts.yaml --one-mode --out results/benchmarks
    .venv/bin/python benchmarks/edge_switching.py --config .test/config.yaml \\
        examples/other_cell/config.yaml --out results/benchmarks

(overlays merged over ``config.yaml`` in order, dictionaries key by key, lists replaced, as
Snakemake merges them in the repository's root; ``--without-config-yaml``: the overlays alone
with the schema's defaults, as the tests' runs in folders without a ``config.yaml``;
``--cuts``: the study's cell cuts them, its modes planted where the study's impact test was
made, as the plan's next-run configuration pins it).
Writes ``<out>/edge_switching.csv`` (and ``edge_switching_one_mode.csv``).

Altintas 2012: Altintas, Y. *Manufacturing Automation: Metal Cutting Mechanics, Machine Tool
Vibrations, and CNC Design*, 2nd ed. Cambridge University Press, 2012.
Altintas & Budak 1995: Altintas, Y.; Budak, E. Analytical prediction of stability lobes in
milling. *CIRP Annals* **44**(1), 357–362, 1995.
Insperger & Stépán 2004: Insperger, T.; Stépán, G. Updated semi-discretization method for
periodic delay-differential equations with discrete delay. *International Journal for
Numerical Methods in Engineering* **61**(1), 117–141, 2004.
Gelb & Vander Velde 1968: Gelb, A.; Vander Velde, W. E. *Multiple-Input Describing Functions
and Nonlinear System Design*. McGraw-Hill, 1968.
"""

from __future__ import annotations

import argparse
import copy
import dataclasses
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

from robomill.chatter.lobes_sdm import classify_multiplier, critical_depth
from robomill.chatter.lobes_zoa import zoa_lobes
from robomill.chatter.model import CuttingModel, EdgeSwitching, ModeXY, tool_from_modes
from robomill.experiment import cut_process, feed_direction
from robomill.forces.model import cut_frame, engagement_angles_rad
from robomill.io.synthetic_layout import synthetic_cuts
from robomill.synth.cell import cell_from_config
from robomill.synth.process import simulate_cut
from robomill.synth.structure import modes_at

REPO = Path(__file__).resolve().parents[1]
SDM_STEPS = 40
DEPTH_MAX_M = 0.03


def edge_switching_cut(teeth: int, Kt_N_m2: float, Kr: float, phi_st: float, phi_ex: float,
                       Kte_N_m: float, Kre_N_m: float, chip_m: float, gain: float, *,
                       Ka: float | None = None, Kae_N_m: float = 0.0) -> CuttingModel:
    """The linear cutting model plus the linearised switching of the edge force where the chip
    vanishes (module docstring; :class:`robomill.chatter.model.EdgeSwitching`); γ = 0: the
    plain linear model."""
    edge = (EdgeSwitching(Kte_N_m, Kre_N_m, chip_m, gain, Kae_N_m) if gain else None)
    return CuttingModel(int(teeth), Kt_N_m2, Kr, phi_st, phi_ex, Ka=Ka, edge=edge)


def merged_config(overlays: list[str], base: bool = True) -> dict:
    """``config.yaml`` with the overlays merged over it in order, as Snakemake merges them in
    a folder holding ``config.yaml`` (the repository's root); ``base=False``: the overlays
    alone, as in a folder without one (the tests' runs: a key only ``config.yaml`` sets then
    takes its schema default when the workflow validates the configuration)."""
    def merge(a, b):
        for k, v in b.items():
            if isinstance(v, dict) and isinstance(a.get(k), dict):
                merge(a[k], v)
            else:
                a[k] = v
        return a

    config = yaml.safe_load((REPO / "config.yaml").read_text()) if base else {}
    for path in overlays:
        merge(config, yaml.safe_load(Path(path).read_text()))
    if base:
        return config
    from robomill.pipeline.config import validate_config
    from robomill.settings import SCHEMAS

    return validate_config(config, SCHEMAS / "config.schema.yaml")  # the schema's defaults


def config_with_cuts(config: dict, cuts: str | None) -> dict:
    """``config`` with its experiment's cuts replaced by the YAML cut list ``cuts`` (None:
    kept) on the same cell: its modes stay planted where the study's impact test was made
    (``synth.process.reference_point_mm`` pinned to the impact point), not around these cuts."""
    if cuts:
        from robomill.io.synthetic_layout import impact_tcp_mm

        config["synth"]["process"]["reference_point_mm"] = impact_tcp_mm(config)
        config["experiment"]["cuts"] = yaml.safe_load(Path(cuts).read_text())
    return config


def limits(cell, cut, gains) -> dict:
    """The cell's own linear limit at ``cut`` [mm] for each gain, zero-order and SDM."""
    proc = cut_process(cut, cell.experiment)
    q = cell.joint_path_rad(cut, np.array([0.5 * float(cell.experiment["cut_length_mm"])]))[0]
    frame = cut_frame(feed_direction(cut))
    tool = tool_from_modes([ModeXY(m.f_hz, m.zeta, m.k_N_m, tuple((np.array(m.shape) @ frame)[:2]))
                            for m in modes_at(cell, q)])
    st, ex = engagement_angles_rad(proc["radial_immersion"], proc["milling"])
    k = cell.cutting
    rpm = float(proc["spindle_rpm"])
    row = {"fz_um": 1e3 * float(proc["feed_per_tooth_mm"])}
    for g in gains:
        model = edge_switching_cut(int(proc["flutes"]), k["Ktc_N_mm2"] * 1e6,
                                   k["Krc_N_mm2"] / k["Ktc_N_mm2"], st, ex, k["Kte_N_mm"] * 1e3,
                                   k["Kre_N_mm"] * 1e3, 1e-3 * float(proc["feed_per_tooth_mm"]),
                                   float(g))
        row[f"zoa_mm_g{g}"] = 1e3 * float(zoa_lobes(tool, model, [rpm])[0][0])
        a, mu = critical_depth(tool, model, rpm, depth_max_m=DEPTH_MAX_M, m=SDM_STEPS,
                               rtol=1e-3)
        row[f"sdm_mm_g{g}"] = 1e3 * a
        row[f"sdm_kind_g{g}"] = classify_multiplier(mu) if np.isfinite(a) else ""
    return row


def quiet(config: dict) -> dict:
    """Without the cell's own excitation: servo force, coefficient scatter and run-out off."""
    p = config["synth"]["process"]
    p.update(servo_force_N=0.0, coefficient_scatter=0.0, runout_um=[0.0, 0.0])
    return config


def no_edge(config: dict) -> dict:
    config["synth"]["cutting"].update(Kte_N_mm=0.0, Kre_N_mm=0.0, Kae_N_mm=0.0)
    return config


def strongest_line_hz(x: np.ndarray, fs_hz: float, fmin_hz: float = 5.0) -> float:
    """The strongest line of ``x`` ``(n,)`` or ``(n, k)`` (Hann window, the columns' magnitude
    spectra summed) above ``fmin_hz`` [Hz]: the highest local maximum there
    (:func:`scipy.signal.find_peaks`), so never the falling skirt of a lower-frequency line;
    NaN when the spectrum has none."""
    from scipy.signal import find_peaks

    x = np.asarray(x, float).reshape(len(x), -1)
    spec = np.abs(np.fft.rfft(x * np.hanning(len(x))[:, None], axis=0)).sum(axis=1)
    f = np.fft.rfftfreq(len(x), 1.0 / fs_hz)
    peaks, _ = find_peaks(spec)
    peaks = peaks[f[peaks] > fmin_hz]
    return float(f[peaks[np.argmax(spec[peaks])]]) if peaks.size else float("nan")


def regenerative(sim, along: np.ndarray | None = None) -> tuple[np.ndarray, float]:
    """Δ = d(t) − d(t − τ) in the cut plane (or along ``along``) and its strongest line over
    the second half [Hz] (:func:`strongest_line_hz`)."""
    t, d = sim.t_s, sim.deflection_m[:, :2]
    back = np.stack([np.interp(t - 1.0 / sim.tooth_hz, t, d[:, j]) for j in range(2)], 1)
    delta = d - back
    delta[t < 2.0 / sim.tooth_hz] = 0.0
    if along is not None:
        delta = (delta @ along)[:, None]
    return delta, strongest_line_hz(delta[delta.shape[0] // 2:], sim.fs_hz)


def truth(config: dict, cut_id: str, variant: str) -> dict:
    c = copy.deepcopy(config)
    if "quiet" in variant:
        quiet(c)
    if "no_edge" in variant:
        no_edge(c)
    cut = next(x for x in synthetic_cuts(c) if x.id == cut_id)
    sim = simulate_cut(cell_from_config(c), cut, c)
    delta, line = regenerative(sim)
    half = delta[delta.shape[0] // 2:]
    return {f"{variant}_regen_um": 1e6 * float(np.sqrt(np.mean(np.sum(half**2, 1)))),
            f"{variant}_line_hz": line, f"{variant}_teeth_out": float(sim.teeth_out)}


def one_mode(depths_mm: list[float]) -> pd.DataFrame:
    """The term against the truth on a one-mode cell (module docstring)."""
    config = quiet(merged_config([]))
    config["experiment"].update(cut_length_mm=20.0, spindle_rpm=28000.0)
    mode = {"f_hz": 800.0, "zeta": 0.03, "k_N_m": 2.0e7}
    # the normal mode, and a stiff axial one (the cell needs no more)
    config["synth"]["modes"] = [{**mode, "shape": [0.0, 1.0, 0.0]},
                                {**mode, "f_hz": 840.0, "k_N_m": 2.0e9, "shape": [0.0, 0.0, 1.0]}]
    config["synth"]["process"]["spindle_modes"] = []
    config["synth"]["loadtests"]["robots"] = []
    cell = cell_from_config(config)
    base = next(x for x in synthetic_cuts(config) if x.id == "s1_g1_px")
    frame = cut_frame(feed_direction(base))
    normal = (np.array([0.0, 1.0, 0.0]) @ frame)[:2]
    k = cell.cutting
    feed = 5.0
    rpm = 28000.0
    chip = 1e-3 * feed / (2 * rpm / 60.0)
    tool = tool_from_modes([ModeXY(800.0, 0.03, 2.0e7, tuple(normal))])
    sdm = {}
    for g in (0.0, 0.5, 1.0):
        model = edge_switching_cut(2, k["Ktc_N_mm2"] * 1e6, k["Krc_N_mm2"] / k["Ktc_N_mm2"], 0.0,
                                   np.pi, k["Kte_N_mm"] * 1e3, k["Kre_N_mm"] * 1e3, chip, g)
        a, _ = critical_depth(tool, model, rpm, depth_max_m=DEPTH_MAX_M, m=2 * SDM_STEPS,
                              rtol=1e-3)
        sdm[g] = 1e3 * a
    rows = []
    for depth in depths_mm:
        sim = simulate_cut(cell, dataclasses.replace(base, feed_mm_s=feed, depth_mm=depth), config)
        delta, line = regenerative(sim, normal)
        q = np.array_split(delta[:, 0], 4)
        rows.append({"depth_mm": depth, "line_hz": line,
                     **{f"regen_q{i + 1}_um": 1e6 * float(np.sqrt(np.mean(x**2)))
                        for i, x in enumerate(q)},
                     **{f"sdm_mm_g{g}": v for g, v in sdm.items()}})
    return pd.DataFrame(rows)


def add_cell_arguments(ap: argparse.ArgumentParser) -> None:
    """The options that name the cell and its cuts (``--config``, ``--without-config-yaml``,
    ``--cuts``) and ``--out``, shared by the benchmarks that read the cell's own truth."""
    ap.add_argument("--config", nargs="*", default=[], help="overlays over config.yaml")
    ap.add_argument("--without-config-yaml", action="store_true",
                    help="the overlays alone, as the tests' runs take them (merged_config)")
    ap.add_argument("--cuts", help="YAML list of cuts (manifest keys); default experiment.cuts")
    ap.add_argument("--out", default="results/benchmarks")


def cell_of_arguments(args) -> tuple[Path, dict, object]:
    """``--out`` (created), the configuration and the cell that :func:`add_cell_arguments`'
    options name."""
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    config = config_with_cuts(merged_config(args.config, base=not args.without_config_yaml),
                              args.cuts)
    return out, config, cell_from_config(config)


def main(argv: list[str] | None = None) -> pd.DataFrame:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    add_cell_arguments(ap)
    ap.add_argument("--gains", default="0,0.5,1")
    ap.add_argument("--one-mode", action="store_true")
    ap.add_argument("--one-mode-depths-mm", default="0.35,0.5,0.6,0.7,0.85,1.0,1.5,2.0")
    ap.add_argument("--skip-cuts", action="store_true", help="only the one-mode check")
    args = ap.parse_args(argv)
    pd.set_option("display.width", 250)
    out, config, cell = cell_of_arguments(args)
    gains = [float(g) for g in args.gains.split(",")]
    rows = []
    for cut in [] if args.skip_cuts else synthetic_cuts(config):
        row = {"cut": cut.id, "depth_mm": float(cut.depth_mm), **limits(cell, cut, gains)}
        for variant in ("as_is", "no_edge", "quiet", "quiet_no_edge"):
            row.update(truth(config, cut.id, variant))
        rows.append(row)
        print(pd.DataFrame([row]).round(3).to_string(index=False, header=len(rows) == 1),
              flush=True)
    table = pd.DataFrame(rows)
    if rows:
        table.to_csv(out / "edge_switching.csv", index=False)
    if args.one_mode:
        check = one_mode([float(d) for d in args.one_mode_depths_mm.split(",")])
        print(check.round(3).to_string(index=False))
        check.to_csv(out / "edge_switching_one_mode.csv", index=False)
    return table


if __name__ == "__main__":
    main()
