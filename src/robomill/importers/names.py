"""Cut ids and cut design keys read from file names (``robomill import … --cut-pattern``).

A lab's files often carry the design in their names (``6-n6000f300ap3ae25``: cut 6 at
6000 rpm, 300 mm/min, a_p 3 mm, a_e 25 %). ``--cut-pattern REGEX`` is a Python regular
expression searched in each source's file name without its extension; its *named groups*
give the cut id and the manifest's cut keys (``docs/data-contract.md``, "The manifest"):

======================================  ==========================================
group                                   manifest key (conversion)
======================================  ==========================================
``cut``                                 the cut id (default: ``--cut``, else the stem)
``set``, ``segment``, ``flutes``        the same key (integer)
``feed_mm_s``, ``depth_mm``,            the same key (number)
``spindle_rpm``, ``tool_diameter_mm``,
``radial_immersion``, ``direction_deg``
``feed_mm_min``                         ``feed_mm_s`` (÷ 60)
``width_pct``, ``radial_immersion_pct`` ``radial_immersion`` (a_e / D in %, ÷ 100)
``direction``                           ``direction`` (``px``, ``mx``, ``py``, ``my``)
``milling``                             ``milling`` (``slot``, ``up``, ``down``)
======================================  ==========================================

``--design KEY=VALUE`` (repeatable, the same names) gives a key the names do not carry for
every cut of the import (``--design direction=px --design flutes=2``). Keys neither gives
stay ``null`` in ``cuts:`` and ``robomill manifest`` lists
them. Every problem is one :class:`~robomill.errors.RawDataError` naming the file (or the
option) and the group.
"""

from __future__ import annotations

import re
from collections.abc import Callable
from pathlib import Path
from typing import Any

from robomill.errors import RawDataError
from robomill.experiment import DIRECTION_VECTORS, FREE_CUT_ID, MILLING


def _number(text: str) -> float | int:
    value = float(text.replace(",", "."))
    return int(value) if value.is_integer() and "." not in text and "," not in text else value


def _integer(text: str) -> int:
    if not text.isdigit():
        raise ValueError(text)
    return int(text)


def _choice(choices: tuple[str, ...]) -> Callable[[str], str]:
    def parse(text: str) -> str:
        if text not in choices:
            raise ValueError(text)
        return text
    return parse


GROUPS: dict[str, tuple[str, Callable[[str], Any], str]] = {
    "set": ("set", _integer, "an integer"),
    "segment": ("segment", _integer, "an integer"),
    "flutes": ("flutes", _integer, "an integer"),
    "feed_mm_s": ("feed_mm_s", _number, "a number [mm/s]"),
    "feed_mm_min": ("feed_mm_s", lambda t: _number(t) / 60.0, "a number [mm/min]"),
    "depth_mm": ("depth_mm", _number, "a number [mm]"),
    "spindle_rpm": ("spindle_rpm", _number, "a number [rpm]"),
    "tool_diameter_mm": ("tool_diameter_mm", _number, "a number [mm]"),
    "radial_immersion": ("radial_immersion", _number, "a number a_e/D"),
    "width_pct": ("radial_immersion", lambda t: _number(t) / 100.0, "a number [% of D]"),
    "radial_immersion_pct": ("radial_immersion", lambda t: _number(t) / 100.0,
                             "a number [% of D]"),
    "direction_deg": ("direction_deg", _number, "a number [deg]"),
    "direction": ("direction", _choice(tuple(DIRECTION_VECTORS)),
                  "one of " + ", ".join(DIRECTION_VECTORS)),
    "milling": ("milling", _choice(MILLING), "one of " + ", ".join(MILLING)),
}
"""Named group → (manifest cut key, parser of the matched text, what the text must be)."""

ACCEPTED = ("cut", *GROUPS)
"""Every group name ``--cut-pattern`` accepts."""


def compile_pattern(pattern: str, source: Path | str = "--cut-pattern") -> re.Pattern:
    """Compile ``--cut-pattern``; its groups must be named and among :data:`ACCEPTED`, and two
    groups must not give the same manifest key.

    Raises
    ------
    RawDataError
        Not a regular expression, an unnamed or unknown group, or two groups for one key.
    """
    where = "option --cut-pattern"
    try:
        rx = re.compile(pattern)
    except re.error as exc:
        raise RawDataError(source, f"--cut-pattern '{pattern}' is not a regular expression "
                           f"({exc})", where=where,
                           expected="a Python regular expression with named groups "
                                    "(?P<name>...)") from None
    unknown = [g for g in rx.groupindex if g not in ACCEPTED]
    if unknown:
        raise RawDataError(source, f"--cut-pattern group(s) {', '.join(unknown)} unknown",
                           where=where, expected="group names among " + ", ".join(ACCEPTED))
    keys: dict[str, str] = {}
    for g in rx.groupindex:
        if g == "cut":
            continue
        key = GROUPS[g][0]
        if key in keys:
            raise RawDataError(source, f"--cut-pattern groups {keys[key]} and {g} both give "
                               f"{key}", where=where, expected="one group per manifest key")
        keys[key] = g
    if "direction" in keys and "direction_deg" in keys:
        raise RawDataError(source, "--cut-pattern groups direction and direction_deg both "
                           "give the feed direction", where=where, expected="one of them")
    return rx


def design_from_name(rx: re.Pattern, source: Path) -> tuple[str | None, dict[str, Any]]:
    """``(cut id or None, {manifest key: value})`` from ``source``'s name (no extension).

    Raises
    ------
    RawDataError
        The pattern does not match the name, a matched text does not parse (the group and
        what it must be are named), or the cut id is malformed.
    """
    source = Path(source)
    stem = source.name[: -len(source.suffix)] if source.suffix else source.name
    m = rx.search(stem)
    if m is None:
        raise RawDataError(source, f"file name {stem!r} does not match --cut-pattern "
                           f"'{rx.pattern}'", where="option --cut-pattern",
                           expected="a pattern matching every source's name (without its "
                                    "extension), or the file imported on its own")
    design: dict[str, Any] = {}
    for group, text in m.groupdict().items():
        if group == "cut" or text is None:
            continue
        key, parse, what = GROUPS[group]
        try:
            design[key] = parse(text)
        except ValueError:
            raise RawDataError(source, f"group {group} matched {text!r}",
                               where="option --cut-pattern", expected=what) from None
    cut = m.groupdict().get("cut")
    if cut is not None and not FREE_CUT_ID.match(cut):
        raise RawDataError(source, f"group cut matched {cut!r}", where="option --cut-pattern",
                           expected="a cut id of letters, digits, '_', '.', '-'")
    return cut, design


def design_from_options(items: list[str] | None) -> dict[str, Any]:
    """``--design KEY=VALUE`` items → ``{manifest key: value}`` (the group names and
    conversions of :data:`GROUPS`).

    Raises
    ------
    RawDataError
        An item without ``=``, an unknown key, a value that does not parse, two items for
        one key.
    """
    design: dict[str, Any] = {}
    for item in items or []:
        name, eq, text = item.partition("=")
        name, text = name.strip(), text.strip()
        if not eq or name not in GROUPS:
            raise RawDataError("--design", f"--design {item!r} is not KEY=VALUE with a known "
                               "key", where="option --design",
                               expected="keys among " + ", ".join(GROUPS))
        key, parse, what = GROUPS[name]
        try:
            value = parse(text)
        except ValueError:
            raise RawDataError("--design", f"--design {name}={text!r}", where="option --design",
                               expected=what) from None
        if key in design:
            raise RawDataError("--design", f"--design gives {key} twice",
                               where="option --design", expected="one value per key")
        design[key] = value
    return design
