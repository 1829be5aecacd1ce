"""Chapter 4's figure of the chatter verdicts: the spectrogram of a judged record
(``results/chatter/spectrograms.nc``) with its tooth-passing comb and, where it chattered, its
chatter frequency (``results/chatter/verdicts.csv``)."""

from __future__ import annotations

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd
import xarray as xr


def shown_record(table: pd.DataFrame, spectrograms: xr.Dataset) -> str | None:
    """The record the chapter shows: the recording (sound, vibration) with the largest energy
    ratio, else the force record with the largest; ``None`` when none has a spectrogram."""
    if "record" not in spectrograms.coords or not len(table):
        return None
    t = table[table["source"].isin(spectrograms["record"].values.tolist())].copy()
    if not len(t):
        return None
    t["recording"] = t["kind"] != "force"
    t = t.sort_values(["recording", "energy_ratio"], ascending=False, na_position="last")
    return str(t.iloc[0]["source"])


def spectrogram_figure(spectrograms: xr.Dataset, table: pd.DataFrame, source: str
                       ) -> plt.Figure:
    """The pooled spectrogram of ``source`` [dB], the comb's multiples (white dotted, the
    tooth-passing harmonics solid when the flutes are known) and the chatter frequency (red)."""
    d = spectrograms.sel(record=source)
    row = table.set_index("source").loc[source]
    f, t = d["f_hz"].values, d["t_s"].values
    ok_f, ok_t = np.isfinite(f), np.isfinite(t)
    p = d["power"].values[np.ix_(ok_f, ok_t)].astype(float)
    db = 10.0 * np.log10(np.maximum(p, np.nanmax(p) * 1e-8))
    fig, ax = plt.subplots(figsize=(7, 4))
    mesh = ax.pcolormesh(t[ok_t], f[ok_f], db, shading="nearest", cmap="viridis")
    fig.colorbar(mesh, ax=ax, label="power per bin [dB]")
    comb, z = float(row["comb_hz"]), row["flutes"]
    top = float(np.nanmax(f))
    if np.isfinite(comb) and comb > 0:
        step = comb * (int(z) if pd.notna(z) and z else 1)
        for k in range(1, int(top / step) + 1):
            ax.axhline(k * step, color="w", lw=0.6, ls="-" if pd.notna(z) else ":", alpha=0.6)
    if row["verdict"] == "chatter":
        ax.axhline(float(row["chatter_hz"]), color="r", lw=1.2,
                   label=f"chatter {float(row['chatter_hz']):.1f} Hz")
        ax.legend(loc="upper right")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{source} (cut {row['cut']}): {row['verdict']}")
    return fig
