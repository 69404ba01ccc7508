"""Flat barometric sensors: barometers cast under a flat rubber layer, pressed at its surface.

Two small designs, from the same contact physics as the fingertip (`anytip.sensor.physics`):
the hydrostatic pressure of a point load on an elastic half-space (Boussinesq and Cerruti),
smoothed over the Hertz contact patch, read by barometers at depth h under the surface.
On a flat layer the half-space formula is exact up to the layer's finite thickness.

- `edge-4baro`: 4 barometers in a line (x = -12, -4, 4, 12 mm) under a rubber strip; a
  round tip presses at x in [-15, 15] mm to an indentation depth up to 1.5 mm. Targets
  `position` (x, m) and `depth` (z, m): what a stage logs, no force.
- `pad-16baro`: 4 x 4 barometers at 6 mm pitch under a rubber pad; a round tip presses at
  (x, y) in [-10, 10] mm with normal force up to 10 N and shear up to 0.4 of it in any
  direction. Targets `force` (fx, fy, fz, N; pressing gives fz < 0) and `position` (x, y, m).

Unit-to-unit variation (scaled by `severity`): barometer placement (0.3 mm) and depth
(10 %), rubber modulus (15 %, log-normal), channel gain (10 %), preload (200 Pa), read-out
noise. Runs are deterministic from their seed, like the fingertip's; each run records
every input in its `simulator` JSON. Shapes: N rows, C barometers.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import numpy as np

from anytip.errors import AnytipError
from anytip.sensor.physics import relax
from anytip.sensor.protocols import PLAN_MOVE_S, PLAN_POINTS, check_plan_points, designed_seconds

SIMULATOR = "anytip.sensor.flat"
VERSION = 1
RATE_HZ = 200.0
ATMOSPHERE_PA = 101_325.0
POISSON = 0.49
REST_S = 1.0  # at rest before the first press (the format asks for at least 0.5 s)
# one press: move to the spot, load, hold, unload (seconds)
MOVE_S, LOAD_S, HOLD_S, UNLOAD_S = 0.4, 0.4, 0.3, 0.4
PROTOCOLS = {"full": 600, "short": 120, "quick": 20}  # presses per run (full: about 15 min)
CONTACT_LEVEL = 0.05  # in contact above 5 % of the maximum depth or force (as an F/T threshold)


@dataclass(frozen=True)
class FlatDesign:
    """A sensor model's nominal build: barometer (x, y) (C, 2) m at `depth_m` under the surface,
    the pressed region (x_min, x_max, y_min, y_max) m, and what the rig commands."""

    name: str
    id_prefix: str
    baro_xy_m: tuple[tuple[float, float], ...]
    depth_m: float
    region_m: tuple[float, float, float, float]
    modulus_pa: float
    tip_radius_m: float
    max_depth_m: float | None = None  # the rig commands indentation depth (edge) ...
    max_force_n: float | None = None  # ... or normal force with shear (pad)
    shear_ratio: float = 0.0
    targets: tuple[tuple[str, str, tuple[str, ...]], ...] = ()  # (name, unit, components)

    @property
    def channels(self) -> int:
        return len(self.baro_xy_m)


_PAD_PITCH = 6e-3
DESIGNS = {
    "edge-4baro": FlatDesign(
        "edge-4baro", "EDGE", tuple((x, 0.0) for x in (-12e-3, -4e-3, 4e-3, 12e-3)), 4e-3,
        (-15e-3, 15e-3, 0.0, 0.0), 0.5e6, 5e-3, max_depth_m=1.5e-3,
        targets=(("position", "m", ("x",)), ("depth", "m", ("z",)))),
    "pad-16baro": FlatDesign(
        "pad-16baro", "PAD", tuple((_PAD_PITCH * (i - 1.5), _PAD_PITCH * (j - 1.5))
                                   for i in range(4) for j in range(4)), 3e-3,
        (-10e-3, 10e-3, -10e-3, 10e-3), 0.8e6, 6e-3, max_force_n=10.0, shear_ratio=0.4,
        targets=(("force", "N", ("fx", "fy", "fz")), ("position", "m", ("x", "y")))),
}


def get_design(name: str) -> FlatDesign:
    if name not in DESIGNS:
        raise AnytipError(f"no simulated flat sensor model {name!r}; known: {sorted(DESIGNS)}")
    return DESIGNS[name]


@dataclass(frozen=True)
class FlatUnit:
    """One built unit: barometer positions (C, 3) m (z < 0 under the surface), rubber modulus
    Pa, per-channel gain, preload Pa and read-out noise Pa (C,)."""

    design: str
    positions_m: np.ndarray
    modulus_pa: float
    gain: np.ndarray
    preload_pa: np.ndarray
    noise_pa: np.ndarray

    def to_json(self) -> dict[str, Any]:
        return {"design": self.design, "positions_m": self.positions_m.tolist(),
                "modulus_pa": self.modulus_pa, "gain": self.gain.tolist(),
                "preload_pa": self.preload_pa.tolist(), "noise_pa": self.noise_pa.tolist()}

    @classmethod
    def from_json(cls, d: dict[str, Any]) -> FlatUnit:
        return cls(d["design"], np.asarray(d["positions_m"]), float(d["modulus_pa"]), np.asarray(d["gain"]),
                   np.asarray(d["preload_pa"]), np.asarray(d["noise_pa"]))


def draw_unit(design: FlatDesign, rng: np.random.Generator, severity: float = 1.0) -> FlatUnit:
    """A unit as casting and assembly make it: the design's nominal build varied by `severity`."""
    c = design.channels
    xy = np.asarray(design.baro_xy_m) + 0.3e-3 * severity * rng.standard_normal((c, 2))
    depth = design.depth_m * (1.0 + 0.1 * severity * rng.standard_normal(c))
    positions = np.column_stack([xy, -np.clip(depth, 0.3 * design.depth_m, None)])
    return FlatUnit(
        design=design.name, positions_m=positions,
        modulus_pa=float(design.modulus_pa * np.exp(0.15 * severity * rng.standard_normal())),
        gain=np.clip(1.0 + 0.1 * severity * rng.standard_normal(c), 0.5, None),
        preload_pa=200.0 * severity * rng.standard_normal(c), noise_pa=np.full(c, 3.0),
    )


def hertz_force(depth_m: np.ndarray, unit: FlatUnit, tip_radius_m: float) -> np.ndarray:
    """(N,) N normal force of a round tip pressed `depth_m` (N,) m into the layer (Hertz)."""
    e_star = unit.modulus_pa / (1.0 - POISSON**2)
    return 4.0 / 3.0 * e_star * np.sqrt(tip_radius_m) * np.clip(depth_m, 0.0, None) ** 1.5


def layer_pressure(point_xy: np.ndarray, force: np.ndarray, unit: FlatUnit,
                   tip_radius_m: float) -> np.ndarray:
    """(N, C) Pa hydrostatic pressure at each barometer for loads at the surface points
    point_xy (N, 2) m with force (N, 3) N on the layer (pressing: fz < 0)."""
    e_star = unit.modulus_pa / (1.0 - POISSON**2)
    a = np.cbrt(3.0 * np.clip(-force[:, 2], 0.0, None) * tip_radius_m / (4.0 * e_star))
    points = np.column_stack([point_xy, np.zeros(len(point_xy))])
    rho = unit.positions_m[None, :, :] - points[:, None, :]
    dist2 = np.einsum("ncj,ncj->nc", rho, rho) + (a * a)[:, None]
    f_dot_rho = np.einsum("ncj,nj->nc", rho, force)
    return (1.0 + POISSON) / (3.0 * np.pi) * f_dot_rho / (dist2 * np.sqrt(dist2))


@dataclass
class FlatRun:
    """One simulated run: time (N,) s, pressure (N, C) Pa absolute, in_contact (N,) bool, targets
    name -> (N, k) float32 in the design's units, and `record` (every input, for `regenerate`)."""

    sensor_id: str
    design: FlatDesign
    created: str
    time: np.ndarray
    pressure: np.ndarray
    in_contact: np.ndarray
    targets: dict[str, np.ndarray]
    record: dict[str, Any]


def _press_profile(rng: np.random.Generator) -> np.ndarray:
    """(n,) in [0, 1]: one press's load over time (0 while moving, ramp, hold, ramp down)."""
    return _profile(MOVE_S, HOLD_S * rng.uniform(0.5, 1.5))


def _profile(move_s: float, hold_s: float) -> np.ndarray:
    """(n,) in [0, 1]: a press moved to for `move_s`, loaded, held `hold_s` and unloaded (seconds)."""
    n = [int(round(s * RATE_HZ)) for s in (move_s, LOAD_S, hold_s, UNLOAD_S)]
    return np.concatenate([np.zeros(n[0]), np.linspace(0, 1, n[1] + 1)[1:], np.ones(n[2]),
                           np.linspace(1, 0, n[3] + 1)[1:]])


@dataclass(frozen=True)
class FlatPlan:
    """A designed calibration of a flat design: P presses, each moved to for `move_s` and then
    loaded, held and unloaded (LOAD_S, HOLD_S, UNLOAD_S). where (P, 2) m the pressed point;
    level (P,) in [0.15, 1] of the design's maximum depth or force; shear (P, 2) the tangential
    force over the normal force (pad; zeros for a design without shear)."""

    name: str
    move_s: float
    where: np.ndarray
    level: np.ndarray
    shear: np.ndarray

    @property
    def press_s(self) -> float:
        """Robot seconds of one press with its move."""
        return self.move_s + LOAD_S + HOLD_S + UNLOAD_S

    @property
    def duration_s(self) -> float:
        return len(self.level) * self.press_s


# A flat design's plan draws its points at random by default: level with presses chosen from full runs, where
# Halton points trail them by 5-15% (research log entries 212 and 214). A run's record names its points
# unless they are Halton's (PLAN_POINTS[0]), so runs simulated before keep their content.
DEFAULT_PLAN_POINTS = "random"


def design_plan(design: FlatDesign, seconds: float, move_s: float = PLAN_MOVE_S, seed: int = 0,
                points: str = DEFAULT_PLAN_POINTS) -> FlatPlan:
    """The designed calibration of `design` that fits `seconds` of robot time: as many presses as
    fit (each `move_s` plus about 1.1 s of contact) over the pressed region, the load levels of the
    full protocol (0.15-1 of the maximum) and, on a design with shear, its directions and ratios,
    drawn by `seed`. `points` 'random' (the default) draws each independently and uniformly over those
    ranges, as the random protocols draw theirs; 'halton' spreads them evenly by a scrambled Halton
    sequence (scipy.stats.qmc). One orientation, no re-mount. Name: plan<seconds>."""
    from scipy.stats import qmc

    check_plan_points(points)
    if not np.isfinite(seconds) or seconds <= 0:
        raise AnytipError(f"a calibration plan needs a finite duration > 0 s, got {seconds}")
    if not np.isfinite(move_s) or move_s <= 0:
        raise AnytipError(f"a designed plan needs a move time > 0 s, got {move_s}")
    press_s = move_s + LOAD_S + HOLD_S + UNLOAD_S
    n = int(np.floor(seconds / press_s * (1 + 1e-12)))  # 120 s of 1.6 s presses is 75, not 74.999
    if n < 1:
        raise AnytipError(f"{seconds:g} s of robot time holds no press of {design.name}'s designed plan "
                          f"(one takes {press_s:.1f} s with its move)")
    x0, x1, y0, y1 = design.region_m
    dims = 2 + (y1 > y0) + 2 * (design.shear_ratio > 0)
    u = (qmc.Halton(dims, scramble=True, seed=seed).random(n) if points == "halton"
         else np.random.default_rng(seed).random((n, dims)))
    y = np.full(n, y0) if y1 == y0 else y0 + (y1 - y0) * u[:, 2]
    where = np.column_stack([x0 + (x1 - x0) * u[:, 0], y])
    shear = np.zeros((n, 2))
    if design.shear_ratio > 0:
        angle, ratio = 2 * np.pi * u[:, -2], design.shear_ratio * u[:, -1]
        shear = ratio[:, None] * np.column_stack([np.cos(angle), np.sin(angle)])
    return FlatPlan(f"plan{seconds:g}", move_s, where, 0.15 + 0.85 * u[:, 1], shear)


def plan_waypoints(design: FlatDesign, plan: FlatPlan) -> tuple[tuple[str, ...], np.ndarray]:
    """The plan as stage waypoints: column names and (4P, k) rows, one per segment end of every
    press (load starts, load reached, hold ends, unloaded). Columns: time_s from the plan's start
    (moves included), x_m and y_m the pressed point, then the command: depth_m (indentation, m) for a
    design the rig drives by depth, else fx_n, fy_n, fz_n (N on the layer; fz_n < 0 presses)."""
    by_depth = design.max_depth_m is not None
    columns = ("time_s", "x_m", "y_m") + (("depth_m",) if by_depth else ("fx_n", "fy_n", "fz_n"))
    ends = np.cumsum([plan.move_s, LOAD_S, HOLD_S, UNLOAD_S])
    rows = []
    for k in range(len(plan.level)):
        top = (np.array([design.max_depth_m * plan.level[k]]) if by_depth else
               design.max_force_n * plan.level[k] * np.append(plan.shear[k], -1.0))
        for t, load in zip(k * plan.press_s + ends, (0.0, 1.0, 1.0, 0.0), strict=True):
            rows.append(np.concatenate([[t], plan.where[k], load * top + 0.0]))  # no -0.0
    return columns, np.asarray(rows)


def _trajectory(design: FlatDesign, unit: FlatUnit, presses: int | FlatPlan, rng: np.random.Generator
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(load point (N, 2) m, force on the layer (N, 3) N, depth (N,) m, load (N,) in [0, 1] of
    the design's maximum) of `presses` random presses or of a designed plan's."""
    x0, x1, y0, y1 = design.region_m
    parts: dict[str, list[np.ndarray]] = {"xy": [], "u": [], "peak": [], "shear": []}
    rest = int(REST_S * RATE_HZ)

    def add(u: np.ndarray, where: np.ndarray, peak: float, shear: np.ndarray) -> None:
        parts["xy"].append(np.tile(where, (len(u), 1)))
        parts["u"].append(u)
        parts["peak"].append(np.full(len(u), peak))
        parts["shear"].append(np.tile(shear, (len(u), 1)))

    add(np.zeros(rest), np.zeros(2), 0.0, np.zeros(2))
    if isinstance(presses, FlatPlan):
        for k in range(len(presses.level)):
            add(_profile(presses.move_s, HOLD_S), presses.where[k], presses.level[k], presses.shear[k])
    else:
        for _ in range(presses):
            u = _press_profile(rng)
            where = np.array([rng.uniform(x0, x1), rng.uniform(y0, y1)])
            angle, ratio = rng.uniform(0, 2 * np.pi), design.shear_ratio * rng.uniform(0, 1)
            shear = ratio * np.array([np.cos(angle), np.sin(angle)])
            add(u, where, rng.uniform(0.15, 1.0), shear)
    xy, u = np.concatenate(parts["xy"]), np.concatenate(parts["u"])
    level, shear = u * np.concatenate(parts["peak"]), np.concatenate(parts["shear"])
    if design.max_depth_m is not None:
        depth = design.max_depth_m * level
        fn = hertz_force(depth, unit, design.tip_radius_m)
    else:
        fn = design.max_force_n * level
        e_star = unit.modulus_pa / (1.0 - POISSON**2)
        depth = (3.0 * fn / (4.0 * e_star * np.sqrt(design.tip_radius_m))) ** (2.0 / 3.0)
    force = np.column_stack([shear * fn[:, None], -fn])
    return xy, force, depth, level


def _presses(design: FlatDesign, protocol: str, rng: np.random.Generator, move_s: float, points: str
             ) -> int | FlatPlan:
    """What a run of `protocol` presses: a count of random presses, or a designed plan of `points`
    whose rig moves `move_s` before each press."""
    seconds = designed_seconds(protocol)
    if seconds is not None:
        return design_plan(design, seconds, move_s, int(rng.integers(2**32)), points)
    if protocol not in PROTOCOLS:
        raise AnytipError(f"flat sensors have protocols {sorted(PROTOCOLS)} and plan<seconds>, "
                          f"not {protocol!r}")
    return PROTOCOLS[protocol]


def _count(presses: int | FlatPlan) -> int:
    return len(presses.level) if isinstance(presses, FlatPlan) else presses


def simulate_run(design: FlatDesign, unit: FlatUnit, protocol: str, seed: list[int], sensor_id: str,
                 created: str, move_s: float = PLAN_MOVE_S, points: str = DEFAULT_PLAN_POINTS) -> FlatRun:
    """One run of `unit` playing `protocol` (a name in PROTOCOLS, or plan<seconds>: `design_plan` with
    `move_s` moves and `points`, drawn from the run's seed), deterministic from `seed`. A designed run
    records moves other than the default and points other than Halton's (`protocol.move_s`,
    `protocol.points`) so that it replays."""
    rng = np.random.default_rng(np.random.SeedSequence(seed))
    presses = _presses(design, protocol, rng, move_s, points)
    xy, force, depth, level = _trajectory(design, unit, presses, rng)
    n = len(level)
    p = relax(layer_pressure(xy, force, unit, design.tip_radius_m), 1.0 / RATE_HZ, 0.05, 2.0)
    pressure = ATMOSPHERE_PA + unit.preload_pa + unit.gain * p + unit.noise_pa * rng.standard_normal(p.shape)
    in_contact = level > CONTACT_LEVEL
    position = xy[:, : 1 if design.max_depth_m is not None else 2]
    values = {"position": position + 2e-5 * rng.standard_normal(position.shape),
              "depth": depth[:, None] + 5e-6 * rng.standard_normal((n, 1)),
              "force": force + 0.05 * rng.standard_normal((n, 3))}
    targets = {name: np.where(in_contact[:, None], values[name], 0.0).astype(np.float32)
               for name, _, _ in design.targets}
    record = {"simulator": SIMULATOR, "version": VERSION, "sensor_id": sensor_id, "created": created,
              "seed": list(seed), "protocol": {"name": protocol, "presses": _count(presses)},
              "unit": unit.to_json()}
    if isinstance(presses, FlatPlan) and move_s != PLAN_MOVE_S:
        record["protocol"]["move_s"] = move_s
    if isinstance(presses, FlatPlan) and points != PLAN_POINTS[0]:
        record["protocol"]["points"] = points
    return FlatRun(sensor_id, design, created, np.arange(n) / RATE_HZ,
                   pressure.astype(np.float32), in_contact, targets, record)


def simulate_fleet(design_name: str, n_units: int, seed: int, protocols: tuple[str, ...] = ("full",),
                   severity: float = 1.0, move_s: float = PLAN_MOVE_S, points: str = DEFAULT_PLAN_POINTS
                   ) -> list[FlatRun]:
    """Every run of `n_units` units of a flat design, one run per protocol; unit i is drawn from
    SeedSequence([seed, i, 0]) and its run k from [seed, i, k + 1], as for the fingertip. The rig
    moves `move_s` before each press of a designed plan (plan<seconds>) of `points` (`design_plan`)."""
    design = get_design(design_name)
    runs = []
    for i in range(n_units):
        unit = draw_unit(design, np.random.default_rng(np.random.SeedSequence([seed, i, 0])), severity)
        sensor_id = f"{design.id_prefix}{seed}-{i:03d}"
        for k, protocol in enumerate(protocols):
            created = f"2024-01-{1 + i % 28:02d}T{(2 * k) % 24:02d}:00:00Z"
            runs.append(simulate_run(design, unit, protocol, [seed, i, k + 1], sensor_id, created, move_s,
                                     points))
    return runs


def regenerate(record: dict[str, Any] | str) -> FlatRun:
    """Replay a flat run from its `simulator` record, bit for bit."""
    record = json.loads(record) if isinstance(record, str) else record
    if record.get("simulator") != SIMULATOR or record.get("version") != VERSION:
        raise AnytipError(f"simulator record {record.get('simulator')!r} version {record.get('version')!r} "
                          f"cannot be replayed by {SIMULATOR} version {VERSION}")
    unit = FlatUnit.from_json(record["unit"])
    return simulate_run(get_design(unit.design), unit, record["protocol"]["name"], record["seed"],
                        record["sensor_id"], record["created"], record["protocol"].get("move_s", PLAN_MOVE_S),
                        record["protocol"].get("points", PLAN_POINTS[0]))
