"""Collision impulse ratio of a finger that retracts after a latency (SaLoutos et al. 2023, Fig. 5).

Two-mass model, SI units throughout. A fingertip of mass m_f meets a rigid object at
speed v0 and stops at once (plastic impact: impulse m_f v0). The finger of mass m_r
behind it keeps moving and compresses the spring k between the two; x >= 0 is the
compression and k x the force the stopped tip passes on to the object. After the
latency t_l the actuator applies a constant force f_in that pulls the finger back:

    m_r x'' = -k x - f_in H(t - t_l),   x(0) = 0,  x'(0) = v0.

The collision ends when the spring first returns to rest (x = 0): from then on it
would pull the tip off the object. Impulse on the object:

    I = m_f v0 + integral_0^T k x dt = m_f v0 + m_r (v0 - x'(T)) - f_in max(0, T - t_l),

the second form by momentum of m_r. eta = I / I(f_in = 0), where I(f_in = 0) =
(m_f + 2 m_r) v0 (an elastic bounce of m_r over half a period pi / w, w = sqrt(k / m_r)).

eta depends on the six parameters only through w t_l, m_f / m_r and
f_in / (v0 sqrt(k m_r)), the actuator force over the peak spring force of a free
bounce: with f_in fixed, a faster approach gives a larger eta. docs/analysis.md compares
this closed form with simplified ones and with a numerical integration.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike
from scipy.integrate import solve_ivp

from anytip.errors import AnytipError

# [m_f, m_r, t_l, k, v0, f_in] of the paper's Fig. 5: 5 g, 0.1 kg, 7 ms, 1500 N/m, 0.15 m/s, 10 N
NOMINAL = {"m_f": 0.005, "m_r": 0.1, "t_l": 0.007, "k": 1500.0, "v0": 0.15, "f_in": 10.0}
PARAMS = tuple(NOMINAL)
_POSITIVE = ("m_r", "k", "v0")  # > 0; the others >= 0


@dataclass(frozen=True)
class Collision:
    """Closed-form outcome; arrays broadcast from the parameters.

    impulse (N s) on the object, duration (s) until the spring is back at rest,
    end_velocity (m/s) of the finger then (negative: moving away), eta = impulse over
    the impulse without actuator.
    """

    impulse: np.ndarray
    duration: np.ndarray
    end_velocity: np.ndarray
    eta: np.ndarray


def check_params(**params: ArrayLike) -> dict[str, np.ndarray]:
    """The parameters as float arrays; AnytipError naming the first bad one and its value."""
    out = {}
    for name, value in params.items():
        arr = np.asarray(value, dtype=float)
        bad = ~np.isfinite(arr) | ((arr <= 0) if name in _POSITIVE else (arr < 0))
        if bad.any():
            need = "> 0" if name in _POSITIVE else ">= 0"
            raise AnytipError(f"collision parameter {name} must be finite and {need}, "
                              f"got {float(arr[bad].flat[0])!r}")
        out[name] = arr
    return out


def free_impulse(m_f: ArrayLike, m_r: ArrayLike, v0: ArrayLike) -> np.ndarray:
    """(broadcast) N s impulse without actuator: the tip's m_f v0 plus m_r's elastic bounce 2 m_r v0."""
    return (np.asarray(m_f) + 2.0 * np.asarray(m_r)) * np.asarray(v0)


def collision(m_f: ArrayLike, m_r: ArrayLike, t_l: ArrayLike, k: ArrayLike, v0: ArrayLike,
              f_in: ArrayLike) -> Collision:
    """Closed form of the model, piecewise in time, for broadcastable parameter arrays (SI).

    Phase 1 (t < t_l): x = (v0 / w) sin(w t). If the free half period pi / w ends first,
    the actuator never acts: T = pi / w, x'(T) = -v0. Phase 2 (tau = t - t_l >= 0):
    x = -x_s + R cos(w tau - psi), x_s = f_in / k, R cos psi = x(t_l) + x_s,
    R sin psi = x'(t_l) / w, which first reaches zero at w tau = psi + arccos(x_s / R)
    with x' = -w sqrt(R^2 - x_s^2).
    """
    p = check_params(m_f=m_f, m_r=m_r, t_l=t_l, k=k, v0=v0, f_in=f_in)
    m_f, m_r, t_l, k, v0, f_in = (p[n] for n in PARAMS)
    w = np.sqrt(k / m_r)
    x1, v1 = v0 / w * np.sin(w * t_l), v0 * np.cos(w * t_l)
    x_s = f_in / k
    a, b = x1 + x_s, v1 / w
    r = np.hypot(a, b)
    psi = np.arctan2(b, a)
    # r > 0 as v0 > 0; the clip only matters where phase 2 is never reached (x1 < 0)
    tau = (psi + np.arccos(np.clip(x_s / r, -1.0, 1.0))) / w
    v_end2 = -w * np.sqrt(np.maximum(r * r - x_s * x_s, 0.0))
    free = w * t_l >= np.pi
    duration = np.where(free, np.pi / w, t_l + tau)
    v_end = np.where(free, -v0, v_end2)
    active = np.where(free, 0.0, duration - t_l)
    impulse = m_f * v0 + m_r * (v0 - v_end) - f_in * active
    return Collision(impulse, duration, v_end, impulse / free_impulse(m_f, m_r, v0))


def collision_impulse_ratio(m_f: float, m_r: float, t_l: float, k: float, v0: float,
                            f_in: float) -> float:
    """eta = impulse / impulse without actuator, in closed form.

    m_f, m_r kg; t_l s; k N/m; v0 m/s (approach speed); f_in N (retracting force).
    """
    return float(collision(m_f, m_r, t_l, k, v0, f_in).eta)


def displacement(t: ArrayLike, m_f: float, m_r: float, t_l: float, k: float, v0: float,
                 f_in: float) -> np.ndarray:
    """(N,) m spring compression x(t) at times t (N,) s, closed form, valid for 0 <= t <= duration."""
    p = check_params(m_f=m_f, m_r=m_r, t_l=t_l, k=k, v0=v0, f_in=f_in)
    w = float(np.sqrt(p["k"] / p["m_r"]))
    t = np.asarray(t, float)
    x1, v1 = v0 / w * np.sin(w * t_l), v0 * np.cos(w * t_l)
    x_s, tau = f_in / k, t - t_l
    phase2 = -x_s + (x1 + x_s) * np.cos(w * tau) + v1 / w * np.sin(w * tau)
    return np.where(t < t_l, v0 / w * np.sin(w * t), phase2)


@dataclass(frozen=True)
class NumericCollision:
    """Outcome of `simulate_collision`: impulse (N s), duration (s), and the solver's
    trajectory, times t (K,) s and compressions x (K,) m, from 0 to the end."""

    impulse: float
    duration: float
    t: np.ndarray
    x: np.ndarray


def simulate_collision(m_f: float, m_r: float, t_l: float, k: float, v0: float, f_in: float,
                       rtol: float = 1e-11, atol: float = 1e-14) -> NumericCollision:
    """Numerical integration of the same model (scipy's DOP853), the check on the closed form.

    State (x, x', integral of k x); the actuator step at t_l splits the integration so
    the solver never steps across the discontinuity; an event stops it at x = 0.
    """
    check_params(m_f=m_f, m_r=m_r, t_l=t_l, k=k, v0=v0, f_in=f_in)
    horizon = 4.0 * np.pi * np.sqrt(m_r / k)  # x = 0 comes within half a period of each phase

    def rest(_t: float, y: np.ndarray) -> float:
        return y[0]

    rest.terminal, rest.direction = True, -1.0
    y, t0, ts, xs = np.array([0.0, v0, 0.0]), 0.0, [], []
    for force, t_end in ((0.0, t_l), (f_in, t_l + horizon)):
        def rhs(_t: float, s: np.ndarray, force: float = force) -> list[float]:
            return [s[1], (-k * s[0] - force) / m_r, k * s[0]]

        if t_end <= t0:
            continue
        sol = solve_ivp(rhs, (t0, t_end), y, method="DOP853", rtol=rtol, atol=atol, events=rest)
        ts.append(sol.t)
        xs.append(sol.y[0])
        if sol.status == 1:  # the spring is back at rest
            end = float(sol.t_events[0][0])
            return NumericCollision(m_f * v0 + float(sol.y_events[0][0][2]), end,
                                    np.concatenate(ts), np.concatenate(xs))
        y, t0 = sol.y[:, -1], float(sol.t[-1])
    raise RuntimeError("the spring did not return to rest within the horizon")


def numeric_impulse_ratio(m_f: float, m_r: float, t_l: float, k: float, v0: float, f_in: float) -> float:
    """eta from `simulate_collision`, the reference for the closed form."""
    sim = simulate_collision(m_f, m_r, t_l, k, v0, f_in)
    return sim.impulse / float(free_impulse(m_f, m_r, v0))


def sinusoid_impulse_ratio(m_f: ArrayLike, m_r: ArrayLike, t_l: ArrayLike, k: ArrayLike,
                           v0: ArrayLike, f_in: ArrayLike) -> np.ndarray:
    """A simplified form: x(t) stays the free sinusoid (v0 / w) sin(w t), the contact lasts
    the free half period pi / w, and the actuator subtracts f_in (pi / w - t_l).

    I = (m_f + 2 m_r) v0 - f_in max(0, pi / w - t_l). It ignores that f_in shortens the
    contact and speeds the finger's retreat; it can go negative. Returns eta (broadcast).
    """
    p = check_params(m_f=m_f, m_r=m_r, t_l=t_l, k=k, v0=v0, f_in=f_in)
    half = np.pi * np.sqrt(p["m_r"] / p["k"])
    free = free_impulse(p["m_f"], p["m_r"], p["v0"])
    return (free - p["f_in"] * np.maximum(0.0, half - p["t_l"])) / free


def instant_stop_impulse_ratio(m_f: ArrayLike, m_r: ArrayLike, t_l: ArrayLike, k: ArrayLike,
                               v0: ArrayLike) -> np.ndarray:
    """The other simplified form (the f_in -> infinity limit): the contact ends at t_l.

    I = m_f v0 + m_r v0 (1 - cos(w t_l)) for w t_l < pi, so eta does not depend on v0.
    A lower bound of the closed form. Returns eta (broadcast).
    """
    p = check_params(m_f=m_f, m_r=m_r, t_l=t_l, k=k, v0=v0)
    wt = np.minimum(np.sqrt(p["k"] / p["m_r"]) * p["t_l"], np.pi)
    return (p["m_f"] + p["m_r"] * (1.0 - np.cos(wt))) / (p["m_f"] + 2.0 * p["m_r"])


def eta_grid(x_name: str, x_values: ArrayLike, y_name: str, y_values: ArrayLike,
             base: dict[str, float] | None = None) -> np.ndarray:
    """(len(y), len(x)) closed-form eta over two parameters, the others at `base` (default NOMINAL)."""
    params = dict(NOMINAL if base is None else base)
    for name in (x_name, y_name):
        if name not in PARAMS:
            raise AnytipError(f"unknown collision parameter {name!r}; known: {', '.join(PARAMS)}")
    params[x_name] = np.asarray(x_values, float)[None, :]
    params[y_name] = np.asarray(y_values, float)[:, None]
    return collision(**params).eta
