"""A bound on the work of one ODE integration: every right-hand side is counted, and an integration that needs
more than ``MAX_RHS`` evaluations stops with ``ODEBudgetExceeded`` instead of running on (a solver chattering
on a discontinuous right-hand side, or a stiff one under an explicit method, can otherwise take hours)."""

from __future__ import annotations

import itertools
from collections.abc import Callable
from typing import Any

__all__ = ["MAX_RHS", "ODEBudgetExceeded", "bounded", "check", "solve_ivp"]

MAX_RHS = 200_000  # right-hand-side evaluations per integration; the paths here need 100 to 10 000


class ODEBudgetExceeded(ArithmeticError):
    """An integration needed more than ``MAX_RHS`` right-hand-side evaluations."""


def bounded(rhs: Callable[..., Any], limit: int | None = None) -> Callable[..., Any]:
    """``rhs`` that raises ``ODEBudgetExceeded`` past its ``limit``-th call (default ``MAX_RHS``)."""
    limit = MAX_RHS if limit is None else limit
    calls = itertools.count(1)  # a third of the cost of a counter in a list (every RHS of every integration)

    def f(t: float, y: Any) -> Any:
        if next(calls) > limit:
            raise ODEBudgetExceeded(f"the integration needed more than {limit} right-hand-side evaluations")
        return rhs(t, y)

    return f


def check(sol: Any) -> Any:
    """A ``solve_ivp`` result, or ``ArithmeticError`` with the solver's message when it failed (status −1)."""
    if sol.status == -1:
        raise ArithmeticError(f"the ODE solver failed: {sol.message}")
    return sol


def solve_ivp(*args: Any, **kwargs: Any) -> Any:
    """``scipy.integrate.solve_ivp``, imported at its first call: scipy.integrate takes a third of a second to import
    and most commands (list, a reproduction whose rows need no integration, a fit) never integrate."""
    from scipy.integrate import solve_ivp as ivp

    return ivp(*args, **kwargs)
