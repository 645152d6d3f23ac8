"""The decay of a two-component slip under Coulomb friction, shared by §IV (cushion) and §V–§VI (two balls).

In an impulse variable τ, each slip component falls at its own rate, dφ = −α φ/v dτ, dψ = −β ψ/v dτ, with
v = √(φ² + ψ²): the cushion has α = 1 + k, β = k (§IV n°11, eqs 2); two balls on the cloth α ≠ β (§VI
n°13, eqs 1′–6); two free balls α = β, the slip keeps its direction (§V n°12). Then φ = φ0 U^α,
ψ = ψ0 U^β for U from 1 down, and

    τ(U) = ∫_U^1 u^(β−1) √(ψ0² + φ0² u^(2d)) du,  d = α − β ≥ 0,
         = H(1) − H(U),  H(U) = ψ0 U^β/β · ₂F₁(−1/2, β/(2d); β/(2d) + 1; −(φ0/ψ0)² U^(2d)).

The slip stops (both components together) when τ reaches H(1); after that the contact holds with no
friction. For α < β the roles of φ and ψ swap; α = β, ψ0 = 0 or φ0 = 0 have elementary forms.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import NamedTuple

import numpy as np

from .paths import maximum, pick

__all__ = ["SlipDecay", "SlipWalk", "classes", "slip_decay"]


NEWTON_MAXITER = 60  # bound on the Newton iteration; a monotone convex iteration needs ~5-8 steps
NEWTON_RTOL = 1e-14  # stop when the step is below this fraction of x, or the residual below it of H(1)
# (H itself is known to a few ulps, about 1e-15: a tighter test would chase rounding)
NEWTON_FLOOR = 1e-9  # a step that stops shrinking below this has reached the noise of H and of the step's own
# logarithms and powers (with mass ratios of 1e6 it can cycle there: 2 of 1e6 scenes of ``make stress``)


# ---- F(c, w) = ₂F₁(−½, c; c + 1; −w), w ≥ 0: the slip-decay function (§IV n°11 eq. (10), §VI n°13) -----------
# F = c ∫_0^1 t^(c−1) √(1 + w t) dt = c w^(−c) G_c(w), G_c(w) = ∫_0^w u^(c−1) √(1 + u) du. Three convergent
# series, each with a proven bound on its truncation (tests/test_slip_kernel.py checks them against mpmath):
#   w ≤ 1, or c ≥ C_BIG: Pfaff's form √(1 + w) Σ p_n y^n, y = w/(1 + w), p_{n+1} = p_n (n − ½)/(n + c + 1);
#     the terms after the first share a sign (no cancellation) and Σ_{n≥K} |p_n| = |p_K| (K + c)/(c + ½), so
#     with y ≤ ½ the tail is below 2 |p_K| 2^(−K), and for c ≥ C_BIG below |p_K|(K + c)/(c + ½) at any y ≤ 1;
#   w > 1, c ≤ C_SERIES: G_c(w) = G_c(1) + ∫_v^½ (1 − s)^(c−1) s^(−c−3/2) ds, s = 1/(1 + u), v = 1/(1 + w),
#     with (1 − s)^(c−1) = Σ b_m s^m (ratio ≤ ½): Σ b_m (½^(e_m) − v^(e_m))/e_m, e_m = m − c − ½. The one term
#     with |e_m| ≤ ½ is written v^e expm1(e ln(½/v))/e, which has no pole: nothing degenerates at c = ½ + m
#     (where the classical connection formulas for z → −∞ need log terms); the others split into a constant
#     of c and a power series in v;
#   w > 1, C_SERIES < c < C_BIG: that series at c − j (j ≤ C_BIG − C_SERIES), then j steps of the contiguous
#     relation F(c + 1) = (c + 1)/(c + 3/2) [√(1 + w)(1 + 1/w) − F(c)/w] (from integrating G_(c+1) by parts),
#     which contracts errors for w ≥ 1 (its factor F(c)/((1 + w)^(3/2) − F(c)) is below 1 there).
# The series for w > 1 cancels as ~ (3/2)^c, hence C_SERIES; Pfaff's needs ≤ 47 terms at y = 1 from c = 16.
C_SERIES = 3.0
C_BIG = 16.0
N_PFAFF = 52  # 2 |p_52| 2^−52 < 4e-19 for every c > 0
N_SPLIT = 60  # 2^(c+1) (c + ½) |b_60/e_60| 2^−60 < 1e-18 for c ≤ C_SERIES


def _horner(coef: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Σ_n coef[n] x^n (rows of ``coef`` broadcast against x). One value is summed in floats, by the same
    loop (a numpy call on one element costs a microsecond); a numpy float (one scene, ``paths.Path.scalar``)
    gives one."""
    if isinstance(coef, np.ndarray) and coef.shape[-1] == 1 and np.size(x) == 1:
        if x.__class__ is np.float64:
            return np.float64(_horner(coef[:, 0].tolist(), float(x)))  # type: ignore[arg-type]
        return np.full(np.broadcast_shapes(coef.shape[1:], np.shape(x)),
                       _horner(coef[:, 0].tolist(), float(np.ravel(x)[0])))  # type: ignore[arg-type]
    acc = coef[-1] * x
    for row in coef[-2:0:-1]:
        acc += row
        acc *= x
    acc += coef[0]
    return acc


class _Series(NamedTuple):
    """The coefficients of ``_F``'s series for given c (rows: terms; columns: scenes, or one column for a class
    of scenes sharing c)."""
    c: np.ndarray
    p: np.ndarray  # Pfaff's coefficients at c
    j: np.ndarray  # contiguous steps from c0 = c − j to c (0 for c ≤ C_SERIES)
    g: np.ndarray  # b_m/e_m at c0 (0 at m = m*)
    mstar: np.ndarray  # m* = ⌊c0 + 1⌋, where |e_m| ≤ ½
    estar: np.ndarray
    bstar: np.ndarray
    const: np.ndarray  # G_c0(1) + Σ_(m≠m*) b_m ½^(e_m)/e_m


def _series(c: np.ndarray) -> _Series:
    """``_F``'s coefficients for the c of a 1-D array (comment above ``C_SERIES``), as many terms as the bounds
    there need for these c (to 2^-56 of F, which is ≥ √(1 + w) max(c/(c + ½), 1/√2))."""
    c = np.asarray(c, dtype=float)
    big = c >= C_BIG
    j = np.where(big, 0.0, np.maximum(np.ceil(c - C_SERIES), 0.0))
    c0 = np.where(big, C_SERIES, c - j)  # (unused from C_BIG: kept finite)
    p = _pfaff_terms(c, np.where(big, 1.0 / c, 2 * np.sqrt(2.0)), big)
    p0 = p if not j.any() else _pfaff_terms(c0, np.full(c.shape, 2 * np.sqrt(2.0)), np.zeros(c.shape, bool))
    mstar = np.floor(c0 + 1)
    bstar, b = np.zeros(c.shape), np.ones(c.shape)
    weight = 2 ** (c0 + 1) * (c0 + 0.5)  # the tail bound 2^(c0+1) (c0 + ½) |g_K| 2^−K, from K > c0 + 1
    stars = set(np.unique(mstar).tolist())  # the few m* of these c (the rows without one need no mask)
    top = float(np.max(c0 + 1)) if c.size else -np.inf
    rows = np.empty((N_SPLIT, c.size))

    def enough(m: int) -> bool:  # every column's tail below the bound (×2^−m is exact: the largest term decides)
        return m > top and (not c.size or float(np.max(weight * np.abs(rows[m]))) * 0.5**m <= 2.0**-56)

    last, checked = N_SPLIT - 1, 0
    for m in range(N_SPLIT):
        if m in stars:
            star = mstar == m
            rows[m] = np.where(star, 0.0, b / np.where(star, 1.0, m - c0 - 0.5))
            bstar = np.where(star, b, bstar)
        else:
            np.divide(b, m - c0 - 0.5, out=rows[m])
        if _tested(m, N_SPLIT):
            if enough(m):
                last = _first(enough, checked, m)
                break
            checked = m + 1
        b = b * ((m + 1 - c0) / (m + 1))
    g = rows[:last + 1]
    const = np.sqrt(2.0) * _horner(p0, 0.5) / c0 + 2 ** (c0 + 0.5) * _horner(g, 0.5)
    return _Series(c, p, j, g, mstar, mstar - c0 - 0.5, bstar, const)


def _pfaff_terms(c: np.ndarray, weight: np.ndarray, big: np.ndarray) -> np.ndarray:
    """Pfaff's coefficients p_n (rows) for the c of a 1-D array, up to the bound of the comment above
    ``C_SERIES``: weight |p_K| 2^−K (y ≤ ½) or, where ``big``, weight |p_K| (K + c) (any y ≤ 1)."""
    rows, t = np.empty((N_PFAFF, c.size)), np.ones(c.shape)
    rows[0] = t
    some_big = bool(big.any())

    def enough(n: int) -> bool:  # the bound met after row n + 1
        t = rows[n + 1]
        if some_big:
            return bool(np.all(weight * np.abs(t) * np.where(big, n + 1 + c, 0.5 ** (n + 1)) <= 2.0**-56))
        return not c.size or float(np.max(weight * np.abs(t))) * 0.5 ** (n + 1) <= 2.0**-56  # (×2^−n−1: exact)

    last, checked = N_PFAFF - 2, 0
    for n in range(N_PFAFF - 1):
        t = np.multiply(t, (n - 0.5) / (n + c + 1), out=rows[n + 1])
        if _tested(n, N_PFAFF - 1):
            if enough(n):
                last = _first(enough, checked, n)
                break
            checked = n + 1
    return rows[:last + 2]


TEST_EVERY = 4  # ``_series``'s truncation tests on every 4th row only (``_first``)


def _tested(i: int, count: int) -> bool:
    """Whether ``_series`` tests its truncation at row i of ``count``: every ``TEST_EVERY``-th, and the last."""
    return i % TEST_EVERY == TEST_EVERY - 1 or i == count - 1


def _first(enough: Callable[[int], bool], checked: int, i: int) -> int:
    """The first k in [checked, i] with ``enough(k)``, given ``enough(i)``: the truncation tests of ``_series`` and
    ``_pfaff_terms`` (each a pass over the columns) are made on every ``TEST_EVERY``-th row only, which ends at the
    same row as testing every one, since their quantities (a bound times |row k|, at most half the previous one)
    decrease with k: once one passes, every later one does."""
    return next(k for k in range(checked, i + 1) if enough(k))


@lru_cache(maxsize=64)
def _class_series(c: float) -> _Series:
    """``_series`` for one c, as columns that broadcast; at the multiple of ¼ that c is within a class's rounding of
    (``CLASS_ULPS``: c = 5/4 on the cloth for k = k′ = 5/2 carries 14 ulps), where ``_split_sum`` takes its powers
    by square roots (F moves by less than that rounding)."""
    q = round(4 * c) / 4
    if q > 0 and abs(c - q) <= CLASS_ULPS * min(1 + 2 * c, 8.0) * np.spacing(c):
        c = q
    return _series(np.array([c]))


@lru_cache(maxsize=64)
def _class_scalars(c: float) -> _Series:
    """``_class_series`` for one scene as numpy floats (``paths.Path.scalar``): the per-column fields as numpy
    floats, the rows of coefficients as they are (``_horner`` sums one column in floats either way)."""
    s = _class_series(c)
    return s._replace(**{k: getattr(s, k)[0] for k in ("c", "j", "mstar", "estar", "bstar", "const")})


CLASS_ULPS = 8  # c's within 8 min(1 + 2c, 8) ulps of one another are one class: c = β/(2(α − β)) carries that
# much rounding, α/(α − β) = 1 + 2c amplifying that of α and β (k = k′ = 2.5 on the cloth: 1.25 ± 14 ulps);
# F, whose elasticity in c is below 1, moves by less than half that spread (tests/test_slip_kernel.py)


def _series_of(c: np.ndarray) -> _Series:
    """``_F``'s coefficients for the c of a 1-D array: one column, at the middle of their range, where they
    agree to their rounding (c = k/2 on the cushion, and on the cloth whenever k = k′: ``CLASS_ULPS``; F moves
    by less than that relative to c), else one per element."""
    c = np.asarray(c, dtype=float)
    one = _class_of(c)
    return _series(c) if one is None else _class_series(one)


def _class_of(c: np.ndarray) -> float | None:
    """The one c of ``_series_of``'s class where the c of a 1-D array are one, else None."""
    if c.size:
        lo, hi = float(np.min(c)), float(np.max(c))
        if hi - lo <= CLASS_ULPS * min(1 + 2 * hi, 8.0) * np.spacing(hi):
            return lo + 0.5 * (hi - lo)
    return None


CLASSES_MAX = 64  # ``classes``: at most this many classes of c (``_class_series``'s cache holds as many)
CLASS_MIN = 2048  # ``classes``: scenes per class at least, on average; below it one table of columns is cheaper
# (a batch of 2048 scenes on the cloth takes about 6 ms, a third of it the call's fixed cost: measured in issue 34)
CLASS_FEW = CLASS_MIN // 4  # ``classes``: a class with fewer scenes joins the others of its size in one table


def classes(alpha: np.ndarray, beta: np.ndarray) -> list[np.ndarray] | None:
    """The scenes of a 1-D batch of decays (``SlipDecay``'s α, β) grouped by their c = b/(2(a − b)) of ``_F``
    (a ≥ b the larger and the smaller of α and β: ``_general``, the same floats), as the indices of each group in
    increasing order of c, when the batch's c are not one class (``_class_of``) but a few exact values: at most
    ``CLASSES_MAX`` of them, with ``CLASS_MIN`` scenes or more each on average (the classes of fewer than
    ``CLASS_FEW`` scenes together, last: one table). Else None. A way of computing §VI n°13's slip decay, nothing of
    the paper's: a batch of balls of a few kinds (k, k′ and M/M′ of a few values) is then solved group by group,
    each group one class whose coefficients broadcast, where one table of a column per scene (``_series``,
    ``_layout``) costs twice the time per scene. Each scene gets the numbers of a batch of its class: bit for bit
    those it gets alone where the class has one c, else within the class's rounding, as in any batch of one class
    (``_class_of``: the middle of its c; a class at a multiple of ¼, as k = k′ = 5/2's c = 5/4, is snapped to it
    either way)."""
    n = alpha.size
    if n < 2 * CLASS_MIN:
        return None
    with np.errstate(divide="ignore", invalid="ignore"):
        a, b = np.maximum(alpha, beta), np.minimum(alpha, beta)
        c = b / (2 * (a - b))
    if _class_of(c) is not None:
        return None
    most = min(CLASSES_MAX, n // CLASS_MIN)
    if np.unique(c[:: max(1, n // (8 * most))]).size > most:  # a sample with too many already: a table
        return None
    values, inverse = np.unique(c, return_inverse=True)
    if values.size > most or np.isnan(values).any():
        return None
    # neighbouring values within one class's rounding (``_class_of``: k = k′ with masses of several kinds) are one
    start, label = 0, np.empty(values.size, dtype=np.intp)
    for j in range(values.size):
        if _class_of(values[start:j + 1]) is None:
            start = j
        label[j] = start
    inverse = label[inverse]
    groups = [np.flatnonzero(inverse == j) for j in np.unique(label)]
    # a class of few scenes would cost a call for little: those go together, as one table (``_F_blocks``), at the end
    few = [g for g in groups if g.size < CLASS_FEW]
    if few:
        groups = [g for g in groups if g.size >= CLASS_FEW] + [np.sort(np.concatenate(few))]
    return groups if len(groups) > 1 else None


def _cols(a: np.ndarray, i: np.ndarray | slice) -> np.ndarray:
    """The columns ``i`` of a coefficient array, or the one column that broadcasts. (``np.take``: its result is laid
    out row by row, as ``_horner`` reads it; ``a[..., i]`` gives one column after another, and Horner's rows then
    read memory with a stride of a column, several times slower.)"""
    if a.shape[-1] == 1:
        return a
    return a[..., i] if isinstance(i, slice) else np.take(a, i, axis=-1)


def _take(s: _Series, i: np.ndarray | slice) -> _Series:
    return s if s.p.shape[-1] == 1 else _Series(*(_cols(a, i) for a in s))


def _F(c: np.ndarray | None, z: np.ndarray, series: _Series | None = None,
       layout: tuple[np.ndarray, int] | None = None) -> np.ndarray:
    """₂F₁(−½, c; c + 1; z) for c > 0, z ≤ 0, to a few ulps (comment above ``C_SERIES``); ``series``: the
    coefficients for c (``_series_of``) if known, one column or one per element; ``layout``: for a column per
    element, the columns' order and their cut into the two series (``_F_blocks``)."""
    if z.__class__ is np.float64 and series is not None and series.c.__class__ is np.float64:
        w = -z  # one scene as a numpy float (``_class_scalars``): the same sums, chosen without masks
        return _pfaff_sum(w, series.p) if w <= 1 or series.c >= C_BIG else _split_sum(w, series)
    z = np.asarray(z, dtype=float)
    if series is None:  # (c may be None when ``series`` is given)
        c, z = np.broadcast_arrays(np.asarray(c, dtype=float), z)
        series = _series_of(c.ravel())
    shape, w, s = z.shape, -z.ravel(), series
    if w.size == 0:
        return np.empty(shape)
    if layout is not None and s.p.shape[-1] > 1:
        return _F_blocks(w, s, *layout).reshape(shape)
    pfaff = (w <= 1) | (s.c >= C_BIG)
    if pfaff.all():
        return _pfaff_sum(w, s.p).reshape(shape)
    if not pfaff.any():
        return _split_sum(w, s).reshape(shape)
    if s.p.shape[-1] > 1:  # a column per element: both series on every element (cheaper than gathering columns)
        with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
            return np.where(pfaff, _pfaff_sum(w, s.p), _split_sum(np.maximum(w, 1.0), s)).reshape(shape)
    out = np.empty(w.shape)
    i = np.nonzero(pfaff)[0]
    out[i] = _pfaff_sum(w[i], s.p)
    i = np.nonzero(~pfaff)[0]
    out[i] = _split_sum(w[i], s)
    return out.reshape(shape)


def _F_blocks(w: np.ndarray, s: _Series, order: np.ndarray, cut: int) -> np.ndarray:
    """``_F`` on a column of coefficients per element whose columns are laid out by the series each needs: column
    j is element ``order[j]``'s, and the first ``cut`` columns are Pfaff's (w ≤ 1 or c ≥ C_BIG where w is largest,
    x = 1: ``SlipDecay``), the others the split series'. Each block sums its own series on a slice of the table
    (no gather, half the rows read, the split series' logarithms and powers on its block only); the few elements
    whose w has crossed 1 since (x falls, and w = r2 x^e2 with it) take the other series on their own columns.
    The same sums per element as both series on every element, chosen by ``_F``'s test."""
    wc, n = w[order], w.size
    res, out = np.empty(n), np.empty(n)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        if cut:
            res[:cut] = _pfaff_sum(wc[:cut], s.p[:, :cut])
            mis = np.flatnonzero(~((wc[:cut] <= 1) | (s.c[:cut] >= C_BIG)))
            if mis.size:
                res[mis] = _split_sum(wc[mis], _take(s, mis))
        if cut < n:
            back = wc[cut:]
            res[cut:] = _split_sum(np.maximum(back, 1.0), _take(s, slice(cut, None)))
            mis = cut + np.flatnonzero((back <= 1) | (s.c[cut:] >= C_BIG))
            if mis.size:
                res[mis] = _pfaff_sum(wc[mis], s.p[:, mis])
    out[order] = res
    return out


def _layout(c: np.ndarray, r2: np.ndarray) -> tuple[np.ndarray, int]:
    """``_F_blocks``'s layout for the c of a table and r2 = w at x = 1: Pfaff's columns first (stable order)."""
    split = ~((r2 <= 1) | (c >= C_BIG))
    return np.argsort(split, kind="stable"), int(np.count_nonzero(~split))


def _pfaff_sum(w: np.ndarray, p: np.ndarray) -> np.ndarray:
    """F by Pfaff's series (w ≤ 1, or c ≥ C_BIG; comment above ``C_SERIES``), coefficients ``p``."""
    return np.sqrt(1 + w) * _horner(p, w / (1 + w))


def _split_sum(w: np.ndarray, s: _Series) -> np.ndarray:
    """F for w ≥ 1 by the series in v = 1/(1 + w), then the contiguous relation (comment above ``C_SERIES``).
    The powers w^(−c0), (1 + 1/w)^c0 and ((1 + w)/2)^(e*) by square roots where c0 (one for all) is a multiple
    of ¼ (``_quarters``: c = k/2 = 5/4 on the cloth for solid balls, k = k′ = 5/2), else by exponentials."""
    j, es = s.j, s.estar
    c0 = s.c - j
    v, root, q = 1 / (1 + w), np.sqrt(1 + w), 1 + 1 / w
    half = (1 + w) * 0.5  # ½/v
    quarters = _quarters(c0, es)
    if quarters is not None:  # the same terms, their powers by square roots (to an ulp or two, as exp and log)
        c4, e4 = quarters
        with np.errstate(invalid="ignore", divide="ignore"):
            E = np.log(half) if e4 == 0 else (_quarter_power(half, e4) - 1) / es
        wc, qc = _quarter_power(w, -c4), _quarter_power(q, c4)
    else:
        L = np.log(half)
        with np.errstate(invalid="ignore", divide="ignore"):
            E = pick(es == 0, L, np.expm1(es * L) / es)
        # (1 + 1/w)^c0 = exp(c0 ln q): q's rounding, below an ulp of q, moves the power by c0 of it (log1p of 1/w
        # is not needed for that, and costs twice the logarithm)
        wc, qc = np.exp(-c0 * np.log(w)), np.exp(c0 * np.log(q))
    f = c0 * (wc * s.const + root * qc * (s.bstar * _int_power(v, s.mstar) * E - _horner(s.g, v)))
    for step in range(int(np.max(j))):  # the contiguous relation up to c
        cc = c0 + step
        f = pick(j > step, (cc + 1) / (cc + 1.5) * (root * (1 + 1 / w) - f / w), f)
    return f


def _quarters(c0: np.ndarray, es: np.ndarray) -> tuple[int, int] | None:
    """(4 c0, 4 e*) as integers where ``_split_sum``'s c0 is one number (a class of scenes, one scene) and a
    multiple of ¼ (then so is e* = m* − c0 − ½), else None."""
    if np.size(c0) != 1:
        return None
    c4 = 4 * float(c0 if c0.__class__ is np.float64 else c0.ravel()[0])
    if c4 != int(c4) or c4 > 4 * C_SERIES:
        return None
    e4 = 4 * float(es if es.__class__ is np.float64 else es.ravel()[0])
    return int(c4), int(e4)


def _quarter_power(x: np.ndarray, e4: int) -> np.ndarray:
    """x^(e4/4) for x > 0 by products of x, √x and ∜x (``_split_sum``: to an ulp or two, as exp(e ln x), at a
    fraction of its cost); a negative power as the positive one of 1/x."""
    if e4 < 0:
        x, e4 = 1 / x, -e4
    n, r = divmod(e4, 4)
    out = None
    if r:
        s = np.sqrt(x)
        out = s if r == 2 else np.sqrt(s) if r == 1 else s * np.sqrt(s)
    for _ in range(n):
        out = x if out is None else out * x
    if out is None:  # x^0
        return np.ones_like(x) if x.__class__ is np.ndarray else np.float64(1.0)
    return out


def _int_power(v: np.ndarray, m: np.ndarray) -> np.ndarray:
    """v^m for ``_split_sum``'s m* = ⌊c0 + 1⌋, an integer from 1 to ⌊C_SERIES⌋ + 1, by products (to an ulp or two,
    as np.power; it costs as much as twenty); one m for all (a class of scenes, one scene) or one per element."""
    out, top = v, int(np.max(m))
    for k in range(2, top + 1):
        out = out * v if np.size(m) == 1 else pick(m >= k, out * v, out)
    return out


def _H(x: np.ndarray, phi0: np.ndarray, psi0: np.ndarray, beta: np.ndarray, d: np.ndarray,
       series: _Series | None = None) -> np.ndarray:
    """τ(0) − τ(U) = ∫_0^U u^(β−1) √(ψ0² + φ0² u^(2d)) du as a function of x = U^β (module docstring);
    ``series``: ``_F``'s coefficients for c = β/(2d)."""
    c = beta / (2 * d)
    return _H_of(x, x ** (1 / c), (phi0 / psi0) ** 2, psi0 / beta, _series_of(c) if series is None else series)


def _H_of(x: np.ndarray, u: np.ndarray, r2: np.ndarray, scale: np.ndarray, series: _Series,
          layout: tuple[np.ndarray, int] | None = None) -> np.ndarray:
    """``_H`` from u = x^(2d/β) = U^(2d), r2 = (φ0/ψ0)² and scale = ψ0/β (``layout``: as for ``_F``)."""
    return scale * x * _F(None, -r2 * u, series, layout)


def _solve_x(target: np.ndarray, total: np.ndarray, e2: np.ndarray, r2: np.ndarray, scale: np.ndarray,
             series: _Series, x0: np.ndarray | None = None, h0: np.ndarray | None = None
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """x in (0, 1] with H(x) = target, 0 < target < H(1) = total, by Newton's method on G(y) = ln H(e^y) − ln
    target, y = ln x. G is increasing and convex (its slope x H′(x)/H(x), the elasticity of H, grows from 1 near
    x = 0 to 1 + 2d/β where φ dominates), so Newton from y = 0 descends monotonically onto the root without
    overshooting, and where H is a power of x (a slip dominated by one component, mass ratios far from 1) it
    lands in one step; Newton in x itself then crawls (a factor 1 − 1/m per step for H ∝ x^m: 66 steps for a
    mass ratio of 1e6 on the cloth). Stops when the step moves x by less than ``NEWTON_RTOL`` of itself or the
    residual is below it of H(1), or when a step below ``NEWTON_FLOOR`` fails to halve (Newton converges
    quadratically until the noise of H stops it); raises past ``NEWTON_MAXITER`` steps. A start ``x0`` left of
    the root costs one step more: by convexity the first step lands right of it. ``e2``, ``r2``, ``scale``
    and ``series`` as in ``_H_of`` (u = x^e2; H′(x) = scale √(1 + r2 u)); ``h0``: H(x0) where known (nan
    elsewhere; a previous root's target). Returns x, H(x) and u."""
    if x0 is None:
        x, h = np.ones_like(total), total.copy()
    else:
        x = np.where(np.isfinite(x0) & (x0 > 0), np.minimum(x0, 1.0), 1.0)  # a slip that stopped: start at 1
        h = np.array(h0, dtype=float) if h0 is not None else np.full(x.shape, np.nan)
        h[x != x0] = np.nan  # the start moved: its H is not known
        k = np.nonzero(np.isnan(h))[0]
        if k.size:
            h[k] = _H_of(x[k], x[k] ** e2[k], r2[k], scale[k], _take(series, k))
        cold = ~(h > 0)  # H underflowed at a tiny start: the logarithm needs H > 0
        x[cold], h[cold] = 1.0, total[cold]
    u = np.power(x, e2)
    live = np.ones(x.shape, dtype=bool)
    last = np.full(x.shape, np.inf)  # the previous step's size
    gather = series.p.shape[-1] == 1  # else the scenes that converged step on, unchanged (gathering the
    # coefficients of the live ones would cost more)
    for _ in range(NEWTON_MAXITER):
        if not live.any():
            return x, h, u
        i = np.nonzero(live)[0] if gather and not live.all() else slice(None)
        xi, ri, si, lv = x[i], r2[i], scale[i], live[i]
        step = np.where(lv, _log_step(xi, h[i], u[i], target[i], ri, si), 0.0)
        xn = np.minimum(xi * np.exp(-step), 1.0)
        un = np.power(xn, e2[i])
        hn = _H_of(xn, un, ri, si, _take(series, i))
        x[i], u[i], h[i] = xn, un, hn
        size = np.abs(step)
        done = _solved(size, hn, target[i], total[i], last[i])
        last[i] = np.where(lv, size, last[i])
        live[i] = lv & ~done
    if live.any():
        raise ArithmeticError(f"slip decay: Newton did not converge in {NEWTON_MAXITER} steps for "
                              f"{int(live.sum())} scene(s)")
    return x, h, u


def _alone(x0: np.ndarray, rate: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """A slip with one component (or both decaying at one rate, α = β: its magnitude): dx = −rate dτ while
    x > 0, then 0 (the elementary decays of the module docstring)."""
    return maximum(x0 - rate * tau, _ZERO)


_ZERO = np.float64(0.0)


def _together(phi0: np.ndarray, psi0: np.ndarray, rate: np.ndarray, tau: np.ndarray
              ) -> tuple[np.ndarray, np.ndarray]:
    """α = β (§V n°12, two free balls): the slip keeps its direction, its magnitude decays as ``_alone``."""
    v0 = np.hypot(phi0, psi0)
    shrink = _alone(v0, rate, tau) / v0
    return phi0 * shrink, psi0 * shrink


def _log_step(x: np.ndarray, h: np.ndarray, u: np.ndarray, target: np.ndarray, r2: np.ndarray, scale: np.ndarray
              ) -> np.ndarray:
    """``_solve_x``'s Newton step in y = ln x: (ln H − ln target)/E, E = dG/dy = x H′(x)/H the elasticity."""
    elasticity = x * scale * np.sqrt(1 + r2 * u) / h
    return (np.log(h) - np.log(target)) / elasticity


def _solved(size: np.ndarray, h: np.ndarray, target: np.ndarray, total: np.ndarray, last: np.ndarray) -> np.ndarray:
    """``_solve_x``'s convergence test after a step of ``size`` (the previous one ``last``) that gave H = h."""
    return ((size <= NEWTON_RTOL) | (np.abs(h - target) <= NEWTON_RTOL * total)
            | ((size <= NEWTON_FLOOR) & (size >= 0.5 * last)))  # stalled at the noise of H


def _solve_x_one(target: np.float64, total: np.float64, e2: np.float64, r2: np.float64, scale: np.float64,
                 series: _Series) -> tuple[np.float64, np.float64, np.float64]:
    """``_solve_x`` from x = 1 for one scene as numpy floats (``_class_scalars``): the same steps and test
    (``_log_step``, ``_solved``), one scene needing no masks."""
    x, h, last = np.float64(1.0), total, np.float64(np.inf)
    u = np.power(x, e2)
    for _ in range(NEWTON_MAXITER):
        step = _log_step(x, h, u, target, r2, scale)
        x = np.minimum(x * np.exp(-step), 1.0)
        u = np.power(x, e2)
        h = _H_of(x, u, r2, scale, series)
        size = np.abs(step)
        if _solved(size, h, target, total, last):
            return x, h, u
        last = size
    raise ArithmeticError(f"slip decay: Newton did not converge in {NEWTON_MAXITER} steps for 1 scene(s)")


def _general(phi0: np.ndarray, psi0: np.ndarray, d: np.ndarray, beta: np.ndarray
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """c = β/(2d) of ``_F`` and, for ``_H_of``, e2 = 1/c (u = x^e2), r2 = (φ0/ψ0)² and scale = ψ0/β."""
    c = beta / (2 * d)
    q = phi0 / psi0
    return c, 1 / c, q * q, psi0 / beta


class SlipDecay:
    """The decay of given initial slips, for several impulses τ: H(1) is computed once, and each solve may start
    from the x of a previous one (the §VI fixed point calls it repeatedly with nearby τ). 1-D arrays. Where the
    scenes' c differ (a table of ``_F``'s coefficients, a column per scene: k ≠ k′ on the cloth), the columns are
    laid out by the series each scene needs at x = 1 (``layout``, ``_F_blocks``) and ``col`` gives each scene's."""

    def __init__(self, phi0: np.ndarray, psi0: np.ndarray, alpha: np.ndarray, beta: np.ndarray) -> None:
        phi0, psi0, alpha, beta = np.broadcast_arrays(*(np.asarray(x, dtype=float).ravel()
                                                        for x in (phi0, psi0, alpha, beta)))
        self.swap = alpha < beta
        self.f0, self.s0 = np.where(self.swap, psi0, phi0), np.where(self.swap, phi0, psi0)
        self.a, self.b = np.where(self.swap, beta, alpha), np.where(self.swap, alpha, beta)
        self.only_f = self.s0 == 0
        self.only_s = (self.f0 == 0) & ~self.only_f
        self.iso = (self.a == self.b) & ~self.only_f & ~self.only_s
        self.gen = ~self.only_f & ~self.only_s & ~self.iso
        g = self.gen
        d = np.where(g, self.a - self.b, 1.0)  # (elsewhere unused: kept finite)
        b, s0 = np.where(g, self.b, 1.0), np.where(g, self.s0, 1.0)
        # per scene, for ``_H_of``: u = x^e2, H(x) = scale x F(c, −r2 u); ``_F``'s coefficients, one column per
        # scene or one for all (``_series_of``: the other scenes take the first general scene's c)
        c, self.e2, self.r2, self.scale = _general(self.f0, s0, d, b)
        self.series, self.layout, self.col = None, None, None
        if g.any():
            cg = np.where(g, c, c[np.argmax(g)])
            one = _class_of(cg)
            if one is not None:
                self.series = _class_series(one)
            else:  # a table: its columns laid out by series (``_F_blocks``); ``col``: each scene's column
                self.layout = _layout(cg, self.r2)
                self.series = _series(cg[self.layout[0]])
                self.col = np.empty(g.size, dtype=np.intp)
                self.col[self.layout[0]] = np.arange(g.size)
        self.total = np.where(g, self.scale * _F(None, -self.r2, self.series, self.layout), np.nan) if g.any() \
            else np.full(g.shape, np.nan)
        self.special = not g.all()  # scenes with an elementary decay
        self.swapped = bool(self.swap.any())
        self.xlast, self.hlast = np.full(g.shape, np.nan), np.full(g.shape, np.nan)  # the last root, its H
        self.everyone = np.arange(g.size)

    def at(self, tau: np.ndarray, idx: np.ndarray, x0: np.ndarray | None = None
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(|φ1|, |ψ1|, x) for the scenes ``idx`` after the impulses ``tau``; x = U^β where the slip turns
        (nan elsewhere); ``x0`` a start for the Newton solve (nan: none). A start that is the scene's last root
        reuses its H (the last target), which saves an evaluation."""
        T = np.asarray(tau, dtype=float)
        f0, s0 = self.f0[idx], self.s0[idx]
        if self.special:
            f1, s1, x = np.zeros_like(f0), np.zeros_like(s0), np.full(f0.shape, np.nan)
            a, b = self.a[idx], self.b[idx]
            o = self.only_f[idx]
            f1[o] = _alone(f0[o], a[o], T[o])
            o = self.only_s[idx]
            s1[o] = _alone(s0[o], b[o], T[o])
            o = self.iso[idx]
            f1[o], s1[o] = _together(f0[o], s0[o], a[o], T[o])
            g = self.gen[idx]
            gi, F0, S0, Tg = idx[g], f0[g], s0[g], T[g]
        else:
            g, gi, F0, S0, Tg = slice(None), idx, f0, s0, T
            if not F0.size:
                return f0.copy(), s0.copy(), np.full(f0.shape, np.nan)
        if F0.size:
            total = self.total[gi]
            xg = np.where(Tg <= 0, 1.0, 0.0)
            ug = xg.copy()  # u = x^(2d/β): φ1 = φ0 x^(α/β) = φ0 x √u
            go = (Tg < total) & (Tg > 0)
            if go.any():
                go = slice(None) if go.all() else np.nonzero(go)[0]
                k = gi[go]
                cols = slice(None) if k.size == self.total.size and np.all(k == self.everyone) else k
                start = h0 = None
                if x0 is not None:
                    start = np.asarray(x0)[g][go]
                    h0 = np.where(start == self.xlast[k], self.hlast[k], np.nan)
                    start = np.where(np.isfinite(start), start, 1.0)
                sol, hs, ug[go] = _solve_x(total[go] - Tg[go], total[go], self.e2[k], self.r2[k], self.scale[k],
                                           _take(self.series, cols if self.col is None else self.col[cols]),
                                           start, h0)
                xg[go] = sol
                self.xlast[k], self.hlast[k] = sol, hs
            if not self.special:
                f1, s1, x = F0 * xg * np.sqrt(ug), S0 * xg, xg
            else:
                f1[g], s1[g], x[g] = F0 * xg * np.sqrt(ug), S0 * xg, xg
        if not self.swapped:
            return f1, s1, x
        sw = self.swap[idx]
        return np.where(sw, s1, f1), np.where(sw, f1, s1), x


def slip_decay(phi0: np.ndarray, psi0: np.ndarray, alpha: np.ndarray, beta: np.ndarray,
               tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Slip components (|φ1|, |ψ1|) after the impulse τ ≥ 0, from |φ0|, |ψ0| ≥ 0 (module docstring). One scene
    as numpy floats (``paths.Path.scalar``) with an elementary decay takes ``SlipDecay.at``'s own formulas without
    its arrays and masks (its branches in its order: ψ0 = 0, then φ0 = 0, then α = β); the same numbers."""
    if phi0.__class__ is psi0.__class__ is alpha.__class__ is beta.__class__ is tau.__class__ is np.float64:
        one = _DecayOne(phi0, psi0, alpha, beta)
        if one.kind != _TURNS:
            return one.elementary(tau)
        # the slip turns: ``SlipDecay.at`` for one scene (x = U^β from 1, ``_solve_x``)
        x = u = np.float64(1.0 if tau <= 0 else 0.0)
        if tau < one.total and tau > 0:
            x, _, u = _solve_x_one(one.total - tau, one.total, one.e2, one.r2, one.scale, one.series)
        f1, s1 = one.f0 * x * np.sqrt(u), one.s0 * x
        return (s1, f1) if one.swap else (f1, s1)
    arrays = np.broadcast_arrays(*(np.asarray(x, dtype=float) for x in (phi0, psi0, alpha, beta, tau)))
    shape = arrays[0].shape
    f1, s1, _ = SlipDecay(*arrays[:4]).at(arrays[4].ravel(), np.arange(arrays[0].size))
    return f1.reshape(shape), s1.reshape(shape)


_ONLY_F, _ONLY_S, _ISO, _TURNS = range(4)  # ``SlipDecay``'s classes of scenes (only_f, only_s, iso, gen)


class _DecayOne:
    """``SlipDecay`` for one scene as numpy floats (``paths.Path.scalar``): the same roles (φ, ψ swapped for
    α < β), the class of the decay (tested in ``SlipDecay``'s order), and for a turning slip ``_general``'s
    coefficients, ``_F``'s (``_class_scalars``: one c, its own class, as ``_series_of`` gives it) and H(1)."""

    __slots__ = ("a", "b", "e2", "f0", "kind", "r2", "s0", "scale", "series", "swap", "total")

    def __init__(self, phi0: np.float64, psi0: np.float64, alpha: np.float64, beta: np.float64) -> None:
        self.swap = bool(alpha < beta)
        if not self.swap:
            self.f0, self.s0, self.a, self.b = phi0, psi0, alpha, beta
        else:
            self.f0, self.s0, self.a, self.b = psi0, phi0, beta, alpha
        self.kind = (_ONLY_F if self.s0 == 0 else _ONLY_S if self.f0 == 0 else _ISO if self.a == self.b
                     else _TURNS)
        if self.kind == _TURNS:
            c, self.e2, self.r2, self.scale = _general(self.f0, self.s0, self.a - self.b, self.b)
            self.series = _class_scalars(float(c))
            self.total = self.scale * _F(None, -self.r2, self.series)

    def elementary(self, tau: np.float64) -> tuple[np.float64, np.float64]:
        """``SlipDecay.at`` for an elementary decay (ψ0 = 0, φ0 = 0 or α = β): (|φ1|, |ψ1|)."""
        if self.kind == _ONLY_F:
            f1, s1 = _alone(self.f0, self.a, tau), _ZERO
        elif self.kind == _ONLY_S:
            f1, s1 = _ZERO, _alone(self.s0, self.b, tau)
        else:
            f1, s1 = _together(self.f0, self.s0, self.a, tau)
        return (s1, f1) if self.swap else (f1, s1)


def _walk_start(x0: np.ndarray, h0: np.ndarray, total: np.ndarray, e2: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """A walk's start (y = ln x, H, x, u) from x0 and its H h0; a cold start at x = 1, H = H(1) where they are
    not usable."""
    ok = np.isfinite(x0) & (x0 > 0) & (h0 > 0)
    if x0.__class__ is np.ndarray and np.all(x0 == 1.0):  # every walk from x = 1 (y = 0, x = u = 1 exactly, as
        # the logarithm and exponentials below give them; without their cost)
        return np.zeros(x0.shape), np.where(ok, h0, total), np.ones(x0.shape), np.ones(x0.shape)
    y = pick(ok, np.log(pick(ok, np.minimum(x0, 1.0), 1.0)), 0.0)
    return y, pick(ok, h0, total), np.exp(y), np.exp(e2 * y)


def _walk_slope(x: np.ndarray, u: np.ndarray, h: np.ndarray, r2: np.ndarray, scale: np.ndarray, e2: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """ln H, the elasticity E = x H′(x)/H (``_solve_x``) and G″ = dE/dy = E (1 + x H″/H′ − E) at x, where
    x H″/H′ = (e2/2) r2 u/(1 + r2 u) follows from H′ = scale √(1 + r2 u) (no evaluation of ``_F``)."""
    ru = r2 * u
    el = x * scale * np.sqrt(1 + ru) / h
    return np.log(h), el, el * (1 + 0.5 * e2 * ru / (1 + ru) - el)


def _walk_gap(a: np.ndarray, b: np.ndarray, el: np.ndarray) -> np.ndarray:
    """(a − b)/E: for a = ln target, b = ln H, the step left to first order (Newton's, ``_walk_slip``)."""
    return (a - b) / el


def _walk_step(a: np.ndarray, b: np.ndarray, el: np.ndarray, k2: np.ndarray) -> np.ndarray:
    """The walk's step in y = ln x for a = ln H, b = ln target: the root nearest 0 of the quadratic model
    ρ − E δ + ½ G″ δ² = 0 of G(y − δ) − ln target (ρ = a − b), written 2ρ/(E + √(E² − 2G″ρ)) (no cancellation);
    where the model has no root, Newton's ρ/E. A departure from ``_solve_x``'s plain Newton for
    speed only: the model is exact to second order, so the steps converge cubically and a solve needs one
    evaluation of H fewer; the same root and the same convergence test (``_solved``)."""
    rho = a - b
    disc = el * el - 2 * k2 * rho
    return pick(disc > 0, 2 * rho / (el + np.sqrt(np.maximum(disc, 0.0))), rho / el)


def _walk_move(y: np.ndarray, step: np.ndarray, e2: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """y, x and u after a step (x ≤ 1)."""
    y = np.minimum(y - step, 0.0)
    return y, np.exp(y), np.exp(e2 * y)


WALK_ACCEPT = 1e-9  # a walk whose step left is below this (in ln x) has settled (``_walk_settled``)


def _walk_settled(size: np.ndarray, h: np.ndarray, target: np.ndarray, total: np.ndarray, last: np.ndarray,
                  dy: np.ndarray) -> np.ndarray:
    """A walk's convergence test: ``_solved``'s, or the step left dy (``_walk_gap``, Newton's from the H just
    evaluated) below ``WALK_ACCEPT``: the slip returned, corrected to first order for dy (``_walk_slip``), is then
    off by its second order, (1e-9)² of the slip (a step fewer than waiting for the step itself to be that small)."""
    return _solved(size, h, target, total, last) | (abs(dy) <= WALK_ACCEPT)


def _walk_slip(f0: np.ndarray, s0: np.ndarray, x: np.ndarray, u: np.ndarray, e2: np.ndarray, dy: np.ndarray
               ) -> tuple[np.ndarray, np.ndarray]:
    """(|φ|, |ψ|) at x, corrected to first order for the step left dy (φ ∝ x^(α/β))."""
    return f0 * x * np.sqrt(u) * (1 + (1 + 0.5 * e2) * dy), s0 * x * (1 + dy)


class SlipWalk:
    """The general decays of a ``SlipDecay`` (scenes ``idx``, all with ``gen``) followed along a moving impulse τ, one
    Newton step of ``_solve_x`` per call of ``advance`` (the §VI end of impact moves τ = f ω at each of its own
    steps, n°13): the step, the evaluation of H and ``_solve_x``'s convergence test (or the step left below
    ``WALK_ACCEPT``: ``_walk_settled``), on arrays kept for the scenes
    still walking (``keep`` drops the others) and updated in place. ``x0``, ``h0``: a start and its H (a root of
    ``SlipDecay.at``). The step is ``_walk_step``'s (Newton's with the curvature of ln H, which ``_solve_x`` does
    not use: the same root and test, an evaluation fewer). With a table of coefficients the walks keep the table's
    layout (``_F_blocks``): all of it when they are all its scenes, else their columns gathered in its order."""

    def __init__(self, dec: SlipDecay, idx: np.ndarray, x0: np.ndarray, h0: np.ndarray) -> None:
        self.total, self.e2, self.r2, self.scale = (a[idx] for a in (dec.total, dec.e2, dec.r2, dec.scale))
        self.f0, self.s0 = dec.f0[idx], dec.s0[idx]
        self.swap = dec.swap[idx] if dec.swapped else None
        self.series, self.layout = dec.series, dec.layout  # (``layout``: a table's, ``_F_blocks``)
        if dec.layout is not None:  # a table: the walks' columns in the table's order, gathered unless all
            cols = dec.col[idx]
            order = np.argsort(cols, kind="stable")
            if not (idx.size == dec.everyone.size and np.array_equal(idx, dec.everyone)):
                self.series = _take(dec.series, cols[order])
                self.layout = (order, int(np.count_nonzero(cols < dec.layout[1])))
        elif dec.series is not None:
            self.series = _take(dec.series, idx)
        self.y, self.h, self.x, self.u = _walk_start(x0, h0, self.total, self.e2)
        self.last = np.full(self.y.shape, np.inf)
        self._slope()

    def _slope(self) -> None:
        """ln H and the elasticity E = x H′(x)/H (``_solve_x``) at the current x."""
        with np.errstate(divide="ignore", invalid="ignore"):
            self.lnh, self.el, self.k2 = _walk_slope(self.x, self.u, self.h, self.r2, self.scale, self.e2)

    def keep(self, i: np.ndarray) -> None:
        """Only the walks ``i`` go on."""
        for name in ("total", "e2", "r2", "scale", "f0", "s0", "y", "h", "x", "u", "last", "lnh", "el", "k2"):
            setattr(self, name, getattr(self, name)[i])
        if self.swap is not None:
            self.swap = self.swap[i]
        if self.layout is not None:  # the kept walks' columns, in the table's order
            order, cut = self.layout
            col = np.empty(order.size, dtype=np.intp)
            col[order] = np.arange(order.size)
            cols = col[i]
            order = np.argsort(cols, kind="stable")
            self.series = _take(self.series, cols[order])  # type: ignore[arg-type]
            self.layout = (order, int(np.count_nonzero(cols < cut)))
        elif self.series is not None:
            self.series = _take(self.series, i)

    def advance(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """One step (``_walk_step``) in y = ln x towards H(x) = H(1) − τ (log form: G convex),
        then H at the new x. Returns (|φ|, |ψ|) at τ, corrected to first order for the step's remaining residual
        (x·e^(−ρ/E), ρ = ln H − ln(H(1) − τ)), and whether the walk has converged for this τ (``_solve_x``'s test;
        a slip that stops, τ ≥ H(1), has)."""
        target = self.total - tau
        stop = ~(target > 0)
        cold = ~(self.h > 0) & ~stop  # stopped before, or H underflowed: start again at x = 1
        if cold.any():
            self.y[cold], self.x[cold], self.u[cold], self.h[cold] = 0.0, 1.0, 1.0, self.total[cold]
            self.last[cold] = np.inf
            self._slope()
        with np.errstate(divide="ignore", invalid="ignore"):
            lnt = np.log(target)
            step = _walk_step(self.lnh, lnt, self.el, self.k2)
            if stop.any():
                step[stop] = 0.0
            self.y, self.x, self.u = _walk_move(self.y, step, self.e2)
            self.h = _H_of(self.x, self.u, self.r2, self.scale, self.series, self.layout)  # type: ignore[arg-type]
            if stop.any():
                self.x[stop], self.u[stop], self.h[stop] = 0.0, 0.0, 0.0
            self._slope()
            size = np.abs(step)
            dy = _walk_gap(lnt, self.lnh, self.el)  # the step left: −ρ/E
            if stop.any():
                dy[stop] = 0.0
            settled = stop | _walk_settled(size, self.h, target, self.total, self.last, dy)
            self.last = size
            phi, psi = _walk_slip(self.f0, self.s0, self.x, self.u, self.e2, dy)
        if self.swap is None:
            return phi, psi, settled
        return np.where(self.swap, psi, phi), np.where(self.swap, phi, psi), settled

    def settle(self, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``advance`` towards one impulse τ per walk until each has converged (``_solve_x``: raises past
        ``NEWTON_MAXITER`` steps), dropping those that have (with a table of coefficients per walk, once most
        have). Returns (|φ|, |ψ|) at τ and the last x and its H, a warm start for a walk at nearby impulses. The walk
        is used up."""
        n = self.y.size
        phi, psi, x, h = np.empty(n), np.empty(n), np.empty(n), np.empty(n)
        ix, tau = np.arange(n), np.asarray(tau, dtype=float)
        pending = np.ones(n, dtype=bool)  # not yet written out (walks that have stay until a compaction)
        table = self.series is not None and self.series.p.shape[-1] > 1  # a column of coefficients per walk:
        # compacted only once most walks have settled (gathering the table costs more than stepping them on;
        # a walk's steps depend on its own numbers only, so those that go on change nothing)
        for _ in range(NEWTON_MAXITER):
            if not pending.any():
                return phi, psi, x, h
            p, q, settled = self.advance(tau)
            new = settled & pending
            k = np.flatnonzero(new)
            j = ix[k]
            phi[j], psi[j], x[j], h[j] = p[k], q[k], self.x[k], self.h[k]
            if k.size:
                pending &= ~new
                if not table or pending.sum() < 0.5 * pending.size:
                    k = np.flatnonzero(pending)
                    self.keep(k)
                    ix, tau, pending = ix[k], tau[k], pending[k]
        if pending.any():
            ix = ix[pending]
            raise ArithmeticError(f"slip decay: Newton did not converge in {NEWTON_MAXITER} steps for "
                                  f"{ix.size} scene(s)")
        return phi, psi, x, h


class _WalkOne:
    """``SlipWalk`` for one scene with a turning slip as numpy floats (``paths.Path.scalar``): the same formulas
    (``_walk_start``, ``_walk_slope``, ``_walk_step``, ``_walk_gap``, ``_walk_move``, ``_H_of``, ``_solved``,
    ``_walk_slip``), its masks as branches. ``dec``: the scene's ``_DecayOne``; ``x0``, ``h0`` as for ``SlipWalk``."""

    __slots__ = ("dec", "el", "h", "k2", "last", "lnh", "u", "x", "y")

    def __init__(self, dec: _DecayOne, x0: np.float64, h0: np.float64) -> None:
        self.dec = dec
        self.y, self.h, self.x, self.u = _walk_start(x0, h0, dec.total, dec.e2)
        self.last = np.float64(np.inf)
        self._slope()

    def _slope(self) -> None:
        d = self.dec
        if self.h > 0:
            self.lnh, self.el, self.k2 = _walk_slope(self.x, self.u, self.h, d.r2, d.scale, d.e2)
        else:
            with np.errstate(divide="ignore", invalid="ignore"):
                self.lnh, self.el, self.k2 = _walk_slope(self.x, self.u, self.h, d.r2, d.scale, d.e2)

    def advance(self, tau: np.float64) -> tuple[np.float64, np.float64, bool]:
        """``SlipWalk.advance`` for the one scene."""
        d = self.dec
        target = d.total - tau
        stop = not target > 0
        if not stop and not self.h > 0:  # stopped before, or H underflowed: start again at x = 1
            self.y, self.x, self.u, self.h = np.float64(0.0), np.float64(1.0), np.float64(1.0), d.total
            self.last = np.float64(np.inf)
            self._slope()
        if stop:  # the slip stops: no step, x = 0
            zero = np.float64(0.0)
            self.y = _walk_move(self.y, zero, d.e2)[0]
            self.x = self.u = self.h = zero
            self._slope()
            self.last, settled, dy = zero, True, zero
        else:
            lnt = np.log(target)
            step = _walk_step(self.lnh, lnt, self.el, self.k2)
            self.y, self.x, self.u = _walk_move(self.y, step, d.e2)
            self.h = _H_of(self.x, self.u, d.r2, d.scale, d.series)
            self._slope()
            size = np.abs(step)
            dy = _walk_gap(lnt, self.lnh, self.el)
            settled = bool(_walk_settled(size, self.h, target, d.total, self.last, dy))
            self.last = size
        phi, psi = _walk_slip(d.f0, d.s0, self.x, self.u, d.e2, dy)
        return (psi, phi, settled) if d.swap else (phi, psi, settled)

    def settle(self, tau: np.float64) -> tuple[np.float64, np.float64, np.float64, np.float64]:
        """``SlipWalk.settle`` for the one scene."""
        for _ in range(NEWTON_MAXITER):
            p, q, settled = self.advance(tau)
            if settled:
                return p, q, self.x, self.h
        raise ArithmeticError(f"slip decay: Newton did not converge in {NEWTON_MAXITER} steps for 1 scene(s)")
