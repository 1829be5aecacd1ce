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
    """The pooled spectrogram of ``source`` [dB], the comb's lines as ticks on the right edge
    (the tooth-passing harmonics; dotted: the spindle rotation's where the flutes are unknown)
    and the chatter frequency (red)."""
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
    if np.isfinite(comb) and comb > 0:  # ticks on the right edge: the lines stay visible
        for k in range(1, int(top / comb) + 1):
            ax.plot([1.0, 1.03], [k * comb] * 2, color="k", lw=0.8, clip_on=False,
                    ls="-" if pd.notna(z) else ":", transform=ax.get_yaxis_transform())
    if row["verdict"] == "chatter":
        ax.axhline(float(row["chatter_hz"]), color="r", lw=1.2,
                   label=f"chatter {float(row['chatter_hz']):.1f} Hz")
        ax.legend(loc="upper right")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("frequency [Hz]")
    ax.set_title(f"{source} (cut {row['cut']}): {row['verdict']}")
    return fig
