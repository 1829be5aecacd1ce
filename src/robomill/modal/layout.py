"""Measurement points of an impact test: directions, point labels, FRF coordinates.

A point is ``(node, signed UFF direction code)`` (X=1, Y=2, Z=3; negative: the negative
axis); the thesis' tool-tip layout is node 1, +X, +Y, +Z (:data:`TOOLTIP`). Any test layout
(SISO, roving hammer, roving accelerometer, tri-axial responses, the 3×3 tool-tip matrix)
is a list of response points (``output``) and reference points (``input``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import xarray as xr

AXES = ("X", "Y", "Z")
"""Output (accelerometer) and input (hammer) directions, base axes."""


AXIS_CODE = {"X": 1, "Y": 2, "Z": 3}
"""UFF direction codes of the base axes (a negative code is the negative axis)."""


TOOLTIP = ((1, 1), (1, 2), (1, 3))
"""The tool-tip points of the thesis layout: node 1, +X, +Y, +Z."""


def parse_direction(text: str | int) -> int:
    """A direction as a signed UFF code: ``"X"``/``"+X"``/``1`` → 1, ``"-Y"``/``-2`` → −2.

    Raises
    ------
    ValueError
        Anything but ±X, ±Y, ±Z (or ±1, ±2, ±3).
    """
    if isinstance(text, (int, np.integer)) and not isinstance(text, bool):
        if abs(int(text)) in (1, 2, 3):
            return int(text)
    elif isinstance(text, str):
        t = text.strip().upper()
        sign = -1 if t.startswith("-") else 1
        t = t.lstrip("+-")
        if t in AXIS_CODE:
            return sign * AXIS_CODE[t]
    raise ValueError(f"direction {text!r} is not one of X, Y, Z, +X, -X, +Y, -Y, +Z, -Z")


def point_label(node: int, dir_code: int) -> str:
    """Label of a measurement point ``(node, ±direction)``: the axis letter, ``-`` before it
    for a negative direction, the node number before that unless it is node 1 (so the
    thesis layout keeps its labels ``X, Y, Z``): ``(1, 2)`` → ``"Y"``, ``(3, -1)`` →
    ``"3-X"``."""
    axis = "XYZ"[abs(int(dir_code)) - 1]
    return f"{'' if int(node) == 1 else int(node)}{'-' if dir_code < 0 else ''}{axis}"


def _point_key(p: tuple[int, int]) -> tuple[int, int, int]:
    return (int(p[0]), abs(int(p[1])), int(p[1]) < 0)


def frf_coords(freq_hz: np.ndarray, outputs: Sequence[tuple[int, int]] = TOOLTIP,
               inputs: Sequence[tuple[int, int]] = TOOLTIP) -> dict:
    """Labelled coordinates ``output, input, frequency`` of an FRF dataset.

    ``output``/``input`` carry the point labels (:func:`point_label`); ``output_node``,
    ``output_dir``, ``input_node``, ``input_dir`` the node numbers and signed UFF direction
    codes (X=1, Y=2, Z=3; negative: the negative axis) of each response and reference point.
    """
    out: dict = {}
    for dim, pts, what in (("output", outputs, "response (accelerometer)"),
                           ("input", inputs, "reference (hammer)")):
        pts = [(int(n), int(d)) for n, d in pts]
        out[dim] = (dim, [point_label(*p) for p in pts],
                    {"units": "1", "long_name": f"{what} point: node and direction"})
        out[f"{dim}_node"] = (dim, np.array([p[0] for p in pts]),
                              {"units": "1", "long_name": f"{what} node number"})
        out[f"{dim}_dir"] = (dim, np.array([p[1] for p in pts]),
                             {"units": "1", "long_name": f"{what} direction, UFF code "
                                                        "(X=1, Y=2, Z=3, negative axis < 0)"})
    out["frequency"] = ("frequency", np.asarray(freq_hz, float),
                        {"units": "Hz", "long_name": "frequency"})
    return out


def points(ds: xr.Dataset, dim: str) -> list[tuple[int, int]]:
    """The ``(node, direction code)`` points along ``output`` or ``input`` of an FRF dataset
    (datasets without node coordinates: node 1, the axis of each label)."""
    if f"{dim}_node" in ds.coords:
        return [(int(n), int(d)) for n, d in zip(ds[f"{dim}_node"].values,
                                                 ds[f"{dim}_dir"].values, strict=True)]
    return [(1, parse_direction(str(v))) for v in ds[dim].values]


def driving_points(outputs: Sequence[tuple[int, int]],
                   inputs: Sequence[tuple[int, int]]) -> list[tuple[int, int, int]]:
    """Driving points of a layout: ``(i_output, i_input, sign)`` where response and reference
    are the same node and axis (``sign`` −1 when their directions are opposite)."""
    out = []
    for i, (no, do) in enumerate(outputs):
        for j, (ni, di) in enumerate(inputs):
            if no == ni and abs(do) == abs(di):
                out.append((i, j, int(np.sign(do) * np.sign(di))))
    return out


def _is_tooltip(outputs, inputs) -> bool:
    return ([tuple(p) for p in outputs] == list(TOOLTIP)
            and [tuple(p) for p in inputs] == list(TOOLTIP))


def measured_directions(ds: xr.Dataset) -> dict[str, str]:
    """Which base axes an impact test covered: ``{"hammer": "X", "response": "XY",
    "measured": "X", "not_measured": "YZ"}`` (axes by letter, sign and node ignored).

    An axis is *measured* when it was both hit and measured (an FRF along it exists at some
    node); the others are *not measured*: the test gives no mode of that direction, the
    mode-shape components along it are empty (NaN) in ``modes.csv``, and what depends on them
    (the tool model of chapter 4, the plan's predictions) is extrapolated there. Written as
    the attributes ``directions_hit``, ``directions_measured``, ``directions_not_measured``
    of ``results/modal/frf.nc`` by the modal stage.
    """
    def axes(pts) -> set[str]:
        return {"XYZ"[abs(int(d)) - 1] for _, d in pts}

    hit, resp = axes(points(ds, "input")), axes(points(ds, "output"))
    both = hit & resp
    return {"hammer": "".join(sorted(hit)), "response": "".join(sorted(resp)),
            "measured": "".join(sorted(both)),
            "not_measured": "".join(a for a in "XYZ" if a not in both)}
