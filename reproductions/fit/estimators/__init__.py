"""Pure estimators on numpy arrays (no files, no printing): ``lsq``, ``trials``, ``shots``."""
