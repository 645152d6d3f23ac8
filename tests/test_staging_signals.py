"""A stop signal landing at the worst moment of a staging folder's life: between its ``mkdir`` and the moment its
maker knows it, inside the ``rmtree`` that removes it, and after the work is done while the interpreter shuts down.
Each case is forced, not waited for (the random-moment tests of test_hostile_environment.py found them only once
in a while, under load). Each runs in a child process: the signal goes to that process alone."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _as_from_a_terminal() -> None:
    """The stop signals at their defaults in the child, as a terminal's shell starts it: under ``nohup`` or a
    background job the suite's own process ignores SIGHUP or SIGINT, the child would inherit that, and resal
    rightly keeps a signal ignored from the start (the tests would then test nothing)."""
    for s in (signal.SIGINT, signal.SIGTERM, signal.SIGHUP):
        signal.signal(s, signal.SIG_DFL)


def _child(code: str, tmp: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    return subprocess.run([sys.executable, "-c", textwrap.dedent(code), str(tmp)], env=env, capture_output=True,
                          text=True, timeout=60, preexec_fn=_as_from_a_terminal)


_PRELUDE = """
    import os, pathlib, signal, sys
    from reproductions import processes, report
    from reproductions.errors import Interrupted
    tmp = pathlib.Path(sys.argv[1])
"""


def _signal_after_mkdir(sig: str) -> str:
    """Child code after which every ``Path.mkdir`` sends ``signal.<sig>`` to the process as the folder exists."""
    return f"""
    real = pathlib.Path.mkdir
    def mkdir(self, *a, **k):
        real(self, *a, **k)
        os.kill(os.getpid(), signal.{sig})
    pathlib.Path.mkdir = mkdir
"""


def test_a_signal_inside_the_removal_of_a_staging_folder_still_removes_it_whole(tmp_path: Path) -> None:
    """The signal arrives at the first file ``rmtree`` unlinks: the removal finishes, then the run is interrupted
    (without the signals held, the exception stops ``rmtree`` there and 29 files stay behind)."""
    r = _child(_PRELUDE + """
    stage = report.make_staging(tmp, "figures")
    for i in range(30):
        (stage / f"f{i}.png").write_bytes(b"x")
    real, fired = os.unlink, []
    def unlink(*a, **k):
        if not fired:
            fired.append(1)
            os.kill(os.getpid(), signal.SIGINT)
        return real(*a, **k)
    os.unlink = unlink
    try:
        with processes.interruptible():
            report.remove_staging(stage)
    except Interrupted as exc:
        print("interrupted", exc.signum, fired)
    """, tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["interrupted", str(int(signal.SIGINT)), "[1]"], r.stdout
    assert list(tmp_path.iterdir()) == []


def test_a_signal_between_the_mkdir_and_its_maker_knowing_the_folder_leaves_nothing(tmp_path: Path) -> None:
    """The signal arrives as ``mkdir`` returns: ``staging_folder`` still knows the folder and removes it."""
    r = _child(_PRELUDE + _signal_after_mkdir("SIGTERM") + """
    try:
        with processes.interruptible():
            with report.staging_folder(tmp, "figures") as p:
                print("body ran", p)
    except Interrupted as exc:
        print("interrupted", exc.signum)
    """, tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["interrupted", str(int(signal.SIGTERM))], r.stdout
    assert list(tmp_path.iterdir()) == []


def test_write_folder_interrupted_as_its_staging_is_made_leaves_the_folder_as_it_was(tmp_path: Path) -> None:
    r = _child(_PRELUDE + """
    (tmp / "exp").mkdir()
    (tmp / "exp" / "old.txt").write_text("earlier")
    """ + _signal_after_mkdir("SIGHUP") + """
    try:
        with processes.interruptible():
            report.write_folder(tmp / "exp", {"new.txt": "new"})
    except Interrupted as exc:
        print("interrupted", exc.signum)
    """, tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["interrupted", str(int(signal.SIGHUP))], r.stdout
    assert sorted(p.name for p in tmp_path.iterdir()) == ["exp"]
    assert sorted(p.name for p in (tmp_path / "exp").iterdir()) == ["old.txt"]


def test_after_the_outermost_block_a_late_signal_cannot_end_a_finished_run(tmp_path: Path) -> None:
    """``interruptible(hold_after=True)`` (``resal``'s main): a SIGINT, SIGTERM or SIGHUP sent after the work is
    done is ignored, and the process exits with the status it chose (0), not by Python's SIGINT death (-2)."""
    r = _child(_PRELUDE + """
    with processes.interruptible(hold_after=True):
        pass
    for s in processes.STOP_SIGNALS:
        os.kill(os.getpid(), s)
    print("survived")
    """, tmp_path)
    assert (r.returncode, r.stdout.split(), r.stderr) == (0, ["survived"], "")


def test_without_hold_after_the_handlers_are_put_back(tmp_path: Path) -> None:
    """The inner blocks (``resal reproduce``'s own) put back the handlers they found: a control for the test above
    (Python's SIGINT handler, then its death by SIGINT)."""
    r = _child(_PRELUDE + """
    with processes.interruptible():
        pass
    os.kill(os.getpid(), signal.SIGINT)
    print("survived")
    """, tmp_path)
    assert r.returncode == -signal.SIGINT and "KeyboardInterrupt" in r.stderr, (r.returncode, r.stderr)


def test_a_signal_inside_a_deferred_block_with_other_threads_waits_for_its_end(tmp_path: Path) -> None:
    """numpy's BLAS threads do not block the stop signals, so the kernel may hand a signal to one of them: masking
    the main thread alone let it through at once. A thread started before the block stands for them here."""
    r = _child(_PRELUDE + """
    import threading, time
    stop = threading.Event()
    t = threading.Thread(target=stop.wait, daemon=True)
    t.start()
    steps = []
    try:
        with processes.interruptible():
            with processes.deferred():
                os.kill(os.getpid(), signal.SIGTERM)
                for _ in range(200):
                    time.sleep(0.001)  # many chances for the handler to run
                steps.append("block finished")
    except Interrupted as exc:
        print(steps, "interrupted", exc.signum)
    """, tmp_path)
    assert r.returncode == 0, r.stderr
    assert r.stdout.split() == ["['block", "finished']", "interrupted", str(int(signal.SIGTERM))], r.stdout


def _library_whose_init_fails(signal_first: bool, chained: bool = True) -> str:
    """Child code that runs ``resal list`` where importing ``yaml`` runs a library's initialisation that fails as
    pybind11's modules do (matplotlib's among them): any error of the init is caught and raised again as
    ``ImportError('initialization failed')`` from it. With ``signal_first`` the error is a stop signal landing
    there (found by CI: a SIGINT 1.66 s into a run on a loaded machine ended it as "cannot load a library", 1)."""
    return f"""
    import importlib.abc, importlib.util, os, signal, sys, time
    class Init(importlib.abc.Loader):
        def create_module(self, spec):
            return None
        def exec_module(self, module):
            try:
                if {signal_first}:
                    os.kill(os.getpid(), signal.SIGINT)
                    for _ in range(200):
                        time.sleep(0.001)  # the handler runs here
                raise RuntimeError("the library's own failure")
            except BaseException as exc:  # pybind11: catch (error_already_set &e) {{ raise_from(e, ...) }}
                if {chained}:
                    raise ImportError("initialization failed") from exc
            # numpy's import_array: PyErr_Print() (the interruption printed and cleared), then its own ImportError
            raise ImportError("initialization failed")
    class Finder(importlib.abc.MetaPathFinder):
        def find_spec(self, name, path=None, target=None):
            return importlib.util.spec_from_loader(name, Init()) if name == "yaml" else None
    sys.meta_path.insert(0, Finder())
    sys.argv = ["resal", "list"]
    from cli.main import main
    main()
    """


def test_a_signal_inside_a_library_initialisation_ends_the_run_as_that_signal(tmp_path: Path) -> None:
    """The signal, wrapped by the library into an ImportError, is still the signal: one line, 128 + n."""
    r = _child(_library_whose_init_fails(True), tmp_path)
    assert (r.returncode, r.stderr) == (128 + signal.SIGINT, "error: interrupted (SIGINT); earlier results left "
                                                            "as they were\n"), (r.returncode, r.stderr)


def test_a_library_initialisation_failing_by_itself_is_a_failure_to_load(tmp_path: Path) -> None:
    """The control: the same init failing with no signal is a failure of the environment, status 1."""
    r = _child(_library_whose_init_fails(False), tmp_path)
    assert r.returncode == 1 and r.stderr.startswith("error: cannot load a library (initialization failed)"), (
        r.returncode, r.stderr)


def test_a_signal_a_library_swallowed_into_its_own_error_still_ends_the_run_as_that_signal(tmp_path: Path) -> None:
    """The init clears the interruption and raises an ImportError with no trace of it (numpy's ``import_array``
    prints and clears the error first): the signal ``interruptible`` received still decides, one line, 128 + n."""
    r = _child(_library_whose_init_fails(True, chained=False), tmp_path)
    assert (r.returncode, r.stderr) == (128 + signal.SIGINT, "error: interrupted (SIGINT); earlier results left "
                                                            "as they were\n"), (r.returncode, r.stderr)
