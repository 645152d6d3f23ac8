"""The verdict rules of configs/README.md checked by what each row computes (issue 35), not by what it says of itself.

- *mutation*: every printed number moved by four of its tolerances; a printed value is never an input, so no computed
  value may move, and every row reproduced before must differ after (a row that stays reproduced reads its printed
  value);
- *identity*: the experiment re-run at random admissible perturbations of its ``params`` numbers (each drawn within
  ±10 % and accepted only where the loader accepts it); a reproduced formula row whose discrepancy is exactly 0 at
  every draw, or a reproduced value row whose computed value does not move at all, is a check that cannot fail (an
  identity or a definition: not-checkable);
- *quotation*: a row's ``text`` quotes the paper only (every word of it is a word the paper prints), and every « … »
  quotation in a row's note or quantity is a quotation that some row's ``text`` holds.

Each check is a function of experiment files (and of a ``run`` function, so that a test can hand it a broken kind);
it returns the rows that break the rule, with why. ``tests/test_verdict_rules.py`` runs them on every shipped file
and on deliberately broken ones.
"""

from __future__ import annotations

import os
import re
import shutil
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import yaml

from reproductions import paper
from reproductions.config import load_experiment, parse_number
from reproductions.errors import InputError
from reproductions.experiments import KINDS

MUTATION_STEPS = 4.0  # tolerances a printed value is moved by: outside the tolerance however the row sat inside it
SPREAD = 0.10  # the identity draws perturb each params number by a factor in [1 − SPREAD, 1 + SPREAD]
DRAWS = 3  # identity draws per experiment: an identity is zero at all of them, a real check at almost none
RETRIES = 6  # inadmissible draws (refused by the loader or the run) redrawn, each with half the spread

RowResult = dict[str, tuple[str, float | None, bool, float | None]]  # id → (verdict, computed, formula, margin)


def _scalars(node: yaml.Node, keys: tuple[str, ...] = ()) -> Iterable[tuple[tuple[str, ...], yaml.ScalarNode]]:
    if isinstance(node, yaml.ScalarNode):
        yield keys, node
    elif isinstance(node, yaml.MappingNode):
        for k, v in node.value:
            yield from _scalars(v, (*keys, str(k.value)))
    elif isinstance(node, yaml.SequenceNode):
        for i, v in enumerate(node.value):
            yield from _scalars(v, (*keys, str(i)))


def _root(text: str) -> dict[str, yaml.Node]:
    doc = yaml.compose(text, Loader=yaml.SafeLoader)
    return {str(k.value): v for k, v in doc.value}


def _replace(text: str, edits: list[tuple[yaml.ScalarNode, str]]) -> str:
    """``text`` with each scalar's characters replaced (a plain scalar, so the marks bound exactly its token)."""
    for node, new in sorted(edits, key=lambda e: e[0].start_mark.index, reverse=True):
        text = text[:node.start_mark.index] + new + text[node.end_mark.index:]
    return text


def run_rows(path: Path) -> RowResult:
    """The rows of one experiment file, run in this process: id → (verdict, computed, formula)."""
    exp = load_experiment(path, KINDS)
    rep = KINDS[exp.kind].run(exp)
    formula = {p.id: p.formula for p in exp.printed}
    return {r.id: (r.verdict, r.computed, formula[r.id], r.margin) for r in rep.rows}


def mutated(text: str, tolerances: dict[str, float]) -> str:
    """The experiment text with every printed value moved up by ``MUTATION_STEPS`` of its row's tolerance (relative,
    or absolute for a printed 0), written with all its digits."""
    printed = _root(text).get("printed")
    edits = []
    for entry in printed.value if isinstance(printed, yaml.SequenceNode) else ():
        fields = {str(k.value): v for k, v in entry.value}
        value = fields.get("value")
        if value is None or not isinstance(value, yaml.ScalarNode) or value.value in ("", "null", "~"):
            continue
        parsed = parse_number(value.value)
        assert parsed is not None, value.value
        x = parsed[0]
        tol = tolerances[str(fields["id"].value)]
        moved = x + MUTATION_STEPS * tol * (abs(x) if x != 0 else 1.0)
        edits.append((value, repr(moved)))
    return _replace(text, edits)


def _integer(raw: str) -> bool:
    return re.fullmatch(r"[+-]?\d+", raw.strip()) is not None


def perturbed(text: str, rng: np.random.Generator, spread: float) -> str:
    """The experiment text with every non-integer number of ``params`` multiplied by a factor drawn in
    [1 − spread, 1 + spread] (integers are counts and choices: kept)."""
    params = _root(text).get("params")
    edits = []
    for _, node in _scalars(params) if params is not None else ():
        if node.style is not None or (node.tag != "tag:yaml.org,2002:str" and node.tag != "tag:yaml.org,2002:float"):
            continue
        parsed = parse_number(node.value)
        if parsed is None or _integer(node.value):
            continue
        edits.append((node, repr(parsed[0] * (1 + spread * rng.uniform(-1.0, 1.0)))))
    return _replace(text, edits)


def _copy_configs(src: Path, dest: Path) -> Path:
    """A copy of the config folder (its data files included), where edited experiment files can be run."""
    shutil.copytree(src, dest, ignore=shutil.ignore_patterns("__pycache__", "*.pyc"))
    return dest


def _mutation_task(args: tuple[str, str]) -> tuple[str, RowResult | str]:
    path, text = args
    mpath = Path(path).with_name(Path(path).stem + ".mutated.yaml")
    mpath.write_text(text, encoding="utf-8")
    try:
        return path, run_rows(mpath)
    finally:
        mpath.unlink()


def mutation_violations(paths: Iterable[Path], scratch: Path, runner: Callable[[Path], RowResult] = run_rows,
                        baseline: dict[str, RowResult] | None = None) -> list[str]:
    """Rows that read their printed value: a computed value that moved when the printed values moved, or a row
    reproduced before that is still reproduced with its printed value ``MUTATION_STEPS`` tolerances away."""
    out = []
    for path in paths:
        path = Path(path)
        folder = scratch / f"mutation-{path.stem}"
        work = _copy_configs(path.parent, folder)
        exp = load_experiment(work / path.name, KINDS)
        tolerances = {p.id: p.tolerance for p in exp.printed if p.value is not None}
        before = baseline[path.stem] if baseline and path.stem in baseline else runner(work / path.name)
        mpath = work / f"{path.stem}.mutated.yaml"
        mpath.write_text(mutated((work / path.name).read_text(encoding="utf-8"), tolerances), encoding="utf-8")
        after = runner(mpath)
        for rid, (verdict, computed, _, _) in before.items():
            v2, c2, _, _ = after[rid]
            if rid not in tolerances:
                continue
            if computed != c2 and not (computed is not None and c2 is not None and np.isnan(computed)
                                       and np.isnan(c2)):
                out.append(f"{exp.id}/{rid}: its computed value moved with its printed value ({computed!r} → {c2!r})")
            elif verdict == "reproduced" and v2 == "reproduced":
                out.append(f"{exp.id}/{rid}: still reproduced with its printed value {MUTATION_STEPS:g} tolerances "
                           "away (it reads its printed value)")
    return out


def draws(path: Path, work: Path, seed: int, n: int = DRAWS,
          runner: Callable[[Path], RowResult] = run_rows) -> list[RowResult]:
    """The rows of ``n`` admissible perturbations of the experiment's params (a draw the loader or the run refuses is
    drawn again with half the spread, up to ``RETRIES`` times)."""
    text = path.read_text(encoding="utf-8")
    out = []
    for d in range(n):
        rng = np.random.default_rng([seed, d])
        spread = SPREAD
        for _ in range(RETRIES):
            dpath = work / f"{path.stem}.draw{d}.yaml"
            dpath.write_text(perturbed(text, rng, spread), encoding="utf-8")
            try:
                out.append(runner(dpath))
                break
            except InputError:
                spread /= 2
            finally:
                dpath.unlink()
    return out


def identity_flags(baseline: RowResult, drawn: list[RowResult]) -> dict[str, str]:
    """Reproduced rows that no input moves: a formula row whose discrepancy is exactly 0 at every draw (unless it is a
    never/always claim whose worst margin, ``Computed.margin``, moves from draw to draw), a value row whose computed
    value is the same at every draw."""
    flags = {}
    for rid, (verdict, computed, formula, margin) in baseline.items():
        if verdict != "reproduced" or computed is None:
            continue
        values = [computed, *(d[rid][1] for d in drawn)]
        margins = [margin, *(d[rid][3] for d in drawn)]
        # exactly 0 at every draw: the two sides are the same arithmetic (a formula row sampled at scenes of its own,
        # not of the params, may keep a non-zero rounding discrepancy from draw to draw: that is no identity)
        if formula and all(v == 0.0 for v in values):
            if None in margins or len(set(margins)) == 1:
                flags[rid] = (f"its discrepancy is exactly {computed!r} at every one of {len(values)} inputs"
                              + (f", its margin always {margins[0]!r}" if None not in margins else ""))
        elif not formula and all(v == computed for v in values):
            flags[rid] = f"its computed value {computed!r} is the same at every one of {len(values)} inputs"
    return flags


def _identity_task(args: tuple[str, str, int, bool]) -> tuple[str, RowResult | None, list[RowResult]]:
    path, work, seed, base = args
    p = Path(path)
    return p.stem, run_rows(p) if base else None, draws(p, Path(work), seed)


def baselines(paths: Iterable[Path], jobs: int | None = None) -> dict[str, RowResult]:
    """The rows of every file of ``paths`` as shipped, by file stem, run on a process pool (``jobs`` workers, default
    the CPU count): the ``baseline`` that ``mutation_violations`` and ``identity_violations`` may share."""
    paths = [Path(p) for p in paths]
    with ProcessPoolExecutor(max_workers=jobs or os.cpu_count() or 1) as pool:
        return {p.stem: rows for p, rows in zip(paths, pool.map(run_rows, paths), strict=True)}


def identity_violations(paths: Iterable[Path], scratch: Path, seed: int = 35, jobs: int | None = None,
                        baseline: dict[str, RowResult] | None = None) -> list[str]:
    """Rows that no admissible input moves (``identity_flags``), over every file of ``paths``, each run on a process
    pool (``jobs`` workers, default the CPU count); the unperturbed rows are taken from ``baseline`` where it has
    the file (``baselines``), else run."""
    paths = [Path(p) for p in paths]
    baseline = baseline or {}
    folder = _copy_configs(paths[0].parent, scratch / "identity")
    tasks = [(str(folder / p.name), str(folder), seed, p.stem not in baseline) for p in paths]
    out = []
    with ProcessPoolExecutor(max_workers=jobs or os.cpu_count() or 1) as pool:
        for stem, base, drawn in pool.map(_identity_task, tasks):
            base = baseline[stem] if base is None else base
            if len(drawn) < 2:
                out.append(f"{stem}: fewer than 2 admissible draws of its params ({len(drawn)})")
                continue
            out += [f"{stem}/{rid}: {why} (a check that cannot fail)"
                    for rid, why in identity_flags(base, drawn).items()]
    return out


_QUOTE = re.compile(r"«\s*(.*?)\s*»", re.S)


def _norm(s: str) -> str:
    return " ".join(s.replace("’", "'").split())


def quotation_violations(rows: Iterable[tuple[str, dict]]) -> list[str]:
    """``rows``: (experiment, summary row). A row's ``text`` (``printed_text``) holds only words the paper prints; every
    « … » in a note or quantity is held by some row's text."""
    rows = list(rows)
    words = paper.words()
    texts = [_norm(r["printed_text"]) for _, r in rows]
    out = []
    for exp, r in rows:
        foreign = sorted({w for w in paper.WORD.findall(r["printed_text"].replace("’", "'"))
                          if w.lower() not in words})
        if foreign:
            out.append(f"{exp}/{r['id']}: its text has words the paper does not print: {', '.join(foreign)}")
        for field in ("note", "quantity"):
            for q in _QUOTE.findall(r.get(field) or ""):
                if not any(_norm(q) in t for t in texts):
                    out.append(f"{exp}/{r['id']}: its {field} quotes « {q} », which no row's text holds")
    return out
