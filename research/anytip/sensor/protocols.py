"""Calibration protocols: force and contact trajectories the rig plays, at a fixed rate.

A protocol covers, for each orientation o of the unit on the rig, the 6 x 6 cells of
15 deg in theta in [-45, 45] and phi in [o - 45, o + 45]. Cell edges lie on the fixed
grid theta = -45 + 15 k deg, phi = -135 + 15 k deg; every label of a patch lies
strictly inside its cell, so a loader recovers patches by binning label angles.
Per patch the rig presses once per normal-force layer at a fresh point of the cell
and draws an asterisk at that layer: shear out and back along `directions` directions,
up to min(shear_max_n, friction * Fn). Segments are cosine-interpolated.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Literal

import numpy as np
from pydantic import BaseModel, ConfigDict, Field, model_validator

from anytip.errors import AnytipError

CELL_DEG = 15.0
THETA_EDGES_DEG = -45.0 + CELL_DEG * np.arange(7)
PHI_EDGES_DEG = -135.0 + CELL_DEG * np.arange(13)
CELLS_PER_AXIS = 6


class Protocol(BaseModel):
    """A calibration protocol. Durations are seconds of robot time, forces newtons."""

    model_config = ConfigDict(extra="forbid", frozen=True)

    name: str
    orientations_deg: tuple[float, ...] = (0.0, -45.0, -90.0)
    patches: int = Field(36, ge=1, le=36, description="patches per orientation")
    layers_n: tuple[float, ...] = (6.25, 12.5, 18.75, 25.0)
    directions: int = Field(8, ge=1)
    friction: float = Field(0.8, gt=0)
    shear_max_n: float = Field(15.0, ge=0)
    ramp_s: float = Field(0.4, gt=0)
    hold_s: float = Field(0.1, gt=0)
    shear_s: float = Field(0.18, gt=0, description="each way, out or back")
    gap_s: float = Field(0.15, gt=0, description="no contact between presses of a patch")
    patch_rest_s: float = Field(1.0, gt=0, description="no contact before each patch")
    margin_deg: float = Field(0.5, ge=0, lt=7.5, description="press points keep off cell edges")
    sample_rate_hz: float = Field(200.0, gt=0)
    order: Literal["serpentine", "spread", "random"] = Field(
        "serpentine", description="patch order: neighbours in turn, spread over the region "
        "from the first press on (a subset of patches is always spread, unless random), or drawn at "
        "random (a random subset of the cells in random order, drawn by the run's generator)")
    layer_cycle: bool = Field(
        False, description="`layers_per_patch` presses per patch, each at the next force layer of "
        "layers_n in turn, the cycle running on from patch to patch (else every patch is pressed "
        "once per layer)")
    layers_per_patch: int = Field(1, ge=1, description="presses per patch with layer_cycle")
    layers_random: bool = Field(
        False, description="with layer_cycle: each press's force layer drawn at random from layers_n "
        "instead of the next in turn")

    @model_validator(mode="after")
    def _on_grid(self) -> Protocol:
        for o in self.orientations_deg:
            lo = o - 45.0
            if lo < PHI_EDGES_DEG[0] or lo + 90.0 > PHI_EDGES_DEG[-1] or (lo + 135.0) % CELL_DEG:
                raise ValueError(
                    f"orientation {o} deg puts phi cells off the 15-deg grid in [-135, 45]"
                )
        return self

    @model_validator(mode="after")
    def _needs_layer_cycle(self) -> Protocol:
        if self.layers_per_patch > 1 and not self.layer_cycle:
            raise ValueError("layers_per_patch > 1 needs layer_cycle (else every layer is pressed)")
        if self.layers_random and not self.layer_cycle:
            raise ValueError("layers_random needs layer_cycle (else every layer is pressed in turn)")
        return self

    def to_json(self) -> dict:
        """The protocol as stored in a run. `order`, `layer_cycle`, `layers_per_patch` and
        `layers_random` are left out at their defaults, so runs made before they existed keep their
        content (and their registry hash)."""
        data = self.model_dump(mode="json")
        if data["order"] == "serpentine":
            del data["order"]
        if not data["layer_cycle"]:
            del data["layer_cycle"]
        if data["layers_per_patch"] == 1:
            del data["layers_per_patch"]
        if not data["layers_random"]:
            del data["layers_random"]
        return data

    @property
    def presses_per_patch(self) -> int:
        return self.layers_per_patch if self.layer_cycle else len(self.layers_n)

    def rows_per_press(self) -> int:
        return int(self.segment_samples().sum())

    def rows_per_orientation(self) -> int:
        rest = self.samples(self.patch_rest_s)
        return self.patches * (rest + self.presses_per_patch * self.rows_per_press())

    @property
    def duration_s(self) -> float:
        """Robot time of the whole protocol, all orientations, in seconds."""
        return len(self.orientations_deg) * self.rows_per_orientation() / self.sample_rate_hz

    def samples(self, seconds: float) -> int:
        return max(1, int(round(seconds * self.sample_rate_hz)))

    def segment_samples(self) -> np.ndarray:
        """Samples of each segment of one press: ramp, hold, (out, back) x directions, ramp, gap."""
        s = self.samples
        return np.array(
            [s(self.ramp_s), s(self.hold_s)]
            + [s(self.shear_s)] * (2 * self.directions)
            + [s(self.ramp_s), s(self.gap_s)]
        )


PROTOCOLS: dict[str, Protocol] = {
    "full": Protocol(name="full"),
    "short": Protocol(name="short", patches=4, layers_n=(12.5, 25.0)),
    # A new unit's quick calibration: one press with a small shear cross per patch, patches
    # spread over the region, so the first seconds already cover it.
    "quick": Protocol(name="quick", layers_n=(15.0,), directions=2, ramp_s=0.25, hold_s=0.05,
                      shear_s=0.12, gap_s=0.1, patch_rest_s=0.25, order="spread"),
    # As quick, but each press takes the next of four force layers and shears in four
    # directions, so the first seconds spread over the region and over force together.
    "sweep": Protocol(name="sweep", layers_n=(6.25, 12.5, 18.75, 25.0), layer_cycle=True, directions=4,
                      ramp_s=0.25, hold_s=0.05, shear_s=0.12, gap_s=0.1, patch_rest_s=0.25,
                      order="spread"),
    # The full protocol recorded in a session of its own: a unit's test session (`is_test_session`).
    "retest": Protocol(name="retest"),
}
TEST_SESSION = "retest"


DESIGNED = re.compile(r"plan(\d+(?:\.\d+)?)")  # `plan<seconds>`: the designed calibration of that budget
PLAN_MOVE_S = 2.0  # a designed plan's move before each press where the rig declares none (s)
# A designed plan's points: spread by a low-discrepancy sequence (the default), or drawn at random
PLAN_POINTS = ("halton", "random")


def check_plan_points(points: str) -> None:
    """AnytipError unless `points` names a designed plan's points (PLAN_POINTS)."""
    if points not in PLAN_POINTS:
        raise AnytipError(f"a designed plan's points are one of {', '.join(PLAN_POINTS)}, not {points!r}")


def designed_seconds(protocol: str | None) -> float | None:
    """The robot seconds a designed calibration's name states (`plan120` -> 120.0), else None."""
    designed = None if protocol is None else DESIGNED.fullmatch(protocol)
    return None if designed is None else float(designed.group(1))


def is_designed(protocol: str | None) -> bool:
    """Whether `protocol` names a designed calibration (`plan<seconds>`, `design_protocol`): its runs
    are a calibration plan, not part of a unit's calibration stream or its test data."""
    return designed_seconds(protocol) is not None


def is_test_session(protocol: str | None) -> bool:
    """Whether `protocol` names a unit's test session (`retest`): runs recorded apart from its
    calibration, in sessions of their own. Where a unit has them, its held-out test rows come from
    them alone and nothing else reads them (no training, calibration stream or plan)."""
    return protocol == TEST_SESSION


def get_protocol(protocol: str | Protocol | dict) -> Protocol:
    """A built-in protocol by name ('full', 'short', 'quick', 'sweep', 'retest', or 'plan<seconds>': the
    designed calibration of that many robot seconds, `design_protocol`), or a Protocol / its dict."""
    if isinstance(protocol, Protocol):
        return protocol
    if isinstance(protocol, dict):
        return Protocol.model_validate(protocol)
    seconds = designed_seconds(protocol)
    if seconds is not None:
        return design_protocol(seconds)
    if protocol not in PROTOCOLS:
        raise AnytipError(
            f"unknown protocol {protocol!r}; built-in protocols: {', '.join(PROTOCOLS)}, plan<seconds>"
        )
    return PROTOCOLS[protocol]


@dataclass
class Trajectory:
    """What the rig commands over one run (N rows).

    force (N, 3) N true contact-frame force; angles (N, 2) rad commanded contact
    (theta, phi), which are the labels; in_contact (N,) bool; press (N,) int index of
    the current press and patch (N,) int index of its patch (rest rows belong to the
    press before, or to press 0 at the start of the run); cells (P, 2) int cell
    indices (theta, phi) on the global grid, one row per patch.
    """

    force: np.ndarray
    angles: np.ndarray
    in_contact: np.ndarray
    press: np.ndarray
    patch: np.ndarray
    cells: np.ndarray


def patch_cells(protocol: Protocol, orientation_deg: float,
                rng: np.random.Generator | None = None) -> np.ndarray:
    """(P, 2) global cell indices (theta index 0..5, phi index 0..11) the rig visits.

    All 36 in serpentine order, a subset spread by a 2-D Kronecker sequence, or (order 'random')
    a subset drawn at random by `rng`, in random order.
    """
    phi0 = int(round((orientation_deg - 45.0 + 135.0) / CELL_DEG))
    grid = [(i, j if i % 2 == 0 else CELLS_PER_AXIS - 1 - j) for i in range(6) for j in range(6)]
    if protocol.order == "random":
        if rng is None:
            raise ValueError("a protocol of random patch order needs the run's generator")
        grid = [grid[k] for k in rng.permutation(len(grid))[: protocol.patches]]
    elif protocol.patches < len(grid) or protocol.order == "spread":
        g = 1.32471795724474602596  # plastic number: the R2 low-discrepancy sequence
        k = np.arange(max(protocol.patches * 4, 400))
        ti = np.floor(6 * ((0.5 + k / g) % 1)).astype(int)
        pj = np.floor(6 * ((0.5 + k / g**2) % 1)).astype(int)
        seen = dict.fromkeys(zip(ti.tolist(), pj.tolist(), strict=True))
        grid = list(seen)[: protocol.patches]
    cells = np.array(grid, dtype=int)
    cells[:, 1] += phi0
    return cells


def _press_points(cells: np.ndarray, n_layers: int, margin: float, rng: np.random.Generator):
    """(P * L, 2) rad press angles: uniform inside each cell, `margin` deg off its edges."""
    lo = np.stack([THETA_EDGES_DEG[cells[:, 0]], PHI_EDGES_DEG[cells[:, 1]]], -1)
    lo = np.repeat(lo, n_layers, axis=0)
    return np.deg2rad(lo + margin + rng.random(lo.shape) * (CELL_DEG - 2 * margin))


def _waypoints(protocol: Protocol, n_presses: int, rng: np.random.Generator) -> np.ndarray:
    """(Q, K + 1, 3) N contact-frame force at the segment ends of each of Q presses: the layers
    in turn (every layer per patch, or one per patch with `layer_cycle`; drawn at random with
    `layers_random`)."""
    levels = np.asarray(protocol.layers_n, float)
    layers = rng.choice(levels, n_presses) if protocol.layers_random else np.resize(levels, n_presses)
    fn = layers * rng.uniform(0.9, 1.0, layers.shape)
    d = protocol.directions
    angle = 2 * np.pi * np.arange(d) / d + rng.uniform(0, 2 * np.pi / d, (n_presses, 1))
    shear = np.minimum(protocol.shear_max_n, protocol.friction * fn)[:, None]
    shear = shear * rng.uniform(0.7, 1.0, (n_presses, d))
    w = np.zeros((n_presses, 2 * d + 5, 3))
    w[:, 1:-2, 2] = -fn[:, None]
    w[:, 3:-2:2, 0] = shear * np.cos(angle)
    w[:, 3:-2:2, 1] = shear * np.sin(angle)
    return w


def _interpolate(waypoints: np.ndarray, seg: np.ndarray) -> np.ndarray:
    """(Q, R, 3) cosine interpolation between waypoints (Q, K + 1, 3); seg (K,) samples."""
    which = np.repeat(np.arange(seg.size), seg)
    start = np.concatenate([[0], np.cumsum(seg)[:-1]])
    u = (np.arange(seg.sum()) - start[which]) / seg[which]
    w = ((1.0 - np.cos(np.pi * u)) / 2.0)[None, :, None]
    a, b = waypoints[:, which], waypoints[:, which + 1]
    return a + w * (b - a)


def build_trajectory(
    protocol: Protocol, orientation_deg: float, rng: np.random.Generator
) -> Trajectory:
    """The rig's commanded trajectory for one orientation; row count is deterministic."""
    cells = patch_cells(protocol, orientation_deg, rng)
    n_layers, n_patch = protocol.presses_per_patch, cells.shape[0]
    points = _press_points(cells, n_layers, protocol.margin_deg, rng)
    force = _interpolate(_waypoints(protocol, n_patch * n_layers, rng), protocol.segment_samples())
    rows = force.shape[1]
    rest = protocol.samples(protocol.patch_rest_s)
    per_patch = force.reshape(n_patch, n_layers * rows, 3)
    force = np.concatenate([np.zeros((n_patch, rest, 3)), per_patch], axis=1).reshape(-1, 3)
    press_local = np.concatenate([np.full(rest, -1), np.repeat(np.arange(n_layers), rows)])
    press = (np.arange(n_patch)[:, None] * n_layers + press_local[None, :]).reshape(-1)
    press = np.maximum(press, 0)
    patch = press // n_layers
    return Trajectory(
        force=force,
        angles=points[press],
        in_contact=force[:, 2] < 0.0,
        press=press,
        patch=patch,
        cells=cells,
    )


# A designed calibration: presses spread over the region, each at the next of four force levels
# with an 8-direction shear asterisk, on as few orientations as cover phi in [-135, 45] deg.
DESIGNED_PRESS = dict(layers_n=(6.25, 12.5, 18.75, 25.0), layer_cycle=True, directions=8, ramp_s=0.25,
                      hold_s=0.05, shear_s=0.12, gap_s=0.1, order="spread")
# From LONG_PLAN_S on, the full protocol's press and patch instead (Protocol's defaults, the patches
# spread): a patch's four force levels 0.15 s apart, so each press starts from the last one's memory as the
# full protocol's test rows do (research log entries 139 and 141: x0.95-0.97 held out at 600 s, chosen on 64
# fresh validation units, and at 525 s by the same units, entry 145); shorter plans need the points (the
# same units score the full protocol's press 15% worse at 300 s and even at 450 s).
FULL_PROTOCOL_PRESS = dict(order="spread")
LONG_PLAN_S = 525.0
COVERING_ORIENTATIONS_DEG = (0.0, -90.0)  # phi in [-45, 45] and [-135, -45]: the whole region
CENTRE_ORIENTATION_DEG = -45.0  # phi in [-90, 0]: the one orientation of a plan too short to re-mount


def design_protocol(seconds: float, move_s: float = PLAN_MOVE_S, remount_s: float = 30.0,
                    points: str = PLAN_POINTS[0]) -> Protocol:
    """The designed calibration of a new unit that fits `seconds` of robot time.

    Covers theta in [-45, 45] deg and phi in [-135, 45] deg from two orientations when the
    re-mount between them takes at most a quarter of the budget, else the middle orientation alone;
    a budget that presses every cell of two orientations adds the third (as the full protocol).
    Each press: the next force level up to 25 N and a shear asterisk in 8 directions; the rig
    takes `move_s` before each press (the protocol's rest between patches). From `LONG_PLAN_S` on,
    each patch is pressed as the full protocol presses it: its four force levels in turn, 0.15 s apart
    (`FULL_PROTOCOL_PRESS`). As many patches per orientation as fit after the re-mounts. Name:
    plan<seconds>. With `points` 'random', the same presses at as many cells drawn at random, in
    random order, and each press of a short plan at a force level drawn at random (a baseline to
    measure the design against, research log entry 215).
    """
    check_plan_points(points)
    if not np.isfinite(seconds) or seconds <= 0:
        raise AnytipError(f"a calibration plan needs a finite duration > 0 s, got {seconds}")
    if not (np.isfinite(move_s) and move_s > 0 and np.isfinite(remount_s) and remount_s >= 0):
        raise AnytipError(f"a designed plan needs a move time > 0 s and a re-mount time >= 0 s, "
                          f"got {move_s} and {remount_s}")
    press = FULL_PROTOCOL_PRESS if seconds >= LONG_PLAN_S else DESIGNED_PRESS
    if points == "random":
        press = {**press, "order": "random", "layers_random": press.get("layer_cycle", False)}
    probe = Protocol(name="probe", patches=1, patch_rest_s=move_s, **press)
    per_patch = probe.rows_per_orientation() / probe.sample_rate_hz

    def patches_with(orientations: tuple[float, ...]) -> int:
        return int((seconds - remount_s * (len(orientations) - 1)) // (per_patch * len(orientations)))

    # two orientations only where the re-mount leaves most of the budget for points (entry 65)
    orientations = (COVERING_ORIENTATIONS_DEG if remount_s <= seconds / 4 else (CENTRE_ORIENTATION_DEG,))
    if patches_with(orientations) > 36:  # every cell of two orientations pressed: add the third
        orientations = PROTOCOLS["full"].orientations_deg
    patches = patches_with(orientations)
    if patches < 1:
        raise AnytipError(f"{seconds:g} s of robot time holds no press of the designed plan "
                          f"(one takes {per_patch:.1f} s with its move)")
    return Protocol(name=f"plan{seconds:g}", orientations_deg=orientations, patches=min(patches, 36),
                    patch_rest_s=move_s, **press)


def press_summary(protocol: Protocol) -> str:
    """What a protocol presses, in words: its presses, places and orientations
    (e.g. '18 presses, one at each of 18 places, on 2 orientations')."""
    n_orient = len(protocol.orientations_deg)
    places = protocol.patches * n_orient
    per_place = protocol.presses_per_patch
    how = "one" if per_place == 1 else f"{per_place} force levels"
    if places == 1:
        presses = "1 press" if per_place == 1 else f"{per_place} presses, {how}"
        return f"{presses} at 1 place, on 1 orientation"
    return (f"{places * per_place} presses, {how} at each of {places} places, "
            f"on {n_orient} orientation{'s' if n_orient > 1 else ''}")


def waypoints(protocol: Protocol, remount_s: float, rng: np.random.Generator) -> np.ndarray:
    """The protocol as robot waypoints, one row per segment end of every press:
    (K, 7) float64 columns time [s from the start, re-mounts included], orientation [deg],
    theta [deg], phi [deg], commanded Fx, Fy, Fz [N] (contact frame; Fz < 0 presses).
    Between presses the commanded force is 0 and the rig moves to the next point."""
    out, clock = [], 0.0
    seg = protocol.segment_samples() / protocol.sample_rate_hz
    for k, o in enumerate(protocol.orientations_deg):
        clock += remount_s if k else 0.0
        cells = patch_cells(protocol, o, rng)
        n_layers = protocol.presses_per_patch
        points = np.degrees(_press_points(cells, n_layers, protocol.margin_deg, rng))
        force = _waypoints(protocol, len(points), rng)  # (Q, segments + 1, 3)
        ends = np.concatenate([[0.0], np.cumsum(seg)])
        for q in range(len(points)):
            if q % n_layers == 0:
                clock += protocol.patch_rest_s
            for j, t in enumerate(ends):
                out.append([clock + t, o, *points[q], *force[q, j]])
            clock += ends[-1]
    return np.array(out)
