"""A lab's folder with a dynamometer record and recordings of the same cut: the pipeline writes
results/chatter/verdicts.csv with one row per record, the force and the recordings compared,
and a recording that cannot be read gets one line while the rest is judged."""

import numpy as np
import pandas as pd
import pytest
import soundfile
import yaml
from conftest import REPO, run_snakemake

from robomill.cli import main
from robomill.io.hashing import sha256_file

pytestmark = [pytest.mark.pipeline]

FS_HZ = 10_000.0
RPM, FLUTES = 6000.0, 3  # spindle 100 Hz, tooth passing 300 Hz
CHATTER_HZ = 1234.5


def _signal(seconds=3.0, chatter=0.0, seed=0):
    t = np.arange(int(FS_HZ * seconds)) / FS_HZ
    x = sum(np.cos(2 * np.pi * 300.0 * k * t + k) / k for k in range(1, 8))
    x = x + chatter * np.sin(2 * np.pi * CHATTER_HZ * t)
    return t, x + 0.05 * np.random.default_rng(seed).standard_normal(t.size)


def test_verdicts_of_force_and_recordings(tmp_path, capsys):
    raw = tmp_path / "raw"
    for d in ("forces", "sound", "vibration"):
        (raw / d).mkdir(parents=True)
    t, fx = _signal(chatter=1.0)
    _, fy = _signal(chatter=0.5, seed=1)
    pd.DataFrame({"t_s": t, "Fx_N": 50 + 20 * fx, "Fy_N": 20 * fy, "Fz_N": 5 + fy}).to_csv(
        raw / "forces" / "c1.csv", index=False, float_format="%.7g")
    soundfile.write(raw / "sound" / "c1.flac", 0.05 * _signal(chatter=1.0, seed=2)[1], 10_000)
    soundfile.write(raw / "sound" / "c2.flac", 0.05 * _signal(seed=3)[1], 10_000)
    (raw / "sound" / "c2_broken.wav").write_bytes(b"RIFF\x00\x00not a wave")
    tv, a = _signal(seed=4)
    pd.DataFrame({"t_s": tv, "ax_m_s2": a}).to_csv(raw / "vibration" / "c2.csv", index=False,
                                                   float_format="%.7g")
    files = [("forces/c1.csv", "force", "c1", {"fs_hz": FS_HZ}),
             ("sound/c1.flac", "sound", "c1", {}), ("sound/c2.flac", "sound", "c2", {}),
             ("sound/c2_broken.wav", "sound", "c2", {}),
             ("vibration/c2.csv", "vibration", "c2", {})]
    manifest = {
        "experiment": {"spindle_rpm": RPM, "flutes": FLUTES, "tool_diameter_mm": 6.0,
                       "cut_length_mm": 10.0},
        "cuts": [{"id": c, "feed_mm_s": 1.0, "depth_mm": 1.0, "direction": "px"}
                 for c in ("c1", "c2")],
        "files": [{"path": p, "kind": k, "cut": c, **x, "sha256": sha256_file(raw / p)}
                  for p, k, c, x in files]}
    (raw / "manifest.yaml").write_text(yaml.safe_dump(manifest, sort_keys=False))
    assert main(["check", str(raw)]) == 1  # robomill check: the broken recording, one line
    problems = [ln for ln in capsys.readouterr().out.splitlines()
                if not ln.startswith("note:") and "problem(s)" not in ln]
    assert len(problems) == 1 and "c2_broken.wav" in problems[0]
    cfg = yaml.safe_load((REPO / ".test" / "config.yaml").read_text())
    cfg["data"] = {"source": "raw", "raw_dir": str(raw)}
    config = tmp_path / "config.yaml"
    config.write_text(yaml.safe_dump(cfg, sort_keys=False))
    work = tmp_path / "work"
    work.mkdir()
    done = run_snakemake(work, "-j1", "results/chatter/verdicts.csv", configfile=config)
    assert done.returncode == 0, done.stderr[-3000:]
    table = pd.read_csv(work / "results/chatter/verdicts.csv")
    assert list(table.columns[:5]) == ["cut", "verdict", "chatter_hz", "source", "evidence"]
    by = table.set_index("source")
    assert len(table) == 5
    for src in ("forces/c1.csv", "sound/c1.flac"):
        assert by.loc[src, "verdict"] == "chatter"
        assert by.loc[src, "chatter_hz"] == pytest.approx(CHATTER_HZ, abs=1.0)
    assert by.loc["sound/c2.flac", "verdict"] == "stable"
    assert by.loc["vibration/c2.csv", "verdict"] == "stable"
    assert by.loc["sound/c2_broken.wav", "verdict"] == "undetermined"
    assert "c2_broken.wav" in by.loc["sound/c2_broken.wav", "evidence"]
    found = yaml.safe_load((work / "results/chatter/verdict_findings.yaml").read_text())
    values = {f["key"]: f["value"] for f in found["findings"]}
    assert values["n_compared"] == 1 and values["n_agree"] == 1  # cut c1: force and sound
    log = (work / "results/logs/chatter/verdicts.log").read_text()
    assert "c2_broken.wav" in log
