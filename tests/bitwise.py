"""Equality to the bit of two results of a path (the scalar route and the batch route, a small batch and a large
one): shared by tests/test_small_batch.py and tests/test_scalar_route.py."""

import dataclasses

import numpy as np


def fields(res):
    return {f.name: getattr(res, f.name) for f in dataclasses.fields(res)}


def bits(x):
    """The bytes of an array, NaNs made one NaN: a NaN carries no number, and the sign bit of a NaN from an invalid
    operation (inf − inf, 0 × inf) depends on the instruction that made it, not on the formula."""
    x = np.ascontiguousarray(x).reshape(-1)
    if x.dtype.kind == "f":
        x = np.where(np.isnan(x), np.nan, x)
    return x.view(np.uint8)


def same(a, b, what):
    """Equal field by field: arrays of one type, dtype, shape and bits (the sign of ±0 included; NaN where NaN);
    the rest equal."""
    fa, fb = fields(a), fields(b)
    assert type(a) is type(b) and fa.keys() == fb.keys(), what
    for name, x in fa.items():
        y = fb[name]
        if isinstance(x, np.ndarray) or isinstance(y, np.ndarray):
            assert type(x) is np.ndarray and type(y) is np.ndarray, (what, name, type(x), type(y))
            assert x.dtype == y.dtype and x.shape == y.shape, (what, name, x.dtype, y.dtype, x.shape, y.shape)
            np.testing.assert_array_equal(bits(x), bits(y), err_msg=f"{what}: {name} ({x} against {y})")
        else:
            assert x == y, (what, name, x, y)
