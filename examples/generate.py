"""Write the synthetic example files of ``resal fit`` (one per kind): ``python examples/generate.py``.

Every file is labelled synthetic in its first lines, with the law and the values that made it, so that a test can
check that ``resal fit`` finds them again. Seeds are fixed: the files are the same on every machine.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from reproductions.fit.estimators.lsq import synthetic_bounces
from reproductions.fit.estimators.shots import synthetic_shots
from reproductions.mechanics import impact, plane

HERE = Path(__file__).resolve().parent


def _write(name: str, header: str, rows: list[tuple[float, ...]], note: str) -> None:
    lines = [f"# SYNTHETIC data, not measurements: {note}", "# written by examples/generate.py", header]
    lines += [",".join(f"{v:.6g}" for v in r) for r in rows]
    (HERE / name).write_text("\n".join(lines) + "\n", encoding="utf-8")


def main() -> None:
    rng = np.random.default_rng(20261201)
    # rebound: constant e = 0.8, unsigned speeds in m/s, constant noise 0.02 m/s on u1
    u0 = np.round(rng.uniform(0.5, 4.0, 12), 3)
    u1 = 0.8 * u0 + rng.normal(0, 0.02, u0.size)
    _write("rebound.csv", "u0_mps,u1_mps", list(zip(u0, u1, strict=True)),
           "rebounds on a wall, e = 0.8, speeds (unsigned) with noise sd 0.02 m/s on u1")
    # cushion: a speed-dependent e, Han (2005)'s law e = 0.39 + 0.257 v - 0.044 v^2, signed, cm/s, 2 % noise
    v0 = np.round(np.linspace(0.5, 3.5, 10), 2)
    e = 0.39 + 0.257 * v0 - 0.044 * v0**2
    v1 = -e * v0 * (1 + rng.normal(0, 0.02, v0.size))
    _write("cushion.csv", "V0_cmps,V1_cmps", list(zip(100 * v0, 100 * v1, strict=True)),
           "perpendicular cushion rebounds made with Han (2005)'s law e = 0.39 + 0.257 v - 0.044 v^2 "
           "(v in m/s), signed velocities in cm/s, relative noise 2 % on V1")
    # drop: heights in mm, e = 0.9, noise sd 2 mm on h1
    h0 = np.round(rng.uniform(200, 1000, 10), 0)
    h1 = 0.81 * h0 + rng.normal(0, 2.0, h0.size)
    _write("drop.csv", "h0_mm,h1_mm", list(zip(h0, h1, strict=True)),
           "a ball dropped on a slab, e = 0.9 (h1 = 0.81 h0), heights in mm with noise sd 2 mm on h1")
    # pendulum: two mass ratios, eps = 0.1, eps' = 0.3, noise sd 0.005 m/s on V1 and V1p
    M = np.repeat([0.6, 0.2], 6)
    Mp = np.repeat([0.2, 0.2], 6)
    V0 = np.round(rng.uniform(0.5, 2.0, 12), 3)
    r = impact.direct_impact(M, Mp, V0, 0.0, eps=0.1, epsp=0.3)
    V1 = r.V1 + rng.normal(0, 0.005, 12)
    V1p = r.V1p + rng.normal(0, 0.005, 12)
    _write("pendulum.csv", "V0,V1,V1p,M_g,Mp_g", list(zip(V0, V1, V1p, 1000 * M, 1000 * Mp, strict=True)),
           "two pendulums, eps = 0.1 (striker), eps' = 0.3 (struck), masses 600/200 g and 200/200 g, "
           "velocities in m/s with noise sd 0.005 m/s")
    # ricochet: nu = 0.75, f = 0.2, a0 = 2 m/s, alpha0 = 0.45 rad, R = 0.0305 m; x in m, t in s
    rc = plane.ricochet(2.0, 0.45, 0.0, R=0.0305, k=2.5, f=0.2, nu=0.75, g=9.80665, n=9)
    x = rc.imprints + rng.normal(0, 3e-4, 10)
    t = np.concatenate([[0.0], np.cumsum(rc.times)]) + rng.normal(0, 1e-4, 10)
    _write("ricochet.csv", "x,t", list(zip(x - x[0], t - t[0], strict=True)),
           "ricochets of a ball of radius 0.0305 m, nu = 0.75, f = 0.2, launched at 2 m/s and 0.45 rad without "
           "spin; noise 0.3 mm on x and 0.1 ms on t")
    # ball-ball: f = 0.06, e = 0.93, balls of radius 0.02855 m; 2 % speed noise, 0.5 degree direction noise
    cols = synthetic_shots(rng, 16, f_bb=0.06, e=0.93, R=0.02855)
    deg = 180 / np.pi
    _write("ball-ball.csv", "v,phi_deg,cue_speed,cue_dir_deg,obj_speed,obj_dir_deg",
           list(zip(cols["v"], cols["phi"] * deg, cols["cue_speed"], cols["cue_dir"] * deg, cols["obj_speed"],
                    cols["obj_dir"] * deg, strict=True)),
           "oblique shots, ball-ball friction f = 0.06, e = 0.93, radius 0.02855 m (use --R 0.02855), cue ball "
           "rolling; speeds in m/s with 2 % noise, angles in degrees with 0.5 degree noise")
    # bounces: a ball dropped from 0.5 m at rest, nu = 0.85, 10 clicks with 1 ms jitter, in milliseconds
    b = synthetic_bounces(rng, 10, nu=0.85, h0=0.5, jitter=1e-3, t_start=0.0)
    _write("bounces.csv", "t_ms", [(1e3 * v,) for v in b["t"]],
           "clicks of a ball dropped at rest from h0 = 0.5 m (use --h0 0.5), nu = 0.85, g = 9.80665 m/s^2; "
           "instants in ms with 1 ms jitter")
    # pendulum heights: eps = 0.1, eps' = 0.3; a light striker on a heavy bob (it swings back) and the reverse
    M, Mp = np.repeat([0.6, 0.2], 5), np.repeat([0.2, 0.6], 5)
    h0 = np.round(rng.uniform(0.1, 0.3, 10), 4)
    r = impact.direct_impact(M, Mp, np.sqrt(2 * 9.80665 * h0), 0.0, eps=0.1, epsp=0.3)
    h1, h1p = (v**2 / (2 * 9.80665) + rng.normal(0, 5e-4, 10) for v in (r.V1, r.V1p))
    _write("pendulum-heights.csv", "h0_mm,h1_mm,h1p_mm,M_g,Mp_g",
           list(zip(1e3 * h0, 1e3 * np.abs(h1), 1e3 * np.abs(h1p), 1e3 * M, 1e3 * Mp, strict=True)),
           "two pendulums, eps = 0.1, eps' = 0.3; release and rise heights in mm with noise sd 0.5 mm; in the "
           "last five trials the 200 g striker swings back off the 600 g bob")
    # markers: angle markers of oblique collisions, §VI with f = 0.06, e = 0.93; its own seed (the files above keep
    # theirs); noise 1.5 degrees on alpha1 and 0.5 degree on the throw
    from reproductions.fit.estimators.markers import angles

    rm = np.random.default_rng(2023)
    psi = {s: np.round(np.sort(rm.uniform(8, 72, 30)), 2) for s in ("alpha1", "throw")}
    obs = {s: angles(psi[s], 0.06, 0.93)[s] + rm.normal(0, {"alpha1": 1.5, "throw": 0.5}[s], 30) for s in psi}
    lines = ["# SYNTHETIC data, not measurements: angle markers of oblique collisions made with §VI (cue ball rolling "
             "onto a ball at rest), ball-ball friction f = 0.06, e = 0.93; noise sd 1.5 degrees on alpha1 and 0.5 "
             "degree on the throw", "# written by examples/generate.py", "series,psi_deg,angle_deg"]
    lines += [f"{s},{p:.2f},{a:.3f}" for s in psi for p, a in zip(psi[s], obs[s], strict=True)]
    (HERE / "markers.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()
