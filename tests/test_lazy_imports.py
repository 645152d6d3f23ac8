"""scipy's heavy subpackages are imported where they are used, not when a module of ours is imported: a command that
fits or integrates nothing (`resal list`, `--help`) starts in a fraction of a second, and every process the test
suite and `make all` start saves half a second."""

import subprocess
import sys

import pytest
from scipy import stats

from reproductions.fit.estimators import markers
from reproductions.lazy import lazy

HEAVY = ("scipy.stats", "scipy.integrate", "scipy.optimize", "scipy.special", "scipy.interpolate")


def test_importing_every_module_of_ours_imports_no_heavy_scipy_subpackage():
    code = ("import sys, pkgutil, importlib, reproductions, cli\n"
            "for pkg in (reproductions, cli):\n"
            "    for m in pkgutil.walk_packages(pkg.__path__, pkg.__name__ + '.'):\n"
            "        importlib.import_module(m.name)\n"
            f"print(' '.join(m for m in {HEAVY!r} if m in sys.modules))\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == [], f"imported at import time (use reproductions.lazy or a local import): {r.stdout}"


def test_a_lazy_module_is_the_module_once_used():
    """The first attribute read imports the module and puts it in the importer's namespace in the stand-in's place:
    from then on the importer reads the module itself (a monkeypatch of the module is seen, no wrapper in between)."""
    ns: dict = {}
    ns["stats"] = lazy("scipy.stats", ns)
    assert ns["stats"] is not stats and "scipy.stats" in repr(ns["stats"])
    assert ns["stats"].chi2 is stats.chi2
    assert ns["stats"] is stats
    other = {"stats": 1}
    assert lazy("scipy.stats", other).norm is stats.norm and other["stats"] == 1  # a name rebound since: left alone


def test_the_markers_cut_is_the_chi2_quantile_it_stands_for():
    """CUT is written as a literal so that importing the module does not import scipy.stats: the same float."""
    assert markers.CUT == float(stats.chi2.ppf(0.95, 1))


def test_a_stand_in_copies_and_answers_introspection_without_importing():
    """Dunder names (copy, pickle, inspect) are the stand-in's own: no import, no endless recursion."""
    import copy

    ns: dict = {}
    ns["interpolate_like"] = stand_in = lazy("resal_no_such_module", ns)  # importing it would fail loudly
    assert not hasattr(stand_in, "__wrapped__")
    twin = copy.copy(stand_in)
    assert "resal_no_such_module" in repr(twin)
    with pytest.raises(ModuleNotFoundError):  # a name of the module's: the import is attempted, and fails
        _ = stand_in.anything


def test_reusing_unchanged_results_imports_no_numpy(tmp_path):
    """`make all` with nothing changed reads summaries and digests only: numpy (0.16 s of a 0.4 s command) is not
    imported. The run that fills the folder first does import it: the probe would see a regression."""
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    code = ("import sys, runpy\n"
            "sys.argv = ['resal', 'reproduce', 'marble-drop', '--out', sys.argv[1]]\n"
            "try:\n"
            "    runpy.run_module('cli.main', run_name='__main__')\n"
            "except SystemExit as e:\n"
            "    assert not e.code, e.code\n"
            "print('NUMPY', 'numpy' in sys.modules, file=sys.stderr)\n")
    env = {"PYTHONPATH": str(root), "PATH": "/usr/bin:/bin", "COLUMNS": "80"}
    seen = []
    for _ in range(2):  # first computes, then reuses
        r = subprocess.run([sys.executable, "-c", code, str(tmp_path / "out")], capture_output=True, text=True,
                           timeout=300, cwd=root, env=env)
        assert r.returncode == 0, r.stderr
        seen.append(r.stderr.strip().splitlines()[-1])
    assert seen == ["NUMPY True", "NUMPY False"], seen


def test_the_fits_and_measured_experiments_run_without_scipy_stats():
    """``fit.distributions`` stands in for scipy.stats (0.3 s of import before ``make all``'s workers fork): the
    experiments whose rows come from fits and tests (χ², t, F, the slope test) run without importing it."""
    code = ("import sys\n"
            "from reproductions import api\n"
            "for e in ('modern-head-on', 'modern-oblique', 'modern-restitution', 'coriolis-pendulum'):\n"
            "    api.run(api.load(e))\n"
            "print('scipy.stats' in sys.modules)\n")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split()[-1] == "False"
