"""Fitting: the paper's coefficients from data, with honest uncertainties, checked before they are reported.

The layout, lowest layer first (imports point down the list; this file imports nothing, so that
``resal --help`` stays light):

- ``estimators/``  pure estimators on numpy arrays: ``lsq`` (least squares with identifiability, the paper's
  fits used by the experiments), ``trials`` (a user's trials: a ratio under a noise model, speed laws, the
  bootstrap), ``shots`` (oblique ball–ball shots, §VI then §II);
- ``kinds/``       ``resal fit <kind>``: ``kinds/__init__`` declares each kind as data (columns, options, example);
  one module per family reads the CSV and fits (rebound, pendulum, ricochet + bounces, ball-ball);
- ``checks``       what every fit checks about itself before it reports: goodness of fit, outliers by
  leave-one-out, conventions (a reading of the data that fits far better), plausible ranges of the inputs;
- ``run``          ``fit_csv``: a kind's name and a file in, a ``FitOutcome`` out;
- ``report``       fit.json, fit.md, residuals.csv and the figures, written whole.
"""
