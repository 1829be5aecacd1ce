"""Chatter: stability lobes for any machine, the Shagniev 2019 time-domain robot–tool–surface model,
FFT chatter detection with adaptive depth, and the study's robot's chatter-free parameters.

Conventions (used by every module of this package and by chapter 4)
--------------------------------------------------------------------
* ``x`` is the feed direction, ``y`` the normal direction in the plane of the cut (the seed's
  ``z``); the tool axis is the third direction.
* The cutter angle φ of a tooth is measured **clockwise from +y**; a tooth cuts while
  φ_st < φ < φ_ex (the engagement g(φ) = 1 [Shagniev 2019]).
* **Up-milling** enters at φ_st = 0 and exits at φ_ex = arccos(1 − 2 a_e/D);
  **down-milling** enters at φ_st = arccos(2 a_e/D − 1) and exits at φ_ex = π;
  slotting is radial immersion a_e/D = 1 (0 … π).
* Chip thickness h_j = (Δx sin φ_j + Δy cos φ_j) g(φ_j) with Δ = current minus
  one-tooth-period-delayed tool displacement (Shagniev 2019; Altintas 2012 eq. 3.50); tangential
  and radial forces R_t = K_t a h, R_r = K_r R_t; on the tool
  R_x = −R_t cos φ − R_r sin φ, R_y = R_t sin φ − R_r cos φ, summed over the teeth.

Modules
-------
:mod:`~robomill.chatter.model`      linear tool models (modes → state space), directional
                                    matrix W(φ) with the optional axial row and edge force's
                                    switching, immersion angles
:mod:`~robomill.chatter.lobes_zoa`  zero-order analytical lobes (Altintas & Budak 1995), the
                                    one routine for one tool and for the planner's batches
:mod:`~robomill.chatter.envelope_kernel` the lobes' lower envelope on a speed grid (numba)
:mod:`~robomill.chatter.lobes_sdm`  first-order semi-discretization (Insperger & Stépán 2004;
                                    the Shagniev 2019 diagram and the benchmark's baseline)
:mod:`~robomill.chatter.lobes_sem`  spectral element with exact free flight (Khasawneh & Mann
                                    2011): converged lobes with a per-speed error estimate
:mod:`~robomill.chatter.timedomain` Shagniev 2019 robot–tool–surface simulation (numba)
:mod:`~robomill.chatter.detection`  sliding-window FFT detection, adaptive depth logic
:mod:`~robomill.chatter.modal_timedomain` the Shagniev 2019 chip and force law on a modal tool
                                    (regenerative and delay-free): the plan's stability check
:mod:`~robomill.chatter.slot_model` the study's robot in a slot's frame: mode coupling,
                                    recommendations
:mod:`~robomill.chatter.lobe_maps`  lobe diagrams as datasets (zoa beside sdm or sem)
:mod:`~robomill.chatter.cases`      the configured lobe cases
:mod:`~robomill.chatter.seed`       the Shagniev 2019 study (lobes, time domain, onset check)
:mod:`~robomill.chatter.slot_lobes` the study's slots: lobes, mode coupling, recommendations,
                                    each cut at its own speed and depth
:mod:`~robomill.chatter.findings`   chapter 4's findings from the stage's artefacts
:mod:`~robomill.chatter.tables`     chapter 4's tables (onset checks, mode coupling)
:mod:`~robomill.chatter.figures`    chapter 4's figures
"""

from robomill.lazy import lazy_exports

__getattr__, __dir__, __all__ = lazy_exports(__name__, {
    "lobes_sdm": ("sdm_lobes", "sdm_spectral_radius"),
    "lobes_sem": ("sem_lobes", "sem_spectral_radius"),
    "lobes_zoa": ("zoa_lobes",),
    "model": ("CuttingModel", "LinearTool", "ModeXY", "immersion_angles", "tool_from_modes"),
    "findings": ("chatter_findings", "load_cases"),
    "tables": ("coupling_table", "onset_table"),
    "figures": ("case_error_figure", "case_lobes_figure", "detection_figure",
                "robot_lobes_figure", "seed_lobes_figure", "seed_spectra_figure",
                "seed_time_figure", "slot_figure"),
})
