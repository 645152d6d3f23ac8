"""Single scenes for ``resal simulate``, read off the registry of models and paths (``mechanics.registry``).

Parameters are in SI units and the paper's notation; angles are taken in degrees on the command line (the
physics works in radians); a 3-vector is written ``v=2,0,0``. Coefficients of the paper (ε, ε′, ν, f, j) have
no default: no value printed in the paper stands in for a measurement the user did not give.
"""

from __future__ import annotations

import math
import sys
from typing import Any

import numpy as np

from .config import comma_problem, comma_readings, parse_number, printable, shorten, underflows
from .errors import ComputationError, InputError, did_you_mean
from .mechanics import paths, registry

__all__ = ["NOT_COMPUTED", "OUTPUTS", "RADIANS", "code_name", "degrees", "describe", "list_models",
           "radians_warnings", "simulate", "solve_scene"]


def _cli(p: paths.Param, value: float | None) -> float | None:
    """A value in the unit the command line uses (degrees for angles)."""
    if value is None:
        return None
    return degrees(value) if p.cli_degrees else value


def code_name(code: paths.PathCode | paths.Regime) -> str:
    """A path's or regime's name as ``simulate --json`` gives it beside its code: RESAL_CORRECTED → resal-corrected."""
    return code.name.lower().replace("_", "-")


def degrees(radians: float) -> float:
    """Degrees, rounded to 15 digits: 60° given on the command line comes back as 60, not 59.99999999999999."""
    return float(f"{math.degrees(radians):.15g}") + 0.0  # + 0.0: no −0


# Unit and meaning of every output of ``simulate`` (the fields of each model's result). "degrees": an angle the
# physics gives in radians, printed in degrees as the command line takes angles; "1": a pure number; "code": a
# regime code (``list_models()["regime_codes"]``); "flag": true or false.
OUTPUTS: dict[str, dict[str, tuple[str, str]]] = {
    "direct-impact": {
        "V1": ("m/s", "velocity of M after the impact"), "V1p": ("m/s", "velocity of M′ after the impact"),
        "newton_e": ("1", "Newton's restitution e equivalent to (ε, ε′)"),
        "vis_viva_lost": ("kg·m²/s²", "vis viva Σmv² lost (twice the kinetic energy lost)")},
    "wall-impact": {
        "V1": ("m/s", "normal velocity after the impact (negative: moving away)"),
        "ratio": ("1", "−V1/V0, Coriolis's ratio of the normal velocities")},
    "plane-impact": {
        "chi1": ("m/s", "tangential velocity of the centre after"),
        "zeta1": ("m/s", "normal velocity after (positive: leaving the plane)"),
        "p1": ("rad/s", "rotation after")},
    "ricochet": {
        "ranges": ("m", "range of the flight after each impact"), "times": ("s", "duration of each flight"),
        "imprints": ("m", "position of each impact and of the landing after the last flight (the first at 0)"),
        "chi": ("m/s", "tangential velocity after each impact"), "zeta": ("m/s", "normal velocity after each impact"),
        "p": ("rad/s", "rotation after each impact"), "regimes": ("code", "friction regime of each impact")},
    "cloth-slide": {
        "t_roll": ("s", "time until the ball rolls"), "x_roll": ("m", "distance along x until then"),
        "y_roll": ("m", "distance along y until then"), "vx_roll": ("m/s", "velocity along x when it rolls"),
        "vy_roll": ("m/s", "velocity along y when it rolls"), "slip0": ("m/s", "initial slip speed")},
    "cushion-impact": {
        "chi1": ("m/s", "velocity along the cushion after"), "zeta1": ("m/s", "normal velocity after"),
        "p1": ("rad/s", "side spin after"), "n1": ("rad/s", "rotation about the cushion's direction after")},
    **{name: {
        "v1": ("m/s", "velocity of the striking ball after (x, y, z)"),
        "w1": ("rad/s", "rotation of the striking ball after (x, y, z)"),
        "v1p": ("m/s", "velocity of the struck ball after (x, y, z)"),
        "w1p": ("rad/s", "rotation of the struck ball after (x, y, z)"),
        "omega1": ("m/s", "normal velocity lost by the striking ball, χ0 − χ1"),
        "T": ("kg·m/s", "tangential impulse on the struck ball (y, z)"),
        "s_c": ("m/s", "slip at the greatest compression (y, z)"),
        "converged": ("flag", "the end of the impact (law (6)) converged (true where there is none)"),
    } for name in ("spheres-free", "spheres-cloth")},
    "cue-stroke": {
        "chi1": ("m/s", "velocity of the centre along Cx (the cue's vertical plane)"),
        "eta1": ("m/s", "velocity of the centre along Cy"), "n1": ("rad/s", "rotation about Cx"),
        "p1": ("rad/s", "rotation about Cy"), "q1": ("rad/s", "rotation about Cz (vertical)"),
        "V1p": ("m/s", "speed of the cue after the stroke"), "omega1": ("m/s", "cue speed lost, eq. (6)"),
        "omega": ("m/s", "cue speed lost at the greatest compression, eq. (12)"),
        "A": ("1", "eq. (8): 1 + the ball's vis viva over M′ω1²"),
        "gamma": ("degrees", "direction of the slip on the cloth, eq. (5) (not computed by the ode path: null)"),
        "cos_phi": ("1", "cosine of the angle of the cue axis with the normal at the contact, eq. (11)")},
}
NOT_COMPUTED = {("cue-stroke", "ode", "gamma")}  # (model, path, output): the path does not compute it (NaN)
# Every angle given below 1.6 (degrees) and none 0: radians typed for degrees, most likely (π/2 ≈ 1.57); the same
# bound as ``resal fit``'s check of a column of degrees (``fit.kinds.markers.RADIANS``)
RADIANS = 1.6


def radians_warnings(m: paths.Model, values: dict[str, Any]) -> list[dict[str, str]]:
    """The warning (as ``resal fit``'s: code and message) when every angle given (``values`` in radians, as
    parsed) is nonzero and below ``RADIANS`` degrees: angles in radians typed where degrees are read."""
    given = {p.name: degrees(values[p.name]) for p in m.params if p.cli_degrees and p.name in values}
    if not given or not all(0 < abs(v) < RADIANS for v in given.values()):
        return []
    said = ", ".join(f"{k}={v:g}" for k, v in given.items())
    meant = ", ".join(f"{v:g} rad is {k}={math.degrees(v):.4g}" for k, v in given.items())
    return [{"code": "implausible-input", "message": f"{said}: {'every angle' if len(given) > 1 else 'an angle'} "
                                                      f"below {RADIANS:g}°, radians typed for degrees? resal "
                                                      f"simulate reads angles in degrees ({meant})"}]


def _param_info(p: paths.Param, vector: bool) -> dict[str, Any]:
    return {"name": p.name, "unit": "degrees" if p.cli_degrees else p.unit, "doc": p.doc,
            "default": _cli(p, p.default), "required": p.default is None, "vector": vector,
            "lo": _cli(p, p.lo), "hi": _cli(p, p.hi), "lo_open": p.lo_open, "hi_open": p.hi_open,
            "integer": p.integer, "range": _range_text(p)}


def _range_text(p: paths.Param) -> str:
    if not p.cli_degrees:
        return p.range_text()
    q = paths.Param(p.name, "degrees", p.doc, None, _cli(p, p.lo), _cli(p, p.hi), p.lo_open, p.hi_open)
    return q.range_text()


def describe(m: paths.Model) -> dict[str, Any]:
    """One model for ``resal simulate --list --json``: parameters (units, ranges, defaults) and declared paths."""
    return {
        "model": m.name, "section": m.section, "doc": m.doc, "admits": m.admissible_text,
        "parameters": [_param_info(p, p.name in m.vectors) for p in m.params],
        "paths": [{"name": p.name, "code": int(p.code), "kind": p.kind.value, "cost": p.cost,
                   "accuracy": p.accuracy, "handles": p.handles_text, "doc": p.doc} for p in m.paths],
        "outputs": [{"name": n, "unit": u, "doc": d} for n, (u, d) in OUTPUTS[m.name].items()],
    }


def list_models() -> dict[str, Any]:
    """Every model, the codes of paths and regimes, and the units convention of the command line."""
    return {
        "units": "SI; angles in degrees on the command line (radians in the physics); vectors as x,y,z",
        "path_codes": {code_name(p): int(p) for p in paths.PathCode},
        "regime_codes": {code_name(r): int(r) for r in paths.Regime},
        "models": [describe(m) for m in registry.MODELS.values()],
    }


def _parse(m: paths.Model, assignment: str) -> tuple[str, Any]:
    """One ``--set name=value``: a number (a comma only between the x,y,z of a vector, never a thousands
    separator or a decimal comma; no nonzero value that underflows to 0 or a subnormal), in its range."""
    name, sep, text = printable(assignment).partition("=")  # quoted as one line, whatever was typed
    name = name.strip()
    where = f"--set {printable(assignment)}"
    if not sep:
        raise InputError(where, "expected name=value")
    param = next((p for p in m.params if p.name == name), None)
    if param is None:
        raise InputError(where, f"unknown parameter '{name}' for {m.name} "
                                f"(expected one of: {', '.join(p.name for p in m.params)})"
                                f"{did_you_mean(name, [p.name for p in m.params])}")
    if name not in m.vectors and "," in text:
        raise InputError(where, f"'{name}' is one number, got '{shorten(text)}': {comma_problem(text)}")
    parts = text.split(",") if name in m.vectors else [text]
    if name in m.vectors and len(parts) != 3:
        one = " or ".join(f"{what} ({x})" for what, x in comma_readings(text))
        raise InputError(where, f"'{name}' is a 3-vector: expected three numbers x,y,z, got '{text}'"
                                + (f" (one number with {one}? a vector takes three)" if one else ""))
    values = []
    for part in parts:
        parsed = parse_number(part.strip())
        if parsed is None:
            raise InputError(where, f"'{name}' must be a number, got '{text}'")
        v = parsed[0]
        admissible = paths.Param(name, "", "", None, _cli(param, param.lo), _cli(param, param.hi), param.lo_open,
                                 param.hi_open, integer=param.integer, why=param.why)
        if underflows(part, v):
            zero = " (or 0)" if admissible.problem(0.0) is None else ""
            raise InputError(where, f"'{name}': {part.strip()} is nonzero but below the smallest normal double "
                                    f"({sys.float_info.min:.1e}), so it reads as {v!r}: expected a value of a "
                                    f"physical size{zero}")
        problem = admissible.problem(v)
        if problem:
            raise InputError(where, f"'{name}' must be {problem}" + (" (degrees)" if param.cli_degrees else "")
                             + f", got {text}")
        values.append(math.radians(v) if param.cli_degrees else v)
    return name, (values if name in m.vectors else values[0])


def _plain(v: Any) -> Any:
    a = np.asarray(v)
    return a.tolist() if a.ndim else (bool(a) if a.dtype == bool else float(a) if a.dtype.kind == "f" else int(a))


def _finite(v: Any) -> bool:
    """Every number in an output (lists nested) is finite; codes and flags pass."""
    if isinstance(v, list):
        return all(_finite(x) for x in v)
    return not isinstance(v, float) or math.isfinite(v)


def solve_scene(m: paths.Model, scene: paths.Scene, method: str, given: str, method_where: str,
                report: str) -> Any:
    """``paths.solve`` on a scene a user gave (``resal simulate`` and ``api.simulate``), its failures as they are
    told: an input that overflows and a path asked outside its region are ``InputError`` (at ``given``, or at
    ``method_where`` for the path), a solver failing on an admissible scene a ``ComputationError`` (ours to fix:
    "please report this ``report``")."""
    try:
        with np.errstate(all="ignore"):  # an overflow is reported here, as one message, not as a warning
            bad_in = [n for n, v in scene.items() if not np.all(np.isfinite(np.asarray(v, dtype=float)))]
            if bad_in:
                raise InputError(given, f"the scene's input {bad_in[0]} is not finite (it overflows): expected "
                                        "values of a physical size")
            return paths.solve(m, scene, method)
    except paths.PathError as err:
        where = method_where if method != "auto" and "handles only" in str(err) else given
        raise InputError(where, str(err)) from None
    except ArithmeticError as err:  # a solver failed on an admissible scene: ours to fix, said plainly
        raise ComputationError(given, f"the {method} computation failed ({err}); this scene is valid input, so "
                                      f"this is a defect of resal: please report this {report}") from None
    except ValueError as err:  # scipy's integrator or root finder refused a state (NaN, a first step of 0)
        if not _from_scipy(err):
            raise
        raise ComputationError(given, f"the {method} computation failed: scipy refused the scene's state "
                                      f"({_first_line(err)}); values this far from a ball's (near the limits of "
                                      "a double) are past what the numerical integration represents: another "
                                      f"--method, or please report this {report}") from None


def _from_scipy(err: BaseException) -> bool:
    """Whether ``err`` was raised inside scipy (its innermost frame)."""
    tb = err.__traceback__
    while tb is not None and tb.tb_next is not None:
        tb = tb.tb_next
    return tb is not None and "scipy" in tb.tb_frame.f_code.co_filename


def _first_line(err: BaseException) -> str:
    return str(err).strip().splitlines()[0] if str(err).strip() else type(err).__name__


def simulate(model: str, assignments: list[str], method: str = "auto") -> dict[str, Any]:
    """Run one scene; ``assignments`` are ``name=value`` strings. Raises ``InputError`` on bad input."""
    if model not in registry.MODELS:
        raise InputError(f"model '{model}'", f"unknown model (expected one of: {', '.join(registry.MODELS)})"
                                             f"{did_you_mean(model, registry.MODELS)}")
    m = registry.MODELS[model]
    if method != "auto" and method not in [p.name for p in m.paths]:
        raise InputError(f"--method {method}", f"{model} has no path '{method}' (expected one of: auto, "
                                               f"{', '.join(p.name for p in m.paths)})"
                                               f"{did_you_mean(method, ['auto', *(p.name for p in m.paths)])}")
    values: dict[str, Any] = {}
    for a in assignments:
        name, v = _parse(m, a)
        values[name] = v
    missing = [p.name for p in m.params if p.default is None and p.name not in values]
    if missing:
        raise InputError("--set", f"{model} needs {', '.join(missing)} (no default: give your measured "
                                  f"value, e.g. --set {missing[0]}=…)")
    given = " ".join(f"--set {a}" for a in assignments) or f"model '{model}'"
    try:
        with np.errstate(all="ignore"):  # an overflow is reported by solve_scene, as one message, not a warning
            scene = m.scene(values)
    except paths.PathError as err:
        raise InputError(given, str(err)) from None
    res = solve_scene(m, scene, method, given, f"--method {method}", "command")
    inputs = {p.name: _plain(_cli(p, float(scene[p.name])) if p.name not in m.vectors else scene[p.name])
              for p in m.params}
    skip = {"method", "path", "regime", "label"}
    code, regime = int(np.ravel(res.path)[0]), int(np.ravel(res.regime)[0])
    path_name = code_name(paths.PathCode(code))
    units = OUTPUTS[model]
    outputs: dict[str, Any] = {}
    for name in res.__dataclass_fields__:
        if name in skip:
            continue
        v = _plain(getattr(res, name))
        if (model, path_name, name) in NOT_COMPUTED and isinstance(v, float) and math.isnan(v):
            v = None
        elif units[name][0] == "degrees":
            v = degrees(v)
        outputs[name] = v
    bad_out = [n for n, v in outputs.items() if v is not None and not _finite(v)]
    if bad_out:
        raise InputError(given, f"the scene's outputs overflow ({', '.join(bad_out)} not finite): expected inputs "
                                "whose products and squares stay within floating point (|x| ≲ 1e150 in SI units)")
    return {"model": model, "method": res.method, "path": code, "path_name": path_name,
            "regime": regime, "regime_name": code_name(paths.Regime(regime)),
            "label": res.label, "inputs": inputs, "outputs": outputs,
            "units": {"inputs": {p.name: "degrees" if p.cli_degrees else p.unit for p in m.params},
                      "outputs": {n: units[n][0] for n in outputs}},
            "warnings": radians_warnings(m, values)}
