"""Each raw-data kind's file check: the reader the kind's analysis uses, called as the
pipeline calls it (``robomill check`` runs the one a kind's record names,
:attr:`robomill.io.kinds.Kind.check`). A check raises
:class:`~robomill.errors.RawDataError` naming the file and what was expected."""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

from robomill.errors import RawDataError


def check_profile(path: Path, entry: Mapping[str, Any]) -> None:
    from robomill.io.profiles import read_profile

    read_profile(path)


def check_force(path: Path, entry: Mapping[str, Any]) -> None:
    from robomill.io.forces import open_force_record

    record = open_force_record(path, float(entry["fs_hz"]))
    for _ in record.chunks(1 << 20):  # every sample is checked as it streams
        pass


def check_tracker(path: Path, entry: Mapping[str, Any]) -> None:
    from robomill.io.tracker import read_tracker

    read_tracker(path, fs_hz=float(entry["fs_hz"]))


def check_impact(path: Path, entry: Mapping[str, Any]) -> None:
    """A hit CSV with :func:`robomill.io.impact.read_hit`; a UFF 58 file (time histories or
    FRFs, as the modal rules read it) with the UFF readers."""
    from robomill.io.impact import read_hit

    if path.suffix.lower() in (".uff", ".unv"):
        from robomill.importers.uff import describe

        describe(path)
        return
    fs = entry.get("fs_hz")
    read_hit(path, fs_hz=None if fs is None else float(fs))


def check_ctrack(path: Path, entry: Mapping[str, Any]) -> None:
    from robomill.io.ctrack import READERS

    table = entry["table"]
    if table not in READERS:
        raise RawDataError(path, f"unknown C-Track table {table!r}", where="manifest table",
                           expected="one of " + ", ".join(READERS))
    READERS[table](path)


def check_robot(path: Path, entry: Mapping[str, Any]) -> None:
    from robomill.io.robots import read_robot_file

    read_robot_file(path)


def check_stiffness(path: Path, entry: Mapping[str, Any]) -> None:
    from robomill.io.robots import read_load_tests, read_robot_file

    n_joints = 6
    robot_path = entry.get("_robot_path")  # the robot file of the same `robot`, as the
    if robot_path is not None:            # stiffness rules pair them
        try:
            n_joints = read_robot_file(robot_path)[0].n_joints
        except RawDataError:
            pass  # reported with the robot file itself
    read_load_tests(path, n_joints)


def check_recording(path: Path, entry: Mapping[str, Any]) -> None:
    """A sound or vibration recording with :func:`robomill.io.recordings.read_recording`."""
    from robomill.io.recordings import read_recording

    read_recording(path, entry["kind"], fs_hz=entry.get("fs_hz"), channels=entry.get("channels"))


def check_areal(path: Path, entry: Mapping[str, Any]) -> None:
    from robomill.io.areal import read_areal

    read_areal(path)
