"""Many files at once, the design read from their names (issue 32.5): ``robomill import
FORMAT SRC... --cut-pattern REGEX`` fills the manifest's ``cuts:``; without a pattern every
new cut id is added with its keys ``null`` and ``robomill manifest`` lists them; tracker runs
along −X or any angle (``--direction mx``, ``--direction-deg``).

The truth is the design each file was generated with (the dictionary ``DESIGN`` below), not
what the pattern parsed.
"""

from __future__ import annotations

import itertools
import re
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import tree_digest

from robomill.cli import main

PATTERN = (r"(?P<cut>\d+)-n(?P<spindle_rpm>\d+)f(?P<feed_mm_min>\d+)ap(?P<depth_mm>[\d.]+)"
           r"ae(?P<width_pct>\d+)")
FARO = Path(__file__).parent / "data" / "constructed" / "faro" / "px_f1.csv"


def dynoware_text(n_rpm: float, rows: int = 400, fs_hz: float = 10_000.0) -> str:
    """A DynoWare 3.2 ASCII export (tab separated) of a 2-flute cut at ``n_rpm``."""
    t = np.arange(rows) / fs_hz
    phase = 2 * np.pi * 2 * n_rpm / 60.0 * t
    fx, fy, fz = -(40 + 25 * np.cos(phase)), -(-15 + 20 * np.sin(phase)), -(8 + 0 * t)
    head = ["Kistler DynoWare\tVersion 3.2.5.0", f"Sampling rate:\t{fs_hz:g}\tHz",
            f"Number of samples:\t{rows}", "", "Time\tFx\tFy\tFz", "s\tN\tN\tN"]
    body = [f"{a:.4f}\t{b:.3f}\t{c:.3f}\t{d:.3f}" for a, b, c, d in zip(t, fx, fy, fz,
                                                                        strict=True)]
    return "\n".join(head + body) + "\n"


def lab_files(folder: Path) -> dict[str, dict]:
    """45 force exports named ``<k>-n<rpm>f<mm/min>ap<mm>ae<%>.txt``; returns the design of
    each cut id (the truth)."""
    folder.mkdir(parents=True, exist_ok=True)
    design = {}
    grid = itertools.product((6000, 8000, 12000), (300, 450, 900),
                             ((0.5, 25), (1, 50), (1.5, 100), (2, 100), (3, 25)))
    for k, (n, f, (ap, ae)) in enumerate(grid, start=1):
        name = f"{k}-n{n}f{f}ap{ap:g}ae{ae}.txt"
        (folder / name).write_text(dynoware_text(n))
        design[str(k)] = {"spindle_rpm": n, "feed_mm_s": f / 60.0, "depth_mm": ap,
                          "radial_immersion": ae / 100.0}
    return design


def test_45_force_files_with_design_names_take_four_commands_to_a_valid_manifest(
        tmp_path, capsys):
    """init --experiment, import --cut-pattern, manifest, check (then snakemake: five
    commands): every cut's design filled from its name (and the direction, which the names do
    not carry, from --design); the experiment block holds the lab's tool, given once to
    init."""
    truth = lab_files(tmp_path / "exports")
    raw = tmp_path / "raw"
    assert main(["init", str(raw), "--experiment", "spindle_rpm=6000", "--experiment",
                 "flutes=2", "--experiment", "tool_diameter_mm=10",
                 "--experiment", "cut_length_mm=40"]) == 0  # the lab's tool, written once
    sources = sorted(str(p) for p in (tmp_path / "exports").iterdir())
    assert main(["import", "dynoware", *sources, "--to", str(raw),
                 "--cut-pattern", PATTERN, "--design", "direction=px"]) == 0
    out = capsys.readouterr().out
    assert "manifest.yaml: cut 6 added (spindle_rpm=6000, feed_mm_s=7.5, depth_mm=0.5, " \
           "radial_immersion=0.25, direction=px)" in out
    assert main(["manifest", str(raw)]) == 0
    out = capsys.readouterr().out
    assert "could not infer" not in out, out
    assert main(["check", str(raw)]) == 0, capsys.readouterr().out
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    cuts = {c["id"]: c for c in m["cuts"]}
    assert set(cuts) == set(truth) and sum(f["kind"] == "force" for f in m["files"]) == 45
    for cid, want in truth.items():
        got = cuts[cid]
        assert got["direction"] == "px"  # --design: what the names do not carry
        for key, value in want.items():
            assert got[key] == pytest.approx(value, rel=1e-12), (cid, key)
    assert {f["path"]: f.get("cut") for f in m["files"]}["forces/6.csv"] == "6"
    assert m["experiment"] == {"spindle_rpm": 6000, "flutes": 2, "tool_diameter_mm": 10,
                               "cut_length_mm": 40.0}


@pytest.mark.parametrize("item, expected", [
    ("flutes=2.5", "(expected an integer)"),
    ("feed_mm_s=2", "(expected keys among spindle_rpm, flutes, tool_diameter_mm, "
                    "cut_length_mm)"),
    ("tool_diameter_mm=ten", "(expected a number [mm])"),
    ("spindle_rpm", "is not KEY=VALUE"),
])
def test_init_experiment_values_are_checked_in_one_line(tmp_path, capsys, item, expected):
    raw = tmp_path / "raw"
    assert main(["init", str(raw), "--experiment", item]) == 1
    out = capsys.readouterr().out
    assert expected in out and out.count("\n") == 1 and "Traceback" not in out
    assert not raw.exists()  # refused before anything is made


def test_init_experiment_updates_an_existing_manifest_and_keeps_the_rest(tmp_path):
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    m["cuts"] = [{"id": "a", "feed_mm_s": 1.0, "depth_mm": 0.5, "direction": "px"}]
    header = (raw / "manifest.yaml").read_text().split("\nexperiment:")[0] + "\n"
    (raw / "manifest.yaml").write_text(header + yaml.safe_dump(m, sort_keys=False))
    assert main(["init", str(raw), "--experiment", "flutes=3"]) == 0
    text = (raw / "manifest.yaml").read_text()
    assert text.startswith(header)  # the template's comments kept
    new = yaml.safe_load(text)
    assert new["experiment"]["flutes"] == 3 and new["experiment"]["spindle_rpm"] is None
    assert new["cuts"] == m["cuts"]


def test_without_a_pattern_every_new_cut_is_listed_with_null_keys(tmp_path, capsys):
    exports = tmp_path / "exports"
    exports.mkdir()
    (exports / "run_a.txt").write_text(dynoware_text(6000))
    (exports / "s2_g1_py.txt").write_text(dynoware_text(6000))
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    assert main(["import", "dynoware", str(exports / "run_a.txt"),
                 str(exports / "s2_g1_py.txt"), "--to", str(raw)]) == 0
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert m["cuts"] == [
        {"id": "run_a", "direction": None, "feed_mm_s": None, "depth_mm": None},
        {"id": "s2_g1_py", "set": 2, "segment": 1, "direction": "py", "feed_mm_s": None,
         "depth_mm": None}]
    capsys.readouterr()
    assert main(["manifest", str(raw)]) == 0
    out = capsys.readouterr().out
    for line in ("cuts[0] (run_a): feed_mm_s not inferred", "cuts[0] (run_a): depth_mm not "
                 "inferred", "cuts[0] (run_a): direction not inferred (write direction px, "
                 "mx, py or my, or direction_deg)", "cuts[1] (s2_g1_py): depth_mm not inferred"):
        assert line in out, out
    assert "cuts[1] (s2_g1_py): direction" not in out


def test_a_partial_pattern_leaves_the_other_keys_null_and_listed(tmp_path, capsys):
    exports = tmp_path / "exports"
    exports.mkdir()
    (exports / "slot_mx_n9000.txt").write_text(dynoware_text(9000))
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    assert main(["import", "dynoware", str(exports / "slot_mx_n9000.txt"), "--to", str(raw),
                 "--cut-pattern", r"(?P<milling>slot)_(?P<direction>[pm][xy])_n(?P<spindle_rpm>"
                 r"\d+)"]) == 0
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert m["cuts"] == [{"id": "slot_mx_n9000", "direction": "mx", "feed_mm_s": None,
                          "depth_mm": None, "milling": "slot", "spindle_rpm": 9000}]
    capsys.readouterr()
    main(["manifest", str(raw)])
    out = capsys.readouterr().out
    assert "(slot_mx_n9000): feed_mm_s not inferred" in out
    assert "(slot_mx_n9000): direction" not in out


@pytest.mark.parametrize("names, pattern, message", [
    (["6-n6000f300ap3ae25", "7-n6000f300ap3"], PATTERN,
     "{src}/7-n6000f300ap3.txt: option --cut-pattern: file name '7-n6000f300ap3' does not "
     "match --cut-pattern '" + PATTERN + "' (expected a pattern matching every source's name"),
    (["6-n6000"], r"(?P<cut>\d+)-n(?P<rpm>\d+)",
     "--cut-pattern: option --cut-pattern: --cut-pattern group(s) rpm unknown (expected "
     "group names among cut, set, segment, flutes, feed_mm_s, feed_mm_min,"),
    (["6-n6000"], r"(?P<cut>\d+)-n(?P<spindle_rpm>\d+",
     r"--cut-pattern: option --cut-pattern: --cut-pattern '(?P<cut>\d+)-n(?P<spindle_rpm>\d+' "
     "is not a regular expression (missing ), unterminated subpattern"),
    (["6-dirqx"], r"(?P<cut>\d+)-dir(?P<direction>\w+)",
     "{src}/6-dirqx.txt: option --cut-pattern: group direction matched 'qx' (expected one of "
     "px, py, my, mx)"),
    (["6-f12", "6-f15"], r"(?P<cut>\d+)-f(?P<feed_mm_s>\d+)",
     "{src}/6-f15.txt: option --cut-pattern: cut 6 gets {'feed_mm_s': 15}, {src}/6-f12.txt "
     "gave it {'feed_mm_s': 12} (expected one design per cut)"),
    (["6-f12"], r"(?P<feed_mm_s>\d+)|(?P<feed_mm_min>x)",
     "--cut-pattern groups feed_mm_s and feed_mm_min both give feed_mm_s"),
])
def test_bad_patterns_are_one_line_and_write_nothing(tmp_path, capsys, names, pattern,
                                                     message):
    exports = tmp_path / "exports"
    exports.mkdir()
    for n in names:
        (exports / f"{n}.txt").write_text(dynoware_text(6000))
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    before = tree_digest(raw)
    capsys.readouterr()
    assert main(["import", "dynoware", *(str(exports / f"{n}.txt") for n in names), "--to",
                 str(raw), "--cut-pattern", pattern]) == 1
    out = capsys.readouterr().out
    assert message.replace("{src}", str(exports)) in out, out
    assert out.splitlines()[-1] == f"{raw}: nothing was written"
    assert len(out.splitlines()) == 2
    assert tree_digest(raw) == before


def test_a_name_that_disagrees_with_the_manifest_is_refused_unless_overwrite(tmp_path,
                                                                             capsys):
    exports = tmp_path / "exports"
    exports.mkdir()
    (exports / "6-n6000f300ap3ae25.txt").write_text(dynoware_text(6000))
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    m["cuts"] = [{"id": "6", "direction": "px", "feed_mm_s": 5.0, "depth_mm": 2.0}]
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    before = tree_digest(raw)
    args = ["import", "dynoware", str(exports / "6-n6000f300ap3ae25.txt"), "--to", str(raw),
            "--cut-pattern", PATTERN]
    capsys.readouterr()
    assert main(args) == 1
    out = capsys.readouterr().out
    assert (f"{raw / 'manifest.yaml'}: cuts[0] (6) has depth_mm 2.0, the file name gives 3 "
            "(expected the same; pass --overwrite to replace it)") in out
    assert tree_digest(raw) == before
    assert main([*args, "--overwrite"]) == 0
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert m["cuts"] == [{"id": "6", "direction": "px", "feed_mm_s": 5.0, "depth_mm": 3,
                          "spindle_rpm": 6000, "radial_immersion": 0.25}]


@pytest.mark.parametrize("argv, path, keys", [
    (["--direction", "mx"], "tracker/mx_f1.csv", {"direction": "mx"}),
    (["--direction-deg", "45"], "tracker/d45_f1.csv", {"direction_deg": 45.0}),
])
def test_tracker_runs_along_minus_x_or_any_angle(tmp_path, capsys, argv, path, keys):
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    assert main(["import", "faro", str(FARO), "--to", str(raw), "--fs-hz", "815",
                 "--feed-mm-s", "1", *argv]) == 0, capsys.readouterr().out
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    entry = m["files"][0]
    assert entry["path"] == path and {k: entry[k] for k in keys} == keys
    assert "direction" not in entry or "direction_deg" not in entry
    # robomill manifest infers the same keys back from the file name
    from robomill.cli.layout import infer_file

    inferred = infer_file(raw, raw / path).entry
    assert {k: inferred[k] for k in keys} == keys and inferred["feed_mm_s"] == 1.0


def test_tracker_needs_one_direction(tmp_path, capsys):
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    capsys.readouterr()
    assert main(["import", "faro", str(FARO), "--to", str(raw), "--fs-hz", "815",
                 "--feed-mm-s", "1", "--direction", "px", "--direction-deg", "0"]) == 1
    assert re.search(r"option --direction: both --direction and --direction-deg",
                     capsys.readouterr().out)


def test_import_help_describes_any_design(capsys):
    assert main(["import", "--help"]) == 0
    out = " ".join(capsys.readouterr().out.split())
    for words in ("Cut ids are free", "direction px, mx, py, my, or direction_deg",
                  "spindle_rpm, flutes, tool_diameter_mm, radial_immersion",
                  "milling (slot, up, down)"):
        assert words in out
    for fmt in ("dynoware", "tdms", "smats", "x3p", "faro", "spatialanalyzer", "uff"):
        assert main(["import", fmt, "--help"]) == 0
        out = " ".join(capsys.readouterr().out.split())
        assert "--cut-pattern REGEX" in out and "Cut ids are free" in out
        if fmt in ("faro", "spatialanalyzer"):
            assert "{px,mx,py,my}" in out and "--direction-deg" in out


def test_the_manifest_template_describes_any_design(tmp_path):
    main(["init", str(tmp_path / "raw")])
    text = (tmp_path / "raw" / "manifest.yaml").read_text()
    for words in ("any id", "mx", "direction_deg", "spindle_rpm", "radial_immersion",
                  "milling", "--cut-pattern"):
        assert words in text
    assert yaml.safe_load(text)["cuts"] == []
