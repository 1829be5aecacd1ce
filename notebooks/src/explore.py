# %% [markdown]
# # Exploring a run
#
# Every intermediate result of the pipeline is a labelled artefact (netCDF with units, or a
# CSV table). This notebook lists them and opens three: a cut's surface spectrum, an FRF of
# the impact test, and the chatter lobe map. Set `results` to the run's results folder.

# %% tags=["parameters"]
results: str = "results"  # the run's results folder
fig_dir: str = None  # where to save figures (None: do not save)

# %%
import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

import robomill
from robomill.plotting import save_figure

pd.set_option("display.max_colwidth", 80)
catalog = robomill.list_artefacts(results)
catalog[["name", "rule", "dims"]]

# %% [markdown]
# Any of them opens with `robomill.open_artefact(path)`; its variables carry `units` and
# `long_name`, its attributes the provenance (rule, commit, config digest, input sha256).

# %%
def path_of(name):
    hit = catalog[catalog.name == name]
    return hit.path.iloc[0] if len(hit) else None


spectra_path = path_of("surface/spectra")
if spectra_path:
    spectra = robomill.open_artefact(spectra_path)
    cut = str(spectra.cut.values[0])
    p = spectra["power"].sel(cut=cut)
    fig, ax = plt.subplots()
    ax.semilogy(p[p.dims[-1]], p, lw=0.8)
    ax.set_xlabel(f"spatial frequency [{spectra[p.dims[-1]].attrs.get('units', '')}]")
    ax.set_ylabel(f"{p.attrs['long_name']} [{p.attrs['units']}]")
    ax.set_title(f"Surface spectrum of cut {cut}")
    if fig_dir:
        save_figure(fig, fig_dir, "explore_surface_psd")
    plt.show()

# %%
frf_path = path_of("modal/frf")
if frf_path:
    from robomill.io.impact import read_frf

    H = read_frf(frf_path)["H"]
    h = H.isel(output=0, input=0)
    fig, ax = plt.subplots()
    ax.semilogy(h["frequency"], np.abs(h), lw=0.8)
    ax.set_xlabel("frequency [Hz]")
    ax.set_ylabel("|H| (receptance)")
    ax.set_title(f"FRF {str(h.output.values)}/{str(h.input.values)} of the impact test")
    if fig_dir:
        save_figure(fig, fig_dir, "explore_frf")
    plt.show()

# %%
lobes_path = path_of("chatter/lobes")
if lobes_path:
    lobes = robomill.open_artefact(lobes_path)
    fig, ax = plt.subplots()
    for solver in lobes.solver.values:
        a = lobes["a_crit_mm"].sel(solver=solver).isel(direction=0)
        ax.plot(a.spindle_rpm, a, "o-", label=str(solver))
    ax.set_xlabel("spindle speed [rpm]")
    ax.set_ylabel("critical axial depth [mm]")
    ax.set_title("Stability lobes of the thesis robot")
    ax.legend()
    if fig_dir:
        save_figure(fig, fig_dir, "explore_lobes")
    plt.show()
