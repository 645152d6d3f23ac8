"""Measurement series from CSV files (a user's own data), read with a clear message for every bad row."""

from __future__ import annotations

import csv
import math
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from .errors import InputError

__all__ = ["MIN_IMPRINTS", "check_imprints", "read_imprints", "read_series"]

MIN_IMPRINTS = 5  # a ricochet series: fewer imprints cannot tell ν from the launch


def read_series(path: Path, columns: Sequence[str], optional: Sequence[str] = (), min_rows: int = 1,
                positive: Sequence[str] = ()) -> dict[str, np.ndarray]:
    """A measurement series from a CSV file with a header; every bad row is reported as file:line."""
    where = str(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise InputError(where, f"cannot read the series file ({exc.strerror})") from None
    except UnicodeDecodeError:
        raise InputError(where, "not a UTF-8 text file") from None
    numbered = [(i + 1, ln) for i, ln in enumerate(text.splitlines()) if ln.strip() and not ln.startswith("#")]
    if not numbered:
        raise InputError(where, f"empty series (expected a header with columns {', '.join(columns)})")
    head_line, head = numbered[0]
    header = [h.strip() for h in next(csv.reader([head]))]
    missing = [c for c in columns if c not in header]
    if missing:
        raise InputError(f"{where}:{head_line}", f"missing column(s) {', '.join(missing)} in the header "
                                                 f"(expected {', '.join(columns)})")
    unknown = [h for h in header if h not in columns and h not in optional]
    if unknown:
        raise InputError(f"{where}:{head_line}", f"unknown column(s) {', '.join(unknown)} "
                                                 f"(expected {', '.join([*columns, *optional])})")
    data: dict[str, list[float]] = {h: [] for h in header}
    for line_no, ln in numbered[1:]:
        cells = [c.strip() for c in next(csv.reader([ln]))]
        if len(cells) != len(header):
            raise InputError(f"{where}:{line_no}", f"expected {len(header)} values, got {len(cells)}")
        for h, cell in zip(header, cells, strict=True):
            try:
                v = float(cell)
            except ValueError:
                raise InputError(f"{where}:{line_no}", f"column '{h}': expected a number, got '{cell}'") from None
            if not math.isfinite(v):
                raise InputError(f"{where}:{line_no}", f"column '{h}': expected a finite number, got '{cell}'")
            if h in positive and v <= 0:
                raise InputError(f"{where}:{line_no}", f"column '{h}': expected a positive number, got '{cell}'")
            data[h].append(v)
    if len(numbered) - 1 < min_rows:
        raise InputError(where, f"expected at least {min_rows} data row(s), got {len(numbered) - 1}")
    return {h: np.asarray(v) for h, v in data.items()}


def check_imprints(x: np.ndarray, where: str) -> None:
    """Imprint positions of a ricochet series: at least ``MIN_IMPRINTS``, strictly increasing."""
    if x.size < MIN_IMPRINTS:
        raise InputError(where, f"expected at least {MIN_IMPRINTS} imprints, got {x.size}")
    bad = np.nonzero(np.diff(x) <= 0)[0]
    if bad.size:
        raise InputError(where, f"imprint positions must increase; imprint {bad[0] + 2} is not beyond imprint "
                                f"{bad[0] + 1} ({x[bad[0] + 1]:g} ≤ {x[bad[0]]:g})")


def read_imprints(path: Path) -> tuple[np.ndarray, np.ndarray | None]:
    """A ricochet series (column x in m, optional t in s), both measured from the first imprint."""
    d = read_series(path, ("x",), optional=("t",), min_rows=1)
    x = d["x"]
    check_imprints(x, str(path))
    t = d.get("t")
    if t is not None and np.any(np.diff(t) <= 0):
        raise InputError(str(path), "impact instants t must increase")
    return x - x[0], None if t is None else t - t[0]
