"""Every time record of a study judged for chatter: each cut's dynamometer force record and
each sound or vibration recording (:mod:`robomill.io.recordings`), one row per cut and record
in ``results/chatter/verdicts.csv`` (:data:`VERDICT_COLUMNS` first), and the records'
spectrograms, pooled to a common size, in ``results/chatter/spectrograms.nc`` for chapter 4.

A record that cannot be read gets the verdict ``undetermined`` with the reader's one line as
its evidence; the other records are judged as usual.

**Air passes** (manifest ``pass: air`` on a ``sound`` or ``vibration`` entry: the same path
moved without material, :func:`is_air_pass`) are no record of a cut's outcome and get no
row; they are the evidence that tells a forced line from chatter
(:func:`robomill.chatter.air.air_test`). A chatter verdict of a cut's record is tested
on the air pass of the same instrument (the same kind at the same rate); a force record's on
the cut's other instruments, each record against its own air pass, at the force record's line:
the dynamometer sits under the workpiece and feels the arm's vibration only through the chip,
so its own air pass is silent. The first air test that finds the line forced decides.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
import pandas as pd

from robomill import catalogue
from robomill.chatter.verdicts import VERDICTS, Verdict, VerdictSettings, judge
from robomill.errors import RawDataError

VERDICT_COLUMNS = ("cut", "verdict", "chatter_hz", "source", "evidence")
"""The table's first columns, in this order (others read it by these names)."""
JUDGED_KINDS = ("force", "sound", "vibration")
"""Manifest kinds whose records are judged."""
AIR_KINDS = ("sound", "vibration")
"""Manifest kinds that may list an air pass (``pass: air``)."""


def is_air_pass(entry: Mapping[str, Any]) -> bool:
    """Whether a manifest entry is an air pass (``pass: air``) of a recording."""
    return entry.get("kind") in AIR_KINDS and str(entry.get("pass") or "loaded") == "air"
IMAGE_F, IMAGE_T = 160, 80
"""Frequency and time bins of the pooled spectrograms."""


def read_samples(manifest, entry: Mapping[str, Any]) -> tuple[np.ndarray, float]:
    """``(samples (n, channels), fs_hz)`` of a listed record, its sha256 checked."""
    path = manifest.verify_file(entry["path"])
    if entry["kind"] == "force":
        from robomill.io.forces import open_force_record

        rec = open_force_record(path, float(entry["fs_hz"]))
        return np.concatenate([f for _, f in rec.chunks()]), rec.fs_hz
    from robomill.io.recordings import read_recording

    rec = read_recording(path, entry["kind"], fs_hz=entry.get("fs_hz"),
                         channels=entry.get("channels"))
    return rec.samples, rec.fs_hz


def record_design(manifest, entry: Mapping[str, Any]) -> tuple[float | None, int | None]:
    """Spindle speed [rpm] and flutes of a record: the entry's own, else its cut's design
    (the cut's keys, else the experiment's); ``None`` where none is stated."""
    rpm, z = entry.get("spindle_rpm"), entry.get("flutes")
    cut = next((c for c in manifest.cuts if c.id == entry.get("cut")), None)
    if cut is not None:
        rpm = rpm if rpm is not None else (cut.spindle_rpm if cut.spindle_rpm is not None
                                           else manifest.experiment.get("spindle_rpm"))
        z = z if z is not None else (cut.flutes if cut.flutes is not None
                                     else manifest.experiment.get("flutes"))
    return (None if rpm is None else float(rpm)), (None if z is None else int(z))


def spectrogram_image(spec: Mapping[str, np.ndarray], n_f: int = IMAGE_F, n_t: int = IMAGE_T
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A spectrogram pooled to ``(n_f, n_t)`` cells (largest power of each cell, so that a
    line survives), with the cells' centre frequencies [Hz] and times [s]; a record with
    fewer bins or frames fills the first cells and leaves NaN after them."""
    f, t, S = spec["f_hz"], spec["t_s"], spec["power"]
    size = (n_f, n_t)
    n_f, n_t = min(n_f, f.size), min(n_t, t.size)
    fe = np.linspace(0, f.size, n_f + 1).astype(int)
    te = np.linspace(0, t.size, n_t + 1).astype(int)
    img = np.maximum.reduceat(np.maximum.reduceat(S, fe[:-1], axis=0), te[:-1], axis=1)
    fc = np.array([f[min(max(a, 0), f.size - 1)] for a in (fe[:-1] + fe[1:]) // 2])
    tc = np.array([t[min(max(a, 0), t.size - 1)] for a in (te[:-1] + te[1:]) // 2])
    pad = [(0, size[0] - n_f), (0, size[1] - n_t)]  # a short record: NaN cells after it
    return (np.pad(fc, pad[0], constant_values=np.nan), np.pad(tc, pad[1], constant_values=np.nan),
            np.pad(img, pad, constant_values=np.nan))


def judge_entry(manifest, entry: Mapping[str, Any], settings: VerdictSettings) -> Verdict:
    """The verdict of one listed record; an unreadable one is ``undetermined`` with the
    reader's line as its evidence."""
    try:
        x, fs = read_samples(manifest, entry)
    except RawDataError as exc:
        return Verdict("undetermined", float("nan"), float("nan"),
                       settings.energy_ratio_threshold, f"not judged: {exc}")
    rpm, z = record_design(manifest, entry)
    return judge(x, fs, settings, spindle_rpm=rpm, flutes=z, keep_spectrogram=True)


def _air_pairs(entry: Mapping[str, Any], judged, air) -> list[tuple[Mapping, Mapping]]:
    """The (cut record, air pass) pairs that can test ``entry``'s line: its own with each air
    pass of its kind and cut; for a force record, each recording of the cut with each air pass
    of the recording's kind."""
    cut = entry.get("cut")
    mine = [a for a in air if a.get("cut") == cut]
    if entry["kind"] != "force":
        return [(entry, a) for a in mine if a["kind"] == entry["kind"]]
    return [(r, a) for r in judged if r.get("cut") == cut and r["kind"] in AIR_KINDS
            for a in mine if a["kind"] == r["kind"]]


def forced_or_chatter(manifest, entry: Mapping[str, Any], verdict: Verdict, judged, air,
                      settings: VerdictSettings) -> Verdict:
    """A chatter verdict of ``entry`` tested on the air passes of its cut (module docstring)
    by :func:`robomill.chatter.air.judge_beside_air`: a line an air pass finds forced is
    set aside and the record judged on its other lines; ``forced`` with the deciding test
    first in its evidence, else ``chatter`` with each test's sentence added; unchanged when
    no air pass can test it."""
    from robomill.chatter.air import AirTest, air_test, judge_beside_air

    pairs = _air_pairs(entry, judged, air)
    if not pairs:
        return verdict
    read: dict[str, tuple[np.ndarray, float] | RawDataError] = {}

    def samples(e: Mapping[str, Any]) -> tuple[np.ndarray, float] | RawDataError:
        if e["path"] not in read:
            try:
                read[e["path"]] = read_samples(manifest, e)
            except RawDataError as exc:
                read[e["path"]] = exc
        return read[e["path"]]

    def test_line(line_hz: float) -> list[AirTest]:
        tests = []
        for rec, a in pairs:
            xs, xa = samples(rec), samples(a)
            bad = next((r for r in (xs, xa) if isinstance(r, RawDataError)), None)
            if bad is not None:
                tests.append(AirTest(False, line_hz, float("nan"), float("nan"),
                                     f"`{a['path']}` not read: {bad}"))
                continue
            name = (f"the air pass `{a['path']}`" if rec is entry else
                    f"the air pass `{a['path']}` against `{rec['path']}`")
            tests.append(air_test(*xs, *xa, line_hz, settings, air_name=name))
        return tests

    x, fs = samples(entry)
    rpm, z = record_design(manifest, entry)
    return judge_beside_air(x, fs, settings, test_line, spindle_rpm=rpm, flutes=z,
                            keep_spectrogram=verdict.spectrogram is not None)


def judge_study(manifest, entries: Iterable[Mapping[str, Any]], settings: VerdictSettings,
                log=None):
    """``(table, spectrograms)``: one row per record but the air passes (columns
    :data:`VERDICT_COLUMNS`, then ``kind`` and :meth:`Verdict.row`'s evidence; a chatter
    verdict tested on the cut's air passes, :func:`forced_or_chatter`), and an
    :class:`xarray.Dataset` of the pooled spectrograms (dims ``record, f_bin, t_bin``)."""
    import xarray as xr

    entries = list(entries)
    air = [e for e in entries if is_air_pass(e)]
    judged = [e for e in entries if not is_air_pass(e)]
    rows, images = [], []
    for e in judged:
        v = judge_entry(manifest, e, settings)
        if v.verdict == "chatter" and air:
            v = forced_or_chatter(manifest, e, v, judged, air, settings)
        row = {"cut": e.get("cut", ""), **v.row(), "source": e["path"], "kind": e["kind"]}
        rows.append(row)
        if log is not None:
            line = f"{e['path']}: {v.verdict}: {v.evidence}"
            (log.warning if v.evidence.startswith("not judged") or v.comb_source == "none"
             and v.verdict == "undetermined" else log.info)(line)
        if v.spectrogram is not None:
            images.append((e["path"], *spectrogram_image(v.spectrogram)))
    cols = list(VERDICT_COLUMNS)
    table = pd.DataFrame(rows)
    if len(table):
        table = table[cols + [c for c in table.columns if c not in cols]]
    else:
        table = pd.DataFrame(columns=cols)
    ds = xr.Dataset()
    if images:
        ds = xr.Dataset(
            {"power": (("record", "f_bin", "t_bin"),
                       np.stack([im[3] for im in images]).astype(np.float32),
                       {"units": "power per bin (signal unit squared)",
                        "long_name": "spectrogram, largest power of each cell"}),
             "f_hz": (("record", "f_bin"), np.stack([im[1] for im in images]),
                      {"units": "Hz", "long_name": "centre frequency of each cell"}),
             "t_s": (("record", "t_bin"), np.stack([im[2] for im in images]),
                     {"units": "s", "long_name": "centre time of each cell"})},
            coords={"record": ("record", [im[0] for im in images],
                               {"units": "1", "long_name": "record (source in the raw folder)"})})
    return table, ds


def _line(r: Mapping[str, Any]) -> str:
    """One record's verdict as a sentence fragment (source, cut, verdict, evidence)."""
    head = f"`{r['source']}` (cut {r['cut']}, {r['kind']}): **{r['verdict']}**"
    if r["verdict"] == "chatter":
        head += f" at {float(r['chatter_hz']):.1f} Hz"
        if isinstance(r.get("speeds_rpm"), str) and r["speeds_rpm"]:
            head += f"; speeds to try {r['speeds_rpm'].replace(' ', ', ')} rpm"
    elif r["verdict"] == "forced":
        head += f" at {float(r['line_hz']):.1f} Hz (forced vibration, not chatter)"
    return f"{head} — {r['evidence']}"


def comparison_table(table: pd.DataFrame) -> pd.DataFrame:
    """Per cut with both a force record and a recording: each recording's verdict beside the
    force record's (``agree``: the same verdict; chatter frequencies within 5 % where both
    chatter)."""
    rows = []
    force = table[table["kind"] == "force"].set_index("cut")
    for _, r in table[table["kind"] != "force"].iterrows():
        if r["cut"] not in force.index:
            continue
        fr = force.loc[r["cut"]]
        fr = fr.iloc[0] if isinstance(fr, pd.DataFrame) else fr
        agree = r["verdict"] == fr["verdict"]
        if agree and r["verdict"] == "chatter":
            agree = abs(float(r["chatter_hz"]) / float(fr["chatter_hz"]) - 1.0) <= 0.05
        rows.append({"cut": r["cut"], "force_source": fr["source"],
                     "force_verdict": fr["verdict"], "force_chatter_hz": fr["chatter_hz"],
                     "recording": r["source"], "recording_verdict": r["verdict"],
                     "recording_chatter_hz": r["chatter_hz"], "agree": bool(agree)})
    return pd.DataFrame(rows, columns=["cut", "force_source", "force_verdict",
                                       "force_chatter_hz", "recording", "recording_verdict",
                                       "recording_chatter_hz", "agree"])


def verdict_findings(table: pd.DataFrame, settings: VerdictSettings, n_air_passes: int = 0):
    """Chapter 4's findings of the verdicts (``results/chatter/verdict_findings.yaml``):
    counts per verdict and kind, one line per recording (and per chattering or undetermined
    force record), the force-vs-recording comparison and the threshold that decided."""
    from robomill.findings import Findings

    art = catalogue.artefact("chatter.verdicts")
    f = Findings("chatter_verdicts")
    f.add("verdict_threshold", settings.energy_ratio_threshold, artefact=art,
          what="energy_ratio_threshold", config_key="chatter.verdicts.energy_ratio_threshold")
    f.add("air_rise_db", settings.air_rise_db, "dB", artefact=art, what="air_rise_db",
          config_key="chatter.verdicts.air_rise_db")
    f.add("n_air_passes", int(n_air_passes), artefact="manifest.yaml",
          what="files with pass: air (sound, vibration), the evidence of the air test")
    kinds = table["kind"] if len(table) else pd.Series(dtype=str)
    f.add("n_records", int(len(table)), artefact=art, what="rows")
    f.add("n_force_records", int((kinds == "force").sum()), artefact=art, what="kind force")
    f.add("n_recordings", int(kinds.isin(["sound", "vibration"]).sum()), artefact=art,
          what="kind sound or vibration")
    for v in VERDICTS:
        f.add(f"n_{v}", int((table["verdict"] == v).sum()) if len(table) else 0, artefact=art,
              what=f"verdict {v}")
    rec = table[kinds != "force"] if len(table) else table
    f.add("recording_lines", [_line(r) for _, r in rec.iterrows()], artefact=art,
          what="sound and vibration rows")
    odd = table[(kinds == "force") & (table["verdict"] != "stable")] if len(table) else table
    f.add("force_lines", [_line(r) for _, r in odd.iterrows()], artefact=art,
          what="force rows not stable")
    forced = table[table["verdict"] == "forced"] if len(table) else table
    f.add("forced_lines", [_line(r) for _, r in forced.iterrows()], artefact=art,
          what="rows forced: a line the cut's air pass shows without cutting")
    if len(table) and (kinds == "force").any():
        fr = table[kinds == "force"]
        f.add("force_ratio_max", float(fr["energy_ratio"].max()), artefact=art,
              what="largest energy_ratio of the force records")
        f.add("force_line_hz_median", float(fr["line_hz"].median()), "Hz", artefact=art,
              what="median line_hz of the force records")
    cmp = comparison_table(table) if len(table) else comparison_table(
        pd.DataFrame(columns=list(VERDICT_COLUMNS) + ["kind"]))
    f.add("n_compared", int(len(cmp)), artefact=art, what="cuts with force and a recording")
    f.add("n_agree", int(cmp["agree"].sum()) if len(cmp) else 0, artefact=art,
          what="recordings whose verdict is the force record's")
    f.add("comparison_lines", [
        f"cut {r['cut']}: force `{r['force_source']}` {r['force_verdict']}"
        + (f" ({float(r['force_chatter_hz']):.1f} Hz)" if r["force_verdict"] == "chatter" else "")
        + f", `{r['recording']}` {r['recording_verdict']}"
        + (f" ({float(r['recording_chatter_hz']):.1f} Hz)"
           if r["recording_verdict"] == "chatter" else "")
        + (": agree" if r["agree"] else ": **disagree**") for _, r in cmp.iterrows()],
        artefact=art, what="force vs recording per cut")
    return f
