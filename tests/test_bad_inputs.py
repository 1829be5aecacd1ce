"""The bad-input corpus: every malformed file raises RawDataError naming it.

Each case is ``(kind, file, call, message regex)``: ``file`` is relative to
``tests/data/bad`` and is the file the message must name; ``call`` picks the reader; the regex
must match the message (it names the row/column/key and what was found). Manifest cases are
folders (``manifest/<case>/``) copied to a temporary directory before they are checked, so the
corpus is never written to. ``docs/data-contract.md`` ("Every error, by kind") lists them.
"""

from __future__ import annotations

import re
import shutil
from pathlib import Path

import pytest

from robomill.io import RawDataError
from robomill.io.ctrack import READERS
from robomill.io.forces import read_forces
from robomill.io.impact import read_frf_uff, read_hit, read_hits_uff
from robomill.io.manifest import load_manifest
from robomill.io.profiles import read_profile
from robomill.io.recordings import read_sound, read_vibration
from robomill.io.robots import read_load_tests, read_robot_file
from robomill.io.tracker import read_tracker

BAD = Path(__file__).parent / "data" / "bad"

CALLS = {
    "profile": read_profile,
    "forces": lambda p: read_forces(p, 1000.0),  # manifest fs_hz = 1000 Hz
    "tracker": lambda p: read_tracker(p, fs_hz=815.0),  # manifest fs_hz = 815 Hz
    "hit": read_hit,
    "hit@5000": lambda p: read_hit(p, fs_hz=5000.0),  # the file is sampled at 10 kHz
    "uff": read_frf_uff,
    "uff_hits": read_hits_uff,
    **{f"ctrack:{t}": reader for t, reader in READERS.items()},
    "robot": read_robot_file,
    "load_tests": read_load_tests,
    "sound": read_sound,
    "vibration": read_vibration,
    "manifest": lambda p: load_manifest(p),
    "manifest+verify": lambda p: load_manifest(p).verify_all(),
}

NOT_NUM = r"value '{}' is not a number \(expected a finite number\)"
UNIT = r"header \(row 1\): column '{}' is missing; column '{}' is in unit '{}'"
TRUNC = r"row {}: row has \d+ fields, the header has \d+ \(truncated last row\?\)"

CASES = [
    # --- profiles/<cut>.csv: x_mm, z_um, >= 64 rows, x_mm uniform and increasing
    ("profile", "profile/empty.csv", "profile", r"file is empty"),
    ("profile", "profile/header_only.csv", "profile",
     r"header only, no data rows \(expected at least 64 data rows\)"),
    ("profile", "profile/missing_column.csv", "profile",
     r"header \(row 1\): column 'z_um' is missing \(expected columns x_mm, z_um\)"),
    ("profile", "profile/misspelt_column.csv", "profile", UNIT.format("z_um", "z_umm", "umm")),
    ("profile", "profile/semicolon_delimiter.csv", "profile",
     r"header \(row 1\): column 'x_mm' is missing"),
    ("profile", "profile/unit_x_m.csv", "profile", UNIT.format("x_mm", "x_m", "m")),
    ("profile", "profile/unit_z_mm.csv", "profile", UNIT.format("z_um", "z_mm", "mm")),
    ("profile", "profile/text_in_number.csv", "profile",
     r"row 4, column z_um: " + NOT_NUM.format("abc")),
    ("profile", "profile/nan.csv", "profile", r"row 7, column z_um: " + NOT_NUM.format("nan")),
    ("profile", "profile/inf.csv", "profile", r"row 9, column z_um: value 'inf' is not finite"),
    ("profile", "profile/truncated_last_row.csv", "profile", TRUNC.format(72)),
    ("profile", "profile/non_monotonic_x.csv", "profile",
     r"row 13, column x_mm: x_mm is not strictly increasing"),
    ("profile", "profile/non_uniform_x.csv", "profile",
     r"row 22, column x_mm: x_mm is not uniformly spaced: step 0.00175 instead of 0.00125"),
    ("profile", "profile/too_few_rows.csv", "profile",
     r"only 10 data rows \(expected at least 64 data rows\)"),
    # --- forces/<cut>.csv: t_s, Fx_N, Fy_N, Fz_N at fs_hz from the manifest
    ("forces", "forces/empty.csv", "forces", r"file is empty"),
    ("forces", "forces/header_only.csv", "forces", r"header only, no data rows"),
    ("forces", "forces/missing_column.csv", "forces",
     r"header \(row 1\): column 'Fz_N' is missing"),
    ("forces", "forces/misspelt_column.csv", "forces", UNIT.format("Fz_N", "Fz_n", "n")),
    ("forces", "forces/unit_t_ms.csv", "forces", UNIT.format("t_s", "t_ms", "ms")),
    ("forces", "forces/unit_Fz_kN.csv", "forces", UNIT.format("Fz_N", "Fz_kN", "kN")),
    ("forces", "forces/text_in_number.csv", "forces",
     r"row 5, column Fy_N: " + NOT_NUM.format("n/a")),
    ("forces", "forces/nan.csv", "forces", r"row 6, column Fx_N: " + NOT_NUM.format("NaN")),
    ("forces", "forces/inf.csv", "forces", r"row 4, column Fz_N: value '-inf' is not finite"),
    ("forces", "forces/truncated_last_row.csv", "forces", TRUNC.format(10)),
    ("forces", "forces/non_monotonic_t.csv", "forces",
     r"row 7, column t_s: t_s is not strictly increasing \(0.004 then 0.003\)"),
    ("forces", "forces/non_uniform_t.csv", "forces",
     r"row 8, column t_s: t_s step is 0.0015 s instead of 0.001 s"),
    ("forces", "forces/wrong_fs.csv", "forces",
     r"column t_s: sampling rate is 500 Hz .*expected fs_hz = 1000 Hz as the manifest says"),
    ("forces", "forces/too_few_rows.csv", "forces",
     r"only 1 data rows \(expected at least 2 data rows\)"),
    ("forces", "forces/unknown_type.txt", "forces", r"unknown file type '\.txt'"),
    # --- forces/<cut>.h5: datasets t_s, Fx_N, Fy_N, Fz_N at the root
    ("forces", "forces/empty.h5", "forces",
     r"file structure \(superblock.*not a readable HDF5 file.*0 bytes on disk"),
    ("forces", "forces/junk.h5", "forces", r"file structure .*not a readable HDF5 file"),
    ("forces", "forces/truncated.h5", "forces",
     r"file structure .*not a readable HDF5 file .*truncated file.*600 bytes on disk"),
    ("forces", "forces/missing_dataset.h5", "forces", r"file root: dataset 'Fy_N' is missing"),
    ("forces", "forces/unequal_lengths.h5", "forces",
     r"dataset Fz_N: dataset Fz_N has 5 samples, t_s has 8 \(truncated record\?\)"),
    ("forces", "forces/not_1d.h5", "forces", r"dataset Fx_N: 'Fx_N' is not a 1-D dataset"),
    ("forces", "forces/text_dataset.h5", "forces", r"dataset Fz_N: 'Fz_N' has dtype"),
    ("forces", "forces/too_few_samples.h5", "forces", r"dataset t_s: only 1 samples"),
    ("forces", "forces/attr_fs_mismatch.h5", "forces",
     r"attribute fs_hz: file attribute fs_hz = 2000 Hz \(expected fs_hz = 1000 Hz"),
    ("forces", "forces/nan_sample.h5", "forces",
     r"dataset Fx_N, sample 3: value nan is not finite"),
    ("forces", "forces/non_monotonic_t.h5", "forces",
     r"dataset t_s, sample 4: t_s is not strictly increasing"),
    ("forces", "forces/wrong_fs.h5", "forces", r"dataset t_s: sampling rate is 500 Hz"),
    # --- tracker/<dir>_f<feed>.csv: t_s, x_mm, y_mm, z_mm at fs_hz = 815
    ("tracker", "tracker/empty.csv", "tracker", r"file is empty"),
    ("tracker", "tracker/header_only.csv", "tracker", r"header only, no data rows"),
    ("tracker", "tracker/missing_column.csv", "tracker",
     r"header \(row 1\): column 'z_mm' is missing"),
    ("tracker", "tracker/unit_z_m.csv", "tracker", UNIT.format("z_mm", "z_m", "m")),
    ("tracker", "tracker/unit_t_ms.csv", "tracker", UNIT.format("t_s", "t_ms", "ms")),
    ("tracker", "tracker/text_in_number.csv", "tracker",
     r"row 11, column y_mm: " + NOT_NUM.format("lost")),
    ("tracker", "tracker/nan.csv", "tracker", r"row 14, column x_mm: " + NOT_NUM.format("nan")),
    ("tracker", "tracker/truncated_last_row.csv", "tracker", TRUNC.format(72)),
    ("tracker", "tracker/non_monotonic_t.csv", "tracker",
     r"row 32, column t_s: t_s is not strictly increasing"),
    ("tracker", "tracker/non_uniform_t.csv", "tracker",
     r"row 42, column t_s: t_s is not uniformly spaced"),
    ("tracker", "tracker/wrong_fs.csv", "tracker",
     r"column t_s: t_s spacing is 0.001 \(expected spacing 0.00122699 \(from the manifest\)"),
    ("tracker", "tracker/too_few_rows.csv", "tracker",
     r"only 20 data rows \(expected at least 64 data rows\)"),
    ("tracker", "tracker/no_motion.csv", "tracker",
     r"columns x_mm, y_mm, z_mm: the target moves only 0 mm"),
    ("tracker", "tracker/position_jump.csv", "tracker",
     r"row 37, columns x_mm, y_mm, z_mm: the position jumps by 5 mm .*\(lost beam\?\)"),
    # --- impact/hit<X|Y|Z>_<k>.csv: t_s, force_N, ax_ms2, ay_ms2, az_ms2, >= 64 rows
    ("impact", "impact/empty.csv", "hit", r"file is empty"),
    ("impact", "impact/header_only.csv", "hit", r"header only, no data rows"),
    ("impact", "impact/missing_column.csv", "hit",
     r"header \(row 1\): column 'force_N' is missing"),
    ("impact", "impact/no_response.csv", "hit",
     r"header \(row 1\): no response column \(expected at least one of ax_ms2, ay_ms2, az_ms2\)"),
    ("impact", "impact/misspelt_column.csv", "hit", UNIT.format("az_ms2", "az_ms", "ms")),
    ("impact", "impact/unit_force_kN.csv", "hit", UNIT.format("force_N", "force_kN", "kN")),
    ("impact", "impact/text_in_number.csv", "hit",
     r"row 5, column force_N: " + NOT_NUM.format("12;5")),
    ("impact", "impact/inf.csv", "hit", r"row 8, column az_ms2: value 'inf' is not finite"),
    ("impact", "impact/truncated_last_row.csv", "hit", TRUNC.format(72)),
    ("impact", "impact/non_monotonic_t.csv", "hit",
     r"row 17, column t_s: t_s is not strictly increasing"),
    ("impact", "impact/non_uniform_t.csv", "hit",
     r"row 52, column t_s: t_s is not uniformly spaced"),
    ("impact", "impact/too_few_rows.csv", "hit", r"only 30 data rows"),
    ("impact", "impact/wrong_fs.csv", "hit@5000",
     r"column t_s: t_s spacing is 0.0001 \(expected spacing 0.0002 \(from the manifest\)"),
    # --- impact FRFs as UFF 58
    ("impact", "impact/uff_empty.uff", "uff", r"no UFF 58 data set"),
    ("impact", "impact/uff_junk.uff", "uff", r"no UFF 58 data set"),
    ("impact", "impact/uff_truncated.uff", "uff",
     r"after data set 8: the last data set does not end with its '-1' line \(truncated file\?\)"),
    ("impact", "impact/uff_unit_code.uff", "uff",
     r"data set 1 \(H X/X\): FRF unit codes 0/13 \(ordinate/denominator\) \(expected 8/13 "
     r"receptance, 11/13 mobility or 12/13 accelerance\)"),
    ("impact", "impact/uff_hits_no_force.uff", "uff_hits",
     r"data set 1 \(acc 1\+X\): acceleration before any hammer force set"),
    ("impact", "impact/uff_bad_direction.uff", "uff",
     r"data set 1 \(H X/X receptance m/N\): direction code 7 in ref_dir"),
    # --- ctrack/<table>.csv
    ("ctrack", "ctrack/circles_too_few_points.csv", "ctrack:circles",
     r"column q_deg, rows with joint = 3: joint 3 has 2 circle point\(s\)"),
    ("ctrack", "ctrack/circles_bad_joint.csv", "ctrack:circles",
     r"row 19, column joint: joint .*7.* is not a joint number \(expected an integer 1..6\)"),
    ("ctrack", "ctrack/circles_unit_x_m.csv", "ctrack:circles", UNIT.format("x_mm", "x_m", "m")),
    ("ctrack", "ctrack/home_empty.csv", "ctrack:home", r"file is empty"),
    ("ctrack", "ctrack/home_nan.csv", "ctrack:home",
     r"row 3, column y_mm: " + NOT_NUM.format("nan")),
    ("ctrack", "ctrack/steps_header_only.csv", "ctrack:steps",
     r"header only, no data rows \(expected at least 2 data rows\)"),
    ("ctrack", "ctrack/steps_bad_direction.csv", "ctrack:steps",
     r"row 5, column direction: direction .*0.* \(expected \+1 or -1"),
    ("ctrack", "ctrack/steps_one_direction.csv", "ctrack:steps",
     r"row 8, column direction: joint 2 step at q = 5 deg is measured from one direction only"),
    ("ctrack", "ctrack/steps_no_home.csv", "ctrack:steps",
     r"column q_deg, rows with joint = 2: joint 2 has no step at q = 0"),
    ("ctrack", "ctrack/base_missing_group.csv", "ctrack:base",
     r"row 4, column group: pose 2 has groups \[1\]"),
    ("ctrack", "ctrack/loads_no_unloaded.csv", "ctrack:loads",
     r"row 4, column load_kg: test 2 has loads \[10.0, 20.0\] kg"),
    ("ctrack", "ctrack/loads_truncated_last_row.csv", "ctrack:loads", TRUNC.format(6)),
    ("ctrack", "ctrack/accuracy_missing_column.csv", "ctrack:accuracy",
     r"header \(row 1\): column 'z_cmd_mm' is missing"),
    ("ctrack", "ctrack/accuracy_text.csv", "ctrack:accuracy",
     r"row 2, column y_mm: " + NOT_NUM.format("2.1mm")),
    # --- stiffness/<robot>.yaml
    ("robot", "robot/empty.yaml", "robot", r"not a YAML mapping"),
    ("robot", "robot/not_yaml.yaml", "robot", r"not valid YAML: .*line 2, column 13"),
    ("robot", "robot/unknown_convention.yaml", "robot",
     r"convention: unknown convention 'denavit' \(expected one of dh, mdh\)"),
    ("robot", "robot/unknown_length_unit.yaml", "robot",
     r"length_unit: unknown length_unit 'cm' \(expected one of mm, m\)"),
    ("robot", "robot/missing_joints.yaml", "robot", r"joints: key 'joints' is missing"),
    ("robot", "robot/five_joints.yaml", "robot", r"joints: 5 joints listed \(expected 6 joints"),
    ("robot", "robot/joint_missing_alpha.yaml", "robot", r"joints\[2\]: key 'alpha' is missing"),
    ("robot", "robot/joint_text.yaml", "robot",
     r"joints\[3\]\.d: value '400mm' is not a number"),
    ("robot", "robot/joint_unknown_key.yaml", "robot", r"joints\[1\]: unknown key\(s\) alfa"),
    ("robot", "robot/tool_two_values.yaml", "robot", r"tool: tool is \[0.0, 100.0\]"),
    ("robot", "robot/tool_nan.yaml", "robot", r"tool\[2\]: value nan is not a number"),
    # --- stiffness/load_tests_<robot>.csv
    ("stiffness", "stiffness/empty.csv", "load_tests", r"file is empty"),
    ("stiffness", "stiffness/five_joint_columns.csv", "load_tests",
     r"header \(row 1\): joint columns q1_deg, .*q5_deg found \(expected 6 joint columns"),
    ("stiffness", "stiffness/unit_dz_um.csv", "load_tests", UNIT.format("dz_mm", "dz_um", "um")),
    ("stiffness", "stiffness/text_in_number.csv", "load_tests",
     r"row 2, column dz_mm: " + NOT_NUM.format("x")),
    ("stiffness", "stiffness/empty_pose.csv", "load_tests", r"row 3, column pose: empty value"),
    ("stiffness", "stiffness/bad_role.csv", "load_tests",
     r"row 4, column role: role 'check' \(expected identify or validate\)"),
    ("stiffness", "stiffness/duplicate_pose.csv", "load_tests",
     r"row 4, column pose: duplicate pose 'cube_01'"),
    ("stiffness", "stiffness/no_identify.csv", "load_tests", r"column role: no identify rows"),
    # --- manifest.yaml (folders; the named file is the manifest or the data file)
    ("manifest", "manifest/no_manifest/manifest.yaml", "manifest", r"manifest does not exist"),
    ("manifest", "manifest/not_yaml/manifest.yaml", "manifest",
     r"not valid YAML: .*line 2, column 5"),  # the libyaml parser still names the place
    ("manifest", "manifest/not_a_mapping/manifest.yaml", "manifest",
     r"not a YAML mapping \(expected top-level keys experiment, cuts, files\)"),
    ("manifest", "manifest/missing_top_key/manifest.yaml", "manifest",
     r"top-level key 'files' is missing"),
    ("manifest", "manifest/missing_experiment_key/manifest.yaml", "manifest",
     r"experiment: key 'flutes' is missing"),
    ("manifest", "manifest/wrong_type/manifest.yaml", "manifest",
     r"experiment: key 'flutes' is 'two' \(expected int\)"),
    ("manifest", "manifest/missing_cut_key/manifest.yaml", "manifest",
     r"cuts\[0\]: key 'depth_mm' is missing"),
    ("manifest", "manifest/malformed_cut_id/manifest.yaml", "manifest",
     r"cuts\[0\]\.id: cut id 'cut 1/a' is malformed \(expected letters, digits"),
    ("manifest", "manifest/cut_id_disagrees/manifest.yaml", "manifest",
     r"cuts\[0\]: cut id 's1_g1_px' disagrees with set=1, segment=2, direction=px"),
    ("manifest", "manifest/duplicate_cut_id/manifest.yaml", "manifest",
     r"cuts\[1\]\.id: duplicate cut id 's1_g1_px' \(also cuts\[0\]\)"),
    ("sound", "sound/header_only.wav", "sound",
     r"file: cannot be read as audio \(.*No 'data' chunk.*\) \(expected a WAV, FLAC, MP3"),
    ("vibration", "vibration/time_back.csv", "vibration",
     r"row 9, column t_s: time does not increase"),
    ("manifest", "manifest/unknown_kind/manifest.yaml", "manifest",
     r"files\[0\]\.kind: unknown kind 'profilometer' \(expected one of profile, force"),
    ("manifest", "manifest/missing_sha256/manifest.yaml", "manifest",
     r"files\[0\]: key 'sha256' is missing"),
    ("manifest", "manifest/missing_kind_key/manifest.yaml", "manifest",
     r"files\[1\] \(forces/s1_g1_px\.csv\): key 'fs_hz' is missing"),
    ("manifest", "manifest/duplicate_path/manifest.yaml", "manifest",
     r"files\[1\]\.path: duplicate path 'profiles/s1_g1_px\.csv' \(also files\[0\]\)"),
    ("manifest", "manifest/path_leaves_folder/manifest.yaml", "manifest",
     r"files\[0\]\.path: path '\.\./profiles/s1_g1_px\.csv' leaves the raw folder"),
    ("manifest", "manifest/unknown_cut/manifest.yaml", "manifest",
     r"files\[0\]\.cut: file refers to unknown cut 's1_g2_px'"),
    ("manifest", "manifest/listed_but_missing/profiles/s1_g1_px.csv", "manifest+verify",
     r"manifest\.yaml: files\[path=profiles/s1_g1_px\.csv\]: "
     r"file listed in the manifest does not exist"),
    ("manifest", "manifest/present_but_unlisted/profiles/s1_g2_px.csv", "manifest+verify",
     r"manifest\.yaml: files: 1 file\(s\) in a data folder are present but not listed in "
     r"the manifest: profiles/s1_g2_px\.csv"),
    ("manifest", "manifest/sha256_mismatch/profiles/s1_g1_px.csv", "manifest+verify",
     r"manifest\.yaml: files\[path=profiles/s1_g1_px\.csv\]\.sha256: "
     r"sha256 is [0-9a-f]{64}, the manifest says [0-9a-f]{64}"),
]


@pytest.mark.parametrize(("kind", "rel", "call", "pattern"), CASES,
                         ids=[c[1] for c in CASES])
def test_bad_input(kind, rel, call, pattern, tmp_path):
    rel_path = Path(rel)
    if kind == "manifest":
        # a folder case: copy it, then point the reader at the copy's manifest.yaml
        case = Path(*rel_path.parts[:2])
        shutil.copytree(BAD / case, tmp_path / case)
        named = tmp_path / rel_path
        target = tmp_path / case / "manifest.yaml"
    else:
        named = target = BAD / rel_path
        assert target.is_file(), f"corpus file {rel} is missing"
    with pytest.raises(RawDataError) as info:
        CALLS[call](target)
    message = str(info.value)
    assert info.value.path == str(named), message  # the error names the offending file
    assert named.name in message
    assert re.search(pattern, message, re.DOTALL), f"{pattern!r} not in {message!r}"


def test_corpus_is_covered():
    """Every file of the corpus is used by a case (no stale, untested bad files)."""
    used = {Path(*Path(c[1]).parts[:2]) if c[0] == "manifest" else Path(c[1]) for c in CASES}
    files = {f.relative_to(BAD) for d in BAD.iterdir() if d.is_dir()
             for f in d.iterdir() if not f.name.startswith(".")}
    assert files == used
