"""Chatter verdicts from a time signal of the cut (force, sound, acceleration): the one routine
that says "stable", "chatter" or "undetermined", at which frequency, and which spindle speeds
to try instead.

Method (the spectral chatter test of [Schmitz & Smith 2009, ch. 4] and [Altintas 2012, ch. 4]:
forced vibration sits on the tooth-passing comb, regenerative chatter on a line between its
teeth):

1. **Spectrogram** (Hann windows of ``window_s``, half overlap, power per bin, the channels'
   powers summed): ``S(f, t)``. Frames whose band power is below ``active_fraction`` of the
   record's 90th-percentile frame are idle (spindle out of the cut) and left out.
2. **Comb**: the tooth-passing harmonics ``k Z n/60`` (the spindle rotation's ``k n/60``
   when the flutes are not given); from the cut's design when the speed is given (moved
   within ``speed_tolerance`` to where the signal's harmonics are, :func:`refine_comb_hz`),
   else estimated from the signal (:func:`estimate_comb_hz`), and said so. The run-out lines
   between the teeth are not excluded: with an even number of flutes they hold the
   period-doubling (flip) chatter at odd multiples of half the tooth-passing frequency
   [Insperger & Stépán 2011]; a run-out line strong enough to pass the threshold is
   named as the line, and its growth tells it apart (step 5).
3. **Strongest non-harmonic line** ``f_c``: a local maximum of the mean spectrum that stands
   ``prominence_db`` above its local floor, farther than ``harmonic_halfwidth_hz`` (and two
   bins) from every comb line (:func:`robomill.spectral_peaks.prominent_peaks`: never a side
   lobe or the skirt of a harmonic).
4. **Energy ratio** per frame, above the frame's floor ``F(t)`` (median power of the band's
   non-harmonic bins)

   .. math:: R(t) = \\frac{\\sum_{|f-f_c| \\le w} (S - F)}{\\sum_k \\sum_{|f-k f_s| \\le w}
             (S - F)}, \\qquad w = 2 Δf

   smoothed by a running median over ``persist_s``; **chatter** when its largest value reaches
   ``energy_ratio_threshold``, **stable** below, **undetermined** when the record has no comb
   (no speed given and none estimable), no harmonic content or is shorter than two windows.
5. **Growth** of the line: least-squares slope of ``10 log10 E_c(t)`` over the active frames
   [dB/s], and the change from the first to the last quarter [dB]. A line above the
   threshold on a harmonic of the spindle's rotation ``k n/60`` (the spindle's speed known,
   not on the tooth comb) is where run-out puts forced lines (a structural mode near it
   amplifies them, more so in sound and acceleration, which weigh vibration by ω²) and where
   period-doubling chatter sits: it is **chatter** when it grows by at least
   ``synchronous_growth_db`` from the first to the last quarter, else **undetermined** (a
   steady line there cannot say which; a record of the cut's entry or a second speed can).
5b. **Chatter off every line** (the synchronous-sampling idea of [Schmitz & Smith 2009,
   ch. 4]: a stable cut's force repeats every spindle revolution, a chattering one does not):
   a record otherwise stable is **chatter** when, in the last quarter of its active frames, at
   least ``broadband_share`` of the band's power lies off the spindle rotation's harmonics
   ``k n/60`` (run-out lines included, lines set aside as forced excluded). Heavy chatter
   whose teeth leave the cut spreads its power over a broad band with no line standing
   ``prominence_db`` above its (raised) floor, and one that sets in late in a short record
   weighs little in the record's mean spectrum; both escape steps 3–4, neither escapes this.
   The frequency named is the strongest off-harmonic bin of that last quarter. Not on a
   record judged again beside an air pass (lines set aside, step 6): an accelerometer
   carries the arm's own broadband vibration off the comb, which the air pass, not this
   share, tells apart from the cut's.
6. **Forced, not chatter** (:func:`robomill.chatter.air.air_test`): a line is forced
   vibration when it is present while the same path is moved without cutting (an **air
   pass** of the same instrument: the robot's servos and motors shake the arm whether it
   cuts or not) and the cut does not make it grow: within ``max(harmonic_halfwidth_hz,
   2 Δf)`` of ``f_c`` the cut's power exceeds the air pass's by less than ``air_rise_db``
   (the evidence says whether the air pass's mean spectrum shows the line ``prominence_db``
   above its local floor). Depth 0 (the air pass) against the cut's depth is the test of
   growth with depth: regenerative chatter exists only above a limiting depth
   [Altintas 2012, ch. 4] and raises its line by orders of magnitude over the air pass, a
   forced line is there at depth 0 already. A forced line is set aside and the record judged
   again on its other lines (:func:`robomill.chatter.air.judge_beside_air`): **chatter** on a
   line no air pass explains, else **forced**; the evidence names the air pass, the lines
   set aside and the numbers.
7. **Speeds** for chatter: the tooth-passing frequency on the chatter frequency,
   ``n_k = 60 f_c / (Z k)``, k = 1, 2, … [Schmitz & Smith 2009, ch. 4], within
   ``speed_range_rpm``, nearest to the cut's speed first, at most ``max_speeds``.

The settings are config ``chatter.verdicts`` (defaults in the schema; :func:`default_settings`).
The same test on the force spectrum, with detection by a growing non-harmonic line, is the
one of [Shagniev 2019]; here it runs on any record of a finished cut.

References: Schmitz, T. L.; Smith, K. S. *Machining Dynamics: Frequency Response to Improved
Productivity*. Springer, New York, 2009 (ch. 4, milling stability and the speed that puts a
tooth-passing harmonic on the chatter frequency). Altintas, Y. *Manufacturing Automation: Metal
Cutting Mechanics, Machine Tool Vibrations, and CNC Design*, 2nd ed. Cambridge University
Press, 2012 (ch. 4, chatter in milling). Insperger, T.; Stépán, G. *Semi-Discretization for
Time-Delay Systems: Stability and Engineering Applications*. Springer, New York, 2011
(period-doubling chatter in milling).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from robomill.settings import FromMapping, schema_default, schema_defaults

VERDICTS = ("stable", "chatter", "forced", "undetermined")
"""The verdicts, in the order the tables list them (``forced``: a line above the threshold
that an air pass shows without cutting, :func:`air_test`)."""


@dataclass(frozen=True)
class VerdictSettings(FromMapping):
    """Config ``chatter.verdicts`` (defaults and meaning in the schema)."""

    energy_ratio_threshold: float
    window_s: float
    band_hz: tuple[float, float]
    harmonic_halfwidth_hz: float
    prominence_db: float
    floor_halfwidth_hz: float
    persist_s: float
    active_fraction: float
    comb_fundamental_hz: tuple[float, float]
    comb_min_score: float
    speed_range_rpm: tuple[float, float]
    max_speeds: int
    speed_tolerance: float
    synchronous_growth_db: float
    air_rise_db: float
    broadband_share: float


def default_settings() -> VerdictSettings:
    """The settings as the schema fills them (``chatter.verdicts`` with no key given)."""
    return VerdictSettings.from_mapping(schema_defaults("chatter")["verdicts"])


@dataclass
class Verdict:
    """One record's verdict and its evidence (see the module's docstring)."""

    verdict: str
    chatter_hz: float
    energy_ratio: float
    threshold: float
    evidence: str
    comb_hz: float = float("nan")
    comb_source: str = "none"
    spindle_rpm: float = float("nan")
    flutes: int | None = None
    line_hz: float = float("nan")
    growth_db_s: float = float("nan")
    growth_db: float = float("nan")
    speeds_rpm: list[float] = field(default_factory=list)
    tooth_targets_hz: list[float] = field(default_factory=list)
    spectrogram: dict[str, np.ndarray] | None = None

    def row(self) -> dict[str, Any]:
        """The verdict as a table row (without the spectrogram)."""
        return {"verdict": self.verdict,
                "chatter_hz": self.chatter_hz,
                "evidence": self.evidence,
                "energy_ratio": self.energy_ratio,
                "energy_ratio_threshold": self.threshold,
                "line_hz": self.line_hz,
                "growth_db_s": self.growth_db_s,
                "growth_db": self.growth_db,
                "comb_hz": self.comb_hz,
                "comb_source": self.comb_source,
                "spindle_rpm": self.spindle_rpm,
                "flutes": np.nan if self.flutes is None else int(self.flutes),
                "speeds_rpm": " ".join(f"{n:.0f}" for n in self.speeds_rpm)}


def spectrogram_power(signal: np.ndarray, fs_hz: float, window_s: float
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(f [Hz], t [s], S [power per bin, (f, t)])`` of ``signal`` ((n,) or (n, channels)):
    Hann windows of ``window_s``, half overlap, mean removed per window, the channels' powers
    summed (:func:`scipy.signal.spectrogram`, ``scaling="spectrum"``)."""
    import scipy.signal

    x = np.asarray(signal, float)
    x = x[:, None] if x.ndim == 1 else x
    n = max(8, min(int(round(window_s * fs_hz)), x.shape[0]))
    f, t, S = scipy.signal.spectrogram(x.T, fs_hz, window="hann", nperseg=n,
                                       noverlap=n // 2, detrend="constant",
                                       scaling="spectrum", axis=-1)
    return f, t, S.sum(axis=0)


def comb_mask(f: np.ndarray, fundamental_hz: float, halfwidth_hz: float, *,
              from_k: int = 1) -> np.ndarray:
    """True where ``f`` lies within ``halfwidth_hz`` of a multiple k ≥ ``from_k`` of
    ``fundamental_hz`` (a harmonic comb: forced vibration; ``from_k=0`` counts the band
    around 0 Hz too)."""
    f = np.asarray(f, float)
    r = f / fundamental_hz
    k = np.round(r)
    return (k >= from_k) & (np.abs(r - k) * fundamental_hz <= halfwidth_hz)


def estimate_comb_hz(f: np.ndarray, power: np.ndarray, s: VerdictSettings
                     ) -> tuple[float, float]:
    """The fundamental of the signal's harmonic comb and its score, from the prominent lines
    of the mean spectrum ``power``.

    A candidate ``f0`` (each of the 20 strongest lines divided by 1…12, within
    ``comb_fundamental_hz``) scores the share of the lines' power within
    ``max(harmonic_halfwidth_hz, 2 Δf)`` of a multiple of it, less the share a comb that dense
    would catch by chance (``2 w / f0``); ``f0`` is refined by least squares over the lines it
    catches, and the best score wins (a tie within 0.02: the higher ``f0``, not a
    subharmonic). ``(nan, score)`` when no candidate reaches ``comb_min_score``."""
    from robomill.spectral_peaks import prominent_peaks

    df = float(f[1] - f[0])
    w = max(s.harmonic_halfwidth_hz, 2.0 * df)
    lo, hi = s.band_hz[0], min(s.band_hz[1], float(f[-1]))
    idx = prominent_peaks(f, power, (lo, hi), prominence_db=s.prominence_db,
                          floor_half_width=s.floor_halfwidth_hz)[:20]
    if idx.size < 2:
        return float("nan"), 0.0
    fl, wl = f[idx], power[idx] / power[idx].sum()
    cands = np.unique(np.concatenate([fl / m for m in range(1, 13)]))
    cands = cands[(cands >= s.comb_fundamental_hz[0]) & (cands <= s.comb_fundamental_hz[1])]
    best = (float("nan"), -np.inf)
    for f0 in cands:
        for _ in range(2):  # score, refine on the caught lines, score again
            k = np.round(fl / f0)
            hit = (k >= 1) & (np.abs(fl - k * f0) <= w + 1e-3 * fl)
            if not hit.any():
                break
            f0 = float(np.sum(wl[hit] * k[hit] * fl[hit]) / np.sum(wl[hit] * k[hit] ** 2))
        k = np.round(fl / f0)
        hit = (k >= 1) & (np.abs(fl - k * f0) <= w + 1e-3 * fl)
        score = float(wl[hit].sum() - min(1.0, 2.0 * w / f0))
        if score > best[1] + 0.02 or (abs(score - best[1]) <= 0.02 and f0 > best[0]):
            best = (f0, score)
    return (best[0] if best[1] >= s.comb_min_score else float("nan")), max(best[1], 0.0)


def refine_comb_hz(f: np.ndarray, power: np.ndarray, comb_hz: float, s: VerdictSettings
                   ) -> float:
    """The design's spindle rotation ``comb_hz`` moved to where the signal's harmonics are
    (the tooth passing's and the run-out's): the spindle under load turns a few per cent off
    its command, and the k-th harmonic drifts k times as far. Searched within
    ``± speed_tolerance`` on a grid fine enough that the highest harmonic used moves a
    quarter bin per step; the score is the sum over the first (up to 20) harmonics in the
    band of ``log P(k f)`` (``P`` interpolated), so that one strong non-harmonic line cannot
    pull the comb onto itself. The best score at an end of the range is no comb found:
    ``comb_hz`` is kept."""
    tol = float(s.speed_tolerance)
    df = float(f[1] - f[0])
    hi = min(s.band_hz[1], float(f[-1]))
    k_max = min(20, int(hi / (comb_hz * (1.0 + tol))))
    if tol <= 0 or k_max < 2:
        return comb_hz
    step = df / (4.0 * k_max)
    grid = comb_hz + np.arange(-tol * comb_hz, tol * comb_hz + step, step)
    k = np.arange(1, k_max + 1)
    tiny = max(float(power.max()), 1e-300) * 1e-15
    score = np.log(np.maximum(np.interp(np.outer(grid, k), f, power), tiny)).sum(axis=1)
    best = int(np.argmax(score))
    if best in (0, grid.size - 1):
        return comb_hz  # the best at an end of the range: no comb found near the design's
    return float(grid[best])


def recommended_speeds_rpm(chatter_hz: float, flutes: int, speed_range_rpm: tuple[float, float],
                           spindle_rpm: float | None = None,
                           max_speeds: int = schema_default("chatter", "verdicts")["max_speeds"],
                           ) -> list[float]:
    """Spindle speeds that put a tooth-passing harmonic on the chatter frequency,
    ``n_k = 60 f_c / (Z k)``, k = 1, 2, … [Schmitz & Smith 2009, ch. 4], within
    ``speed_range_rpm``; nearest to ``spindle_rpm`` first (else highest first), at most
    ``max_speeds``."""
    if not (np.isfinite(chatter_hz) and flutes):
        return []
    lo, hi = speed_range_rpm
    k_min = max(1, int(np.ceil(60.0 * chatter_hz / (flutes * hi))))
    k_max = int(np.floor(60.0 * chatter_hz / (flutes * lo)))
    n = 60.0 * chatter_hz / (flutes * np.arange(k_min, k_max + 1))
    if spindle_rpm is not None and np.isfinite(spindle_rpm):
        n = n[np.argsort(np.abs(n - spindle_rpm), kind="stable")]
    return [float(x) for x in n[:max_speeds]]


def _running_median(x: np.ndarray, size: int) -> np.ndarray:
    import scipy.ndimage

    return scipy.ndimage.median_filter(x, size=max(int(size), 1), mode="nearest")


def judge(signal: np.ndarray, fs_hz: float, settings: VerdictSettings, *,
          spindle_rpm: float | None = None, flutes: int | None = None,
          keep_spectrogram: bool = False, set_aside_hz: tuple[float, ...] = ()) -> Verdict:
    """The verdict of one record (the module's docstring gives the method).

    ``signal``: (n,) or (n, channels) samples at ``fs_hz``; ``spindle_rpm`` and ``flutes`` from
    the cut's design when known (``None``: the comb is estimated from the signal, and speeds
    need ``flutes``). ``keep_spectrogram`` keeps ``f_hz, t_s, power`` (band only) for figures.
    ``set_aside_hz``: lines found forced (:func:`robomill.chatter.air.judge_beside_air`), left
    out of the non-harmonic lines as the comb's are.
    """
    s = settings
    x = np.asarray(signal, float)
    if x.shape[0] < 2 * max(8, int(round(s.window_s * fs_hz))):
        return Verdict("undetermined", float("nan"), float("nan"), s.energy_ratio_threshold,
                       f"record of {x.shape[0] / fs_hz:.3g} s is shorter than two "
                       f"{s.window_s:g} s windows")
    f, t, S = spectrogram_power(x, fs_hz, s.window_s)
    df = float(f[1] - f[0])
    lo, hi = s.band_hz[0], min(s.band_hz[1], 0.95 * fs_hz / 2.0)
    band = (f >= lo) & (f <= hi)
    e_band = S[band].sum(axis=0)
    active = e_band >= s.active_fraction * np.quantile(e_band, 0.9)
    if not np.any(e_band > 0):
        return Verdict("undetermined", float("nan"), float("nan"), s.energy_ratio_threshold,
                       "the record is silent in the band")
    P = S[:, active].mean(axis=1)
    rpm = float(spindle_rpm) if spindle_rpm else float("nan")
    z = int(flutes) if flutes else None
    if np.isfinite(rpm):
        nominal = rpm / 60.0 * (z or 1)  # refined on the spindle's lines (run-out included)
        comb, source = refine_comb_hz(f, P, rpm / 60.0, s) * (z or 1), "design"
        comb_text = (f"comb from the design: {rpm:.0f} rpm, "
                     + (f"tooth passing {nominal:.2f} Hz ({z} flutes)" if z else
                        f"spindle rotation {nominal:.2f} Hz (flutes not given)")
                     + (f", found on the signal at {comb:.2f} Hz "
                        f"({100 * (comb / nominal - 1):+.1f} %)"
                        if abs(comb / nominal - 1) > 1e-3 else ""))
    else:
        comb, score = estimate_comb_hz(f, P, s)
        source = "estimated"
        if not np.isfinite(comb):
            return Verdict("undetermined", float("nan"), float("nan"), s.energy_ratio_threshold,
                           "no spindle speed stated and no harmonic comb found in the signal "
                           f"(best comb score {score:.2f} < {s.comb_min_score:g})",
                           comb_source="none", flutes=z)
        comb_text = (f"comb estimated from the signal: fundamental {comb:.2f} Hz "
                     f"(score {score:.2f}; {60 * comb:.0f} rpm if it is the spindle rotation"
                     + (f", {60 * comb / z:.0f} rpm if it is the tooth passing" if z else "")
                     + ")")
    w_h = max(s.harmonic_halfwidth_hz, 2.0 * df)
    harm = comb_mask(f, comb, w_h)
    out = Verdict("stable", float("nan"), 0.0, s.energy_ratio_threshold, "",
                  comb_hz=comb, comb_source=source, spindle_rpm=rpm, flutes=z)
    if keep_spectrogram:
        out.spectrogram = {"f_hz": f[band], "t_s": t, "power": S[band],
                           "active": active}
    from robomill.spectral_peaks import prominent_peaks

    comb_lines = comb * np.arange(1, int(hi / comb) + 2)
    idx = prominent_peaks(f, P, (lo, hi), prominence_db=s.prominence_db,
                          floor_half_width=s.floor_halfwidth_hz,
                          exclude=np.concatenate([comb_lines, np.asarray(set_aside_hz, float)]),
                          exclude_width=w_h)
    floor_t = np.median(S[band & ~harm], axis=0) if np.any(band & ~harm) else np.zeros(t.size)
    near_h = comb_mask(f, comb, 2.0 * df) & band
    e_h = np.clip(S[near_h] - floor_t, 0.0, None).sum(axis=0)
    if not np.any(e_h[active] > 0):
        out.verdict = "undetermined"
        out.evidence = f"no power on the comb in {lo:g}–{hi:g} Hz; {comb_text}"
        return out
    spin = (rpm / 60.0 * comb / nominal) if np.isfinite(rpm) else (
        comb if not z else float("nan"))
    off = band & ~comb_mask(f, spin if np.isfinite(spin) else comb, w_h)
    for f_aside in set_aside_hz:
        off &= np.abs(f - float(f_aside)) > w_h
    if idx.size == 0:
        out.evidence = (f"no non-harmonic line rises {s.prominence_db:g} dB above its floor in "
                        f"{lo:g}–{hi:g} Hz (energy ratio 0 < {s.energy_ratio_threshold:g}); "
                        f"{comb_text}")
        return _broadband(out, f, S, band, off, active, s, bool(len(set_aside_hz)))
    from robomill.spectral_peaks import interpolate_peak

    i = int(idx[0])
    f_c = interpolate_peak(f, P, i)
    near_c = np.abs(f - f[i]) <= 2.0 * df
    e_c = np.clip(S[near_c] - floor_t, 0.0, None).sum(axis=0)
    ta, ec, eh = t[active], e_c[active], e_h[active]
    persist = max(1, int(round(s.persist_s / (t[1] - t[0])))) if t.size > 1 else 1
    ratio_t = _running_median(ec / np.maximum(eh, 1e-300), min(persist, ta.size))
    ratio = float(ratio_t.max())
    out.energy_ratio, out.line_hz = ratio, f_c
    if ta.size >= 4:
        db = 10.0 * np.log10(ec + 1e-12 * max(ec.max(), 1e-300))
        out.growth_db_s = float(np.polyfit(ta, db, 1)[0])
        q = max(1, ta.size // 4)
        out.growth_db = float(10.0 * np.log10((ec[-q:].mean() + 1e-300)
                                              / (ec[:q].mean() + 1e-300)))
    growth = (f"; growth {out.growth_db_s:+.2f} dB/s, {out.growth_db:+.1f} dB first to last "
              "quarter" if np.isfinite(out.growth_db_s) else "")
    rel = "≥" if ratio >= s.energy_ratio_threshold else "<"
    out.evidence = (f"strongest non-harmonic line {f_c:.1f} Hz: energy ratio {ratio:.3g} {rel} "
                    f"threshold {s.energy_ratio_threshold:g}{growth}; {comb_text}")
    k_sync = round(f_c / spin) if np.isfinite(spin) and spin > 0 else 0
    synchronous = k_sync >= 1 and abs(f_c - k_sync * spin) <= w_h
    if ratio >= s.energy_ratio_threshold and synchronous and not (
            np.isfinite(out.growth_db) and out.growth_db >= s.synchronous_growth_db):
        out.verdict = "undetermined"
        out.evidence += (f"; the line is the spindle rotation's harmonic {k_sync} "
                         f"({k_sync} × {spin:.2f} Hz), where run-out lines and period-doubling "
                         f"chatter both sit, and it grows less than "
                         f"{s.synchronous_growth_db:g} dB: this record cannot tell them apart")
        return out
    if ratio >= s.energy_ratio_threshold:
        out.verdict, out.chatter_hz = "chatter", f_c
        out.tooth_targets_hz = [f_c / k for k in range(1, 6)]
        out.speeds_rpm = recommended_speeds_rpm(f_c, z or 0, s.speed_range_rpm,
                                                rpm, s.max_speeds)
        if not z:
            out.evidence += ("; no flutes given: tooth-passing targets f_c/k = "
                             + ", ".join(f"{v:.1f}" for v in out.tooth_targets_hz) + " Hz")
        return out
    return _broadband(out, f, S, band, off, active, s, bool(len(set_aside_hz)))


def _broadband(out: Verdict, f: np.ndarray, S: np.ndarray, band: np.ndarray, off: np.ndarray,
               active: np.ndarray, s: VerdictSettings, set_aside: bool) -> Verdict:
    """Step 5b of the module's docstring on a record otherwise stable: chatter when the share
    of the band's power off the spindle's harmonics (``off``) in the last quarter of the
    active frames reaches ``broadband_share``; else (or with lines ``set_aside`` as forced)
    ``out`` unchanged."""
    frames = np.flatnonzero(active)
    if set_aside or frames.size == 0 or not np.any(off):
        return out
    last = frames[-max(1, frames.size // 4):]
    total = float(S[band][:, last].sum())
    share = float(S[off][:, last].sum()) / total if total > 0 else 0.0
    if share < s.broadband_share:
        return out
    i = int(np.argmax(np.where(off, S[:, last].mean(axis=1), -np.inf)))
    f_c = float(f[i])
    out.verdict, out.chatter_hz = "chatter", f_c
    out.evidence += (f"; but {100 * share:.0f} % of the band's power in the record's last "
                     f"quarter lies off the spindle's harmonics (≥ {100 * s.broadband_share:.0f}"
                     f" %: the force no longer repeats each revolution), strongest at "
                     f"{f_c:.1f} Hz: chatter")
    out.tooth_targets_hz = [f_c / k for k in range(1, 6)]
    out.speeds_rpm = recommended_speeds_rpm(f_c, out.flutes or 0, s.speed_range_rpm,
                                            out.spindle_rpm, s.max_speeds)
    return out
