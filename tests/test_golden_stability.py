"""Golden numbers are ones the data determine: rounding-level changes must not move them.

Two ways rounding differs on another machine, both provoked here on this one: (1) every number of every config
perturbed by one ulp, and every optimiser started elsewhere; (2) a fresh process under another OpenBLAS kernel
and the other threading (one BLAS thread where this run has several, two where it has one: `make test` runs its
workers on one). Either must leave the golden comparison clean.
"""

import json
import math
import os
import platform
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import optimize

from reproductions import api, config, golden
from reproductions.experiments import ricochet
from reproductions.report import summary

ROOT = Path(__file__).resolve().parent.parent


def _one_ulp(orig):
    def number(self, key, what="a number", *, default=None, lo=None, hi=None, lo_open=False, hi_open=False):
        v = orig(self, key, what, default=default, lo=lo, hi=hi, lo_open=lo_open, hi_open=hi_open)
        if v == 0.0 or (default is not None and not self.has(key)):
            return v  # an exact zero or an unset default is not a measured number
        up = np.nextafter(v, np.inf)
        return float(np.nextafter(v, -np.inf) if hi is not None and up > hi else up)
    return number


def _moved_start(orig):
    def least_squares(fun, x0, *args, bounds=(-np.inf, np.inf), **kw):
        x0 = np.asarray(x0, dtype=float)
        lo, hi = (np.broadcast_to(np.asarray(b, dtype=float), x0.shape) for b in bounds)
        x1 = x0 * (1 + 1e-3) + 1e-6
        x1 = np.where(x1 >= hi, x0 - 1e-3 * (x0 - lo), x1)  # stay strictly inside the bounds
        return orig(fun, np.clip(x1, lo, hi), *args, bounds=bounds, **kw)
    return least_squares


def _ulp_series(orig):
    def simulate_series(p, s, rng):
        x, t = orig(p, s, rng)
        return np.nextafter(x, np.inf) * (x != 0), np.nextafter(t, np.inf) * (t != 0)
    return simulate_series


@pytest.fixture(scope="module")
def unperturbed():
    return summary(api.run(api.load("roze-ricochets")), prov={})


@pytest.fixture(scope="module")
def perturbed(unperturbed):
    mp = pytest.MonkeyPatch()
    mp.setattr(config.Node, "number", _one_ulp(config.Node.number))
    mp.setattr(optimize, "least_squares", _moved_start(optimize.least_squares))
    mp.setattr(ricochet, "simulate_series", _ulp_series(ricochet.simulate_series))
    try:
        yield {eid: summary(api.run(api.load(eid)), prov={}) for eid in api.experiment_ids()}
    finally:
        mp.undo()


@pytest.mark.parametrize("eid", api.experiment_ids())
def test_one_ulp_and_another_start_move_no_golden_number(eid, perturbed):
    g = json.loads((golden.GOLDEN_DIR / f"{eid}.json").read_text(encoding="utf-8"))
    now = golden.flatten(perturbed[eid])
    moved = {k: golden.movement(v, now[k][0]) for k, v in g["values"].items() if k in now}
    assert set(now) == set(g["values"]), "the perturbed run reports other quantities"
    worst = max(moved, key=moved.get)
    # 0.1: a movement must stay an order of magnitude inside its tolerance, not merely within it
    assert moved[worst] < 0.1, f"{worst} moved by {moved[worst]:.3g} of its tolerance under a one-ulp perturbation"


def test_the_perturbation_reaches_the_data(unperturbed, perturbed):
    """Guard against a perturbation that silently does nothing: the raw fitted numbers do change."""
    a = [f["value"] for f in unperturbed["fits"] if f["value"] is not None]
    b = [f["value"] for f in perturbed["roze-ricochets"]["fits"] if f["value"] is not None]
    assert a != b and np.allclose(a, b, rtol=1e-8)


def _bundled_openblas() -> list[Path]:
    """numpy's own OpenBLAS libraries (numpy.libs beside the package, as its Linux wheels ship them)."""
    return sorted((Path(np.__file__).parent.parent / "numpy.libs").glob("libscipy_openblas*"))


def _running_kernel() -> str | None:
    """The kernel OpenBLAS runs in this process (numpy's bundled scipy-openblas, asked through ctypes), or None
    where that library or its function is not found (then no kernel is left out)."""
    import ctypes

    for lib in _bundled_openblas():
        try:
            dll = ctypes.CDLL(str(lib))
        except OSError:
            continue
        for name in ("scipy_openblas_get_corename64_", "scipy_openblas_get_corename", "openblas_get_corename"):
            f = getattr(dll, name, None)
            if f is not None:
                f.restype = ctypes.c_char_p
                return f().decode(errors="replace")
    return None


def _kernels() -> list[str]:
    """Kernels other than the one this run uses (that one is the suite's own run)."""
    machine = platform.machine().lower()
    found: list[str] = []
    if machine in ("x86_64", "amd64"):
        flags = Path("/proc/cpuinfo").read_text() if Path("/proc/cpuinfo").is_file() else ""
        # Prescott (SSE3) runs on every x86-64 and shares no kernel with the AVX2/AVX-512 defaults
        found = ["Prescott"] + (["SkylakeX"] if "avx512f" in flags else [])
    elif machine in ("aarch64", "arm64"):
        found = ["ARMV8"]
    running = (_running_kernel() or "").lower()
    return [k for k in found if k.lower() != running]


def test_the_running_kernel_is_known_where_numpy_bundles_openblas():
    """The filter above must not silently keep a kernel because it could not ask: where numpy ships its OpenBLAS
    (the wheels on Linux), the running kernel is read, and OPENBLAS_CORETYPE, where set to a kernel this processor
    runs, is what it reads."""
    if not _bundled_openblas():
        pytest.skip("this numpy does not bundle scipy-openblas")
    kernel = _running_kernel()
    assert kernel, "numpy bundles OpenBLAS but its kernel could not be read"
    asked = os.environ.get("OPENBLAS_CORETYPE")
    if asked:
        assert kernel.lower() == asked.lower()


@pytest.mark.parametrize("kernel", _kernels() or [pytest.param(None, marks=pytest.mark.skip("no known kernel"))])
def test_same_verdict_under_another_openblas_kernel_and_threading(kernel):
    threads = "2" if os.environ.get("OPENBLAS_NUM_THREADS") == "1" else "1"
    env = dict(os.environ, OPENBLAS_CORETYPE=kernel, OPENBLAS_NUM_THREADS=threads, OMP_NUM_THREADS=threads)
    proc = subprocess.run([sys.executable, "-m", "reproductions.golden", "--check"], cwd=ROOT, env=env,
                          capture_output=True, text=True, timeout=600)
    diffs = json.loads(proc.stdout.strip().splitlines()[-1]) if proc.stdout.strip() else None
    assert diffs is not None, proc.stderr[-2000:]
    assert set(diffs) == set(api.experiment_ids())
    bad = {k: v for k, v in diffs.items() if v}
    assert not bad and proc.returncode == 0, "\n".join(f"{k}: {d}" for k, v in bad.items() for d in v[:5])


def test_every_golden_tolerance_has_a_reason():
    for path in sorted(golden.GOLDEN_DIR.glob("*.json")):
        g = json.loads(path.read_text(encoding="utf-8"))
        for k, v in g["values"].items():
            assert v["why"] in g["tolerances"] and g["tolerances"][v["why"]].strip(), f"{path.name}: {k}"
            assert math.isfinite(v["rtol"]) and math.isfinite(v["atol"])
