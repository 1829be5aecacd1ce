"""The `robomill` command: init, manifest, check, import.

The raw folders are generated here (small contract files: a 10 kHz force record, a profile,
a tracker run, an impact hit); importers are a fake module registered for the test, so that
the command's own behaviour (staging, atomicity, manifest merge) is tested independently of
the format importers.
"""

from __future__ import annotations

import argparse
import re
import shutil
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import tree_digest

from robomill.cli import main

BIN = Path(sys.executable).parent
LINE = re.compile(r"^\S+: .+: .+$")  # file: where: problem (expected ...)


# ---- a small raw folder ---------------------------------------------------------------------
def write_csv(path: Path, columns: dict[str, np.ndarray], fmt: str = "%.9g") -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    data = np.column_stack(list(columns.values()))
    np.savetxt(path, data, delimiter=",", header=",".join(columns), comments="", fmt=fmt)
    return path


def make_raw(raw: Path) -> Path:
    """A contract raw folder without manifest: one cut's force (10 kHz), profile, a tracker
    run (815 Hz) and one impact hit (5 kHz)."""
    t = np.arange(2000) / 10_000.0
    rng = np.random.default_rng(0)
    write_csv(raw / "forces/s1_g1_px.csv", {"t_s": t, "Fx_N": rng.normal(size=t.size),
                                           "Fy_N": 5 + rng.normal(size=t.size),
                                           "Fz_N": rng.normal(size=t.size)})
    x = np.arange(400) * 0.01
    write_csv(raw / "profiles/s1_g1_px.csv", {"x_mm": x, "z_um": np.sin(2 * np.pi * 0.5 * x)})
    tt = np.arange(1000) / 815.0
    write_csv(raw / "tracker/px_f2.csv", {"t_s": tt, "x_mm": 600 + 2.0 * tt,
                                         "y_mm": np.zeros_like(tt), "z_mm": 200 + 0 * tt})
    th = np.arange(256) / 5000.0
    write_csv(raw / "impact/hitX_1.csv", {"t_s": th, "force_N": np.exp(-th * 1e3),
                                         "ax_ms2": np.sin(th * 500), "ay_ms2": 0 * th,
                                         "az_ms2": 0 * th})
    return raw


def complete_manifest(raw: Path) -> dict:
    """Run `robomill manifest`, then fill in what it could not infer (as a user would)."""
    assert main(["manifest", str(raw)]) == 0
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    m["experiment"] = {"spindle_rpm": 6000, "flutes": 2, "tool_diameter_mm": 6.0,
                       "cut_length_mm": 40.0}
    for c in m["cuts"]:
        c.update(feed_mm_s=2.0, depth_mm=0.25)
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    return m


# ---- the command itself -----------------------------------------------------------------------
@pytest.mark.parametrize("verb", ["init", "import", "manifest", "check"])
def test_every_verb_has_help_through_the_console_script_and_python_m(verb):
    for cmd in ([str(BIN / "robomill")], [sys.executable, "-m", "robomill"]):
        proc = subprocess.run([*cmd, verb, "--help"], capture_output=True, text=True,
                              timeout=60)
        assert proc.returncode == 0, proc.stderr
        assert f"robomill {verb}" in proc.stdout
    if verb == "import":
        for fmt in ("dynoware", "tdms", "uff", "spatialanalyzer", "faro", "smats", "x3p"):
            assert fmt in proc.stdout


def test_no_verb_is_a_usage_error(capsys):
    with pytest.raises(SystemExit) as exc:
        main([])
    assert exc.value.code == 2


# ---- init ---------------------------------------------------------------------------------------
def test_init_makes_the_skeleton_and_keeps_existing_files(tmp_path, capsys):
    raw = tmp_path / "raw"
    assert main(["init", str(raw)]) == 0
    for d in ("profiles", "forces", "tracker", "impact", "ctrack", "stiffness"):
        assert (raw / d).is_dir()
    manifest = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert set(manifest) == {"experiment", "cuts", "files"}
    assert (raw / "manifest.yaml").read_text().startswith("# manifest.yaml")
    cell = yaml.safe_load((raw / "cell.yaml").read_text())
    assert set(cell) == {"robot", "q_home_deg", "tool_rotation", "transmissions"}
    assert set(cell["robot"]) == {"name", "convention", "length_unit", "angle_unit", "joints",
                                  "tool"}
    assert set(cell["transmissions"][0]) == {"joint", "stage", "rev_per_joint_rev", "teeth"}
    assert "base_from_instrument:" in (raw / "cell.yaml").read_text()  # commented option
    (raw / "cell.yaml").write_text("# mine\n")
    assert main(["init", str(raw)]) == 0
    assert (raw / "cell.yaml").read_text() == "# mine\n"
    assert "exists, kept" in capsys.readouterr().out


# ---- manifest -----------------------------------------------------------------------------------
def test_manifest_infers_kind_metadata_rate_and_sha256(tmp_path, capsys):
    from robomill.io.hashing import sha256_file

    raw = make_raw(tmp_path / "raw")
    (raw / "impact/hammer.uff").write_text("    -1\n")  # a native export: not listed
    assert main(["manifest", str(raw)]) == 0
    out = capsys.readouterr().out
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    files = {f["path"]: f for f in m["files"]}
    assert set(files) == {"forces/s1_g1_px.csv", "profiles/s1_g1_px.csv", "tracker/px_f2.csv",
                          "impact/hitX_1.csv"}
    assert files["forces/s1_g1_px.csv"] | {} == {
        "path": "forces/s1_g1_px.csv", "kind": "force", "cut": "s1_g1_px", "fs_hz": 10_000.0,
        "sha256": sha256_file(raw / "forces/s1_g1_px.csv")}
    assert files["tracker/px_f2.csv"]["fs_hz"] == 815.0
    assert (files["tracker/px_f2.csv"]["direction"], files["tracker/px_f2.csv"]["feed_mm_s"]
            ) == ("px", 2.0)
    assert (files["impact/hitX_1.csv"]["direction"], files["impact/hitX_1.csv"]["hit"]) == (
        "X", 1)
    assert m["cuts"] == [{"id": "s1_g1_px", "set": 1, "segment": 1, "direction": "px",
                          "feed_mm_s": None, "depth_mm": None}]
    # what it could not infer is listed
    assert "could not infer" in out
    assert "experiment.spindle_rpm not inferred" in out
    assert "cuts[0] (s1_g1_px): feed_mm_s not inferred" in out
    assert "impact/hammer.uff: native uff export" in out and "robomill import uff" in out


def test_manifest_lists_a_real_uff_in_impact_as_a_contract_file(tmp_path, capsys):
    """UFF 58 in impact/ is what `robomill import uff` writes: `robomill manifest` must list
    it (kind impact, its content), not ask for it to be imported again."""
    raw = make_raw(tmp_path / "raw")
    real = Path(__file__).parent / "data/real/uff/pyuff_measurement_roving_hammer.uff"
    shutil.copyfile(real, raw / "impact/beam.uff")
    assert main(["manifest", str(raw)]) == 0
    out = capsys.readouterr().out
    files = {f["path"]: f for f in yaml.safe_load((raw / "manifest.yaml").read_text())["files"]}
    assert files["impact/beam.uff"]["kind"] == "impact"
    assert files["impact/beam.uff"]["uff_content"] == "frf"
    assert "impact/beam.uff: native" not in out


def test_manifest_keeps_what_the_user_wrote(tmp_path, capsys):
    raw = make_raw(tmp_path / "raw")
    complete_manifest(raw)
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    force = next(f for f in m["files"] if f["kind"] == "force")
    force["fs_hz"] = 9_999.0  # the user knows better (say): kept, the disagreement reported
    force["note"] = "dynamometer 9257B"
    m["operator"] = "me"
    text = "# my comments\n# second line\n" + yaml.safe_dump(m, sort_keys=False)
    (raw / "manifest.yaml").write_text(text)
    write_csv(raw / "profiles/s1_g2_py.csv", {"x_mm": np.arange(100) * 0.01,
                                             "z_um": np.zeros(100)})
    assert main(["manifest", str(raw)]) == 0
    out = capsys.readouterr().out
    new_text = (raw / "manifest.yaml").read_text()
    assert new_text.startswith("# my comments\n# second line\n")
    new = yaml.safe_load(new_text)
    assert new["experiment"] == m["experiment"] and new["operator"] == "me"
    force = next(f for f in new["files"] if f["kind"] == "force")
    assert force["fs_hz"] == 9_999.0 and force["note"] == "dynamometer 9257B"
    assert "fs_hz: manifest says 9999.0, the file suggests 10000.0" in out
    assert [c["id"] for c in new["cuts"]] == ["s1_g1_px", "s1_g2_py"]
    assert new["cuts"][0]["feed_mm_s"] == 2.0  # kept
    assert "profiles/s1_g2_py.csv: added as profile" in out
    # a second run changes nothing
    before = (raw / "manifest.yaml").read_text()
    assert main(["manifest", str(raw)]) == 0
    assert (raw / "manifest.yaml").read_text() == before


def test_manifest_refuses_to_rewrite_invalid_yaml(tmp_path, capsys):
    raw = make_raw(tmp_path / "raw")
    (raw / "manifest.yaml").write_text("files: [\n")
    assert main(["manifest", str(raw)]) == 1
    assert (raw / "manifest.yaml").read_text() == "files: [\n"
    assert "not valid YAML" in capsys.readouterr().out


# ---- check --------------------------------------------------------------------------------------
def test_check_passes_a_good_folder(tmp_path, capsys):
    raw = make_raw(tmp_path / "raw")
    complete_manifest(raw)
    capsys.readouterr()
    assert main(["check", str(raw)]) == 0
    out = capsys.readouterr().out
    assert "0 problem(s)" in out


def test_check_reads_uff_impact_files_with_the_uff_readers(tmp_path, capsys):
    """A UFF 58 file in impact/ is read as the modal rules read it, not as a hit CSV; a
    UFF that is no impact data is one problem naming the file and the field."""
    raw = make_raw(tmp_path / "raw")
    uff = Path(__file__).parent / "data/real/uff"
    shutil.copyfile(uff / "pyuff_measurement_roving_hammer.uff", raw / "impact/beam.uff")
    complete_manifest(raw)
    capsys.readouterr()
    assert main(["check", str(raw)]) == 0, capsys.readouterr().out
    shutil.copyfile(uff / "pyuff_catman_time_history.uff", raw / "impact/beam.uff")
    assert main(["manifest", str(raw)]) == 0  # the user re-lists (new sha256)
    capsys.readouterr()
    assert main(["check", str(raw)]) == 1
    out = capsys.readouterr().out
    assert "impact/beam.uff" in out and "column 't_s'" not in out
    assert "1 problem(s)" in out


def test_check_reports_every_planted_problem_one_line_each(tmp_path, capsys):
    raw = make_raw(tmp_path / "raw")
    m = complete_manifest(raw)
    del m["experiment"]["flutes"]                                   # 1 experiment key
    m["cuts"].append({"id": "s1_g9_zz", "set": 1, "segment": 9, "direction": "zz",
                      "feed_mm_s": 1.0, "depth_mm": 0.25})           # 2 unknown direction
    files = {f["path"]: f for f in m["files"]}
    files["tracker/px_f2.csv"]["fs_hz"] = 800.0                      # 3 wrong rate
    files["impact/hitX_1.csv"]["kind"] = "hammer"                    # 4 unknown kind
    m["files"].append({"path": "forces/s1_g2_px.csv", "kind": "force", "cut": "s1_g1_px",
                       "fs_hz": 1e4, "sha256": "0" * 64})            # 5 listed, absent
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m, sort_keys=False))
    with open(raw / "profiles/s1_g1_px.csv", "a") as fh:            # 6 sha256 changed
        fh.write("4.0,0.0\n")
    write_csv(raw / "forces/extra.csv", {"t_s": np.arange(3.0)})    # 7 unlisted
    before = tree_digest(raw)
    capsys.readouterr()
    assert main(["check", str(raw), "--quiet"]) == 1
    lines = capsys.readouterr().out.splitlines()
    assert len(lines) == 7, lines
    for line in lines:
        assert LINE.match(line), line
    text = "\n".join(lines)
    m_path = str(raw / "manifest.yaml")
    expected = [
        (m_path, "experiment", "key 'flutes' is missing"),
        (m_path, "cuts[1].direction", "direction 'zz' is unknown"),
        (str(raw / "tracker/px_f2.csv"), "t_s", "(from the manifest)"),
        (m_path, f"files[{list(files).index('impact/hitX_1.csv')}].kind",
         "unknown kind 'hammer'"),
        (str(raw / "forces/s1_g2_px.csv"), "files[path=forces/s1_g2_px.csv]",
         "does not exist"),
        (str(raw / "profiles/s1_g1_px.csv"), "sha256", "the manifest says"),
        (str(raw / "forces/extra.csv"), "manifest.yaml: files", "not listed"),
    ]
    for file, where, problem in expected:
        assert any(line.startswith(file + ":") and where in line and problem in line
                   for line in lines), (file, where, problem, text)
    assert "(expected" in text
    assert tree_digest(raw) == before  # check writes nothing


def test_check_without_manifest_and_on_a_missing_folder(tmp_path, capsys):
    raw = make_raw(tmp_path / "raw")
    assert main(["check", str(raw)]) == 1
    assert "manifest does not exist" in capsys.readouterr().out
    assert main(["check", str(tmp_path / "nowhere")]) == 1
    assert "not a folder" in capsys.readouterr().out


def test_check_notes_cell_file_without_reader_or_checks_it(tmp_path, capsys):
    raw = make_raw(tmp_path / "raw")
    complete_manifest(raw)
    assert main(["init", str(raw)]) == 0  # adds cell.yaml, keeps the manifest
    capsys.readouterr()
    code = main(["check", str(raw)])
    out = capsys.readouterr().out
    try:
        import robomill.io.cell  # noqa: F401
    except ImportError:
        assert code == 0 and "cell.yaml: not checked" in out
    else:
        assert "cell.yaml" not in out or code == 1


# ---- import -------------------------------------------------------------------------------------
FAKE = '''
"""A fake importer for the tests: each source line 't,fx,fy,fz' -> a force CSV."""
from pathlib import Path

from robomill.errors import RawDataError

FORMAT = "fake"
KIND = "force"
DESCRIPTION = "test importer (text force records)"


def add_arguments(parser):
    parser.add_argument("--fs-hz", type=float, default=1000.0)


def convert(sources, staging, args):
    out = []
    for i, src in enumerate(sources):
        text = Path(src).read_text()
        if "BAD" in text:
            raise RawDataError(src, "the word BAD", where="line 1", expected="numbers")
        cut = args.cut or f"s1_g{i + 1}_px"
        rel = f"forces/{cut}.csv"
        (staging / "forces").mkdir(exist_ok=True)
        (staging / rel).write_text("t_s,Fx_N,Fy_N,Fz_N\\n" + text)
        out.append({"path": rel, "kind": "force", "cut": cut, "fs_hz": args.fs_hz})
    return out
'''


@pytest.fixture
def fake_registry(tmp_path, monkeypatch):
    mod_dir = tmp_path / "mods"
    mod_dir.mkdir()
    (mod_dir / "fake_importer_21.py").write_text(textwrap.dedent(FAKE))
    (mod_dir / "broken_importer_21.py").write_text('FORMAT = "broken"\n')
    (mod_dir / "needsdep_importer_21.py").write_text("import nosuchpackage_21  # noqa\n")
    monkeypatch.syspath_prepend(str(mod_dir))
    import robomill.importers as importers

    monkeypatch.setattr(importers, "FORMATS", {"fake": "fake_importer_21",
                                               "broken": "broken_importer_21",
                                               "needsdep": "needsdep_importer_21",
                                               "absent": "robomill.importers.absent_21"})
    return importers


def _sources(tmp_path, *texts):
    out = []
    for i, text in enumerate(texts):
        p = tmp_path / f"src{i}.txt"
        p.write_text(text)
        out.append(str(p))
    return out


ROWS = "0.0,1,2,3\n0.001,1,2,3\n"


def test_import_moves_files_and_merges_the_manifest(tmp_path, fake_registry, capsys):
    from robomill.io.hashing import sha256_file

    raw = tmp_path / "raw"
    main(["init", str(raw)])
    srcs = _sources(tmp_path, ROWS, ROWS)
    assert main(["import", "fake", *srcs, "--to", str(raw), "--fs-hz", "1000"]) == 0
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert (raw / "manifest.yaml").read_text().startswith("# manifest.yaml")  # header kept
    assert [f["path"] for f in m["files"]] == ["forces/s1_g1_px.csv", "forces/s1_g2_px.csv"]
    for f in m["files"]:
        assert f["sha256"] == sha256_file(raw / f["path"])
        assert f["fs_hz"] == 1000.0 and f["kind"] == "force"
    assert "imported" in capsys.readouterr().out
    # the new cuts are listed with feed and depth to fill in (robomill manifest lists them)
    assert m["cuts"] == [{"id": f"s1_g{i}_px", "set": 1, "segment": i, "direction": "px",
                          "feed_mm_s": None, "depth_mm": None} for i in (1, 2)]
    assert not list(raw.rglob(".*importing")) and not list(raw.rglob(".*replaced"))


def test_import_failure_writes_nothing(tmp_path, fake_registry, capsys):
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    before = tree_digest(raw)
    srcs = _sources(tmp_path, ROWS, "BAD\n")
    assert main(["import", "fake", *srcs, "--to", str(raw)]) == 1
    out = capsys.readouterr().out
    assert f"{srcs[1]}: line 1: the word BAD (expected numbers)" in out
    assert "nothing was written" in out
    assert tree_digest(raw) == before
    # a missing source: nothing either
    assert main(["import", "fake", str(tmp_path / "nope.txt"), "--to", str(raw)]) == 1
    assert "source file does not exist" in capsys.readouterr().out
    assert tree_digest(raw) == before


def test_import_never_overwrites_silently(tmp_path, fake_registry, capsys):
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    src = _sources(tmp_path, ROWS)
    assert main(["import", "fake", *src, "--to", str(raw), "--cut", "s1_g1_px"]) == 0
    before = tree_digest(raw)
    src2 = _sources(tmp_path, ROWS + "0.002,9,9,9\n")
    assert main(["import", "fake", *src2, "--to", str(raw), "--cut", "s1_g1_px"]) == 1
    assert "exists already" in capsys.readouterr().out
    assert tree_digest(raw) == before
    assert main(["import", "fake", *src2, "--to", str(raw), "--cut", "s1_g1_px",
                 "--overwrite"]) == 0
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    assert len(m["files"]) == 1
    assert (raw / "forces/s1_g1_px.csv").read_text().endswith("0.002,9,9,9\n")


def test_import_undoes_a_half_done_move(tmp_path, fake_registry, monkeypatch, capsys):
    import shutil

    import robomill.cli.importing as importing

    raw = tmp_path / "raw"
    main(["init", str(raw)])
    before = tree_digest(raw)
    calls = []
    real_copy = shutil.copy2

    def failing_copy(src, dst, *a, **k):
        calls.append(dst)
        if len(calls) == 2:
            raise OSError("disk full")
        return real_copy(src, dst, *a, **k)

    monkeypatch.setattr(importing.shutil, "copy2", failing_copy)
    srcs = _sources(tmp_path, ROWS, ROWS)
    assert main(["import", "fake", *srcs, "--to", str(raw)]) == 1
    assert "disk full" in capsys.readouterr().out
    assert tree_digest(raw) == before


def test_import_refuses_an_entry_already_listed(tmp_path, fake_registry, capsys):
    raw = tmp_path / "raw"
    main(["init", str(raw)])
    m = yaml.safe_load((raw / "manifest.yaml").read_text())
    m["files"] = [{"path": "forces/s1_g1_px.csv", "kind": "force", "cut": "s1_g1_px",
                   "fs_hz": 1.0, "sha256": "0" * 64}]
    (raw / "manifest.yaml").write_text(yaml.safe_dump(m))
    before = tree_digest(raw)
    assert main(["import", "fake", *_sources(tmp_path, ROWS), "--to", str(raw)]) == 1
    assert "lists forces/s1_g1_px.csv already" in capsys.readouterr().out
    assert tree_digest(raw) == before


@pytest.mark.parametrize(("fmt", "message"), [
    ("nosuch", "unknown format 'nosuch' (expected one of fake, broken, needsdep, absent)"),
    ("needsdep", "needs the Python package 'nosuchpackage_21', which is not installed"),
    ("absent", "module robomill.importers.absent_21 is not part of this robomill"),
    ("broken", "lacks DESCRIPTION, add_arguments, convert"),
])
def test_import_bad_format_is_a_clear_usage_error(tmp_path, fake_registry, capsys, fmt,
                                                  message):
    assert main(["import", fmt, "x", "--to", str(tmp_path / "raw")]) == 2
    assert message in capsys.readouterr().out
    assert not (tmp_path / "raw").exists()


def test_import_help_lists_formats_with_their_state(fake_registry, capsys):
    assert main(["import", "--help"]) == 0
    out = capsys.readouterr().out
    assert "fake" in out and "test importer (text force records)" in out
    assert "absent" in out and "(unavailable:" in out


def test_import_format_help_shows_its_options(fake_registry, capsys):
    assert main(["import", "fake", "--help"]) == 0
    out = capsys.readouterr().out
    assert "--fs-hz" in out and "--to DIR" in out and "--cut ID" in out


def test_importer_returning_bad_entries_writes_nothing(tmp_path, fake_registry, capsys):
    from robomill.cli.importing import ImportFailed, import_files

    class Bad:
        __name__ = "bad"

        @staticmethod
        def convert(sources, staging, args):
            return [{"path": "../outside.csv", "kind": "force"}]

    raw = tmp_path / "raw"
    raw.mkdir()
    with pytest.raises(ImportFailed, match="not written under the staging folder"):
        import_files(Bad, [Path(_sources(tmp_path, ROWS)[0])], raw,
                     argparse.Namespace(cut=None))
    assert list(raw.iterdir()) == []


def test_every_registered_importer_module_exists():
    import importlib.util

    from robomill.importers import FORMATS, INTERFACE, load_importer

    missing = [m for m in FORMATS.values() if importlib.util.find_spec(m) is None]
    assert missing == []
    for fmt in FORMATS:
        module = load_importer(fmt)
        assert all(hasattr(module, a) for a in INTERFACE)
        assert module.FORMAT == fmt
