"""The one-trial fits as they were at commit 37aa67d, kept as an independent reference.

The fits (lineload.fitting) now run many trials at once in one batch core, and
their one-trial functions are that core with a batch of one.  To check that the
batch core gives what the straightforward code gave, the tests compare it with
this copy of the earlier code: the fits and the model functions they call,
unchanged except for docstrings removed and results returned as plain dicts; with
them, the per-trial checks of lineload.sensitivity (curve gap, reach).
It uses no lineload code.
"""

import math

import numpy as np

CHI2_1DOF_95 = 3.841458820694124
L_SEARCH_SPAN = 1000.0
MAX_ONE_TO_ONE_RATIO = 1.0 / math.sqrt(6.0)


def waterbed_deflection_mm(distance_mm, depth_mm, L_mm):
    s = np.asarray(distance_mm, dtype=float) / L_mm
    profile = depth_mm * (3.0 * s**2 - 4.0 * s + 1.0)
    return np.where(s > 1.0, 0.0, profile)


def resting_position_mm(distance_mm, depth_mm, L_mm):
    distance_mm, L_mm = np.broadcast_arrays(
        np.asarray(distance_mm, dtype=float), np.asarray(L_mm, dtype=float)
    )
    k = 6.0 * (depth_mm / L_mm) ** 2
    t = distance_mm / L_mm
    inside = (t < 1.0) & (k < 1.0)
    t_in = np.where(inside, t, 0.0)
    k_in = np.where(inside, k, 0.0)
    s = np.clip(t_in + k_in * t_in * (t_in - 1.0) ** 2, 0.0, 1.0)
    for _ in range(50):
        residual = s - k_in * s * (s - 1.0) ** 2 - t_in
        step = residual / (1.0 - k_in * (s - 1.0) * (3.0 * s - 1.0))
        s = np.clip(s - step, 0.0, 1.0)
        if np.max(np.abs(step), initial=0.0) <= 1e-15:
            break
    curved = inside & (k > 0.0)
    X_mm = np.where(curved, s * np.where(curved, L_mm, 1.0), distance_mm)
    return np.where(k < 1.0, X_mm, np.nan)


def shifted_deflection_mm(distance_mm, depth_mm, L_mm):
    X_mm = resting_position_mm(distance_mm, depth_mm, L_mm)
    return waterbed_deflection_mm(X_mm, depth_mm, L_mm)


def _shape_and_slope(phi):
    sin, sin2 = (np.sin(phi), np.sin(2.0 * phi))
    numerator = 2.0 * phi - sin2
    shape = numerator / (4.0 * sin**2)
    return (shape, 1.0 - numerator * sin2 / (4.0 * sin**4))


def _solve_half_angle_scalar(target):
    phi = min(3.0 * target - 3.6 * target**3, math.pi / 2)
    if phi < 0.001:
        return phi
    for _ in range(50):
        sin, sin2 = (math.sin(phi), math.sin(2.0 * phi))
        numerator = 2.0 * phi - sin2
        step = (numerator / (4.0 * sin**2) - target) / (1.0 - numerator * sin2 / (4.0 * sin**4))
        phi = min(max(phi - step, 0.001), math.pi / 2)
        if abs(step) <= 1e-15 + 1e-13 * phi:
            break
    return phi


def _solve_half_angle(target):
    target = np.asarray(target, dtype=float)
    if target.size == 1:
        return np.full(target.shape, _solve_half_angle_scalar(float(target.reshape(-1)[0])))
    start = np.minimum(3.0 * target - 3.6 * target**3, np.pi / 2)
    small = start < 0.001
    phi = np.where(small, 1.0, start)
    for _ in range(50):
        shape, slope = _shape_and_slope(phi)
        step = np.where(small, 0.0, (shape - target) / slope)
        phi = np.clip(phi - step, 0.001, np.pi / 2)
        if np.all(np.abs(step) <= 1e-15 + 1e-13 * phi):
            break
    return np.where(small, start, phi)


def arc_geometry(depth_mm, L_mm):
    depth_mm, L_mm = np.broadcast_arrays(
        np.asarray(depth_mm, dtype=float), np.asarray(L_mm, dtype=float)
    )
    target = depth_mm * L_mm / (L_mm**2 + depth_mm**2)
    phi = _solve_half_angle(target)
    chord_mm = np.hypot(L_mm, depth_mm)
    with np.errstate(divide="ignore", invalid="ignore"):
        radius_mm = chord_mm / (2.0 * np.sin(phi))
        offset_mm = radius_mm * np.cos(phi)
        centre_x_mm = L_mm / 2.0 + offset_mm * depth_mm / chord_mm
        centre_z_mm = -depth_mm / 2.0 - offset_mm * L_mm / chord_mm
    is_graph = np.tan(phi) * depth_mm <= L_mm
    return {
        "phi_rad": phi,
        "radius_mm": radius_mm,
        "centre_x_mm": centre_x_mm,
        "centre_z_mm": centre_z_mm,
        "is_graph": is_graph,
    }


def arc_deflection_mm(distance_mm, depth_mm, L_mm):
    distance_mm = np.asarray(distance_mm, dtype=float)
    geometry = arc_geometry(depth_mm, L_mm)
    if not bool(geometry["is_graph"]):
        return np.full(distance_mm.shape, np.nan)
    dx = distance_mm - geometry["centre_x_mm"]
    z_mm = geometry["centre_z_mm"] + np.sqrt(np.maximum(geometry["radius_mm"] ** 2 - dx**2, 0.0))
    return np.where(distance_mm <= L_mm, -z_mm, 0.0)


def boussinesq_deflection_mm(distance_mm, A_mm, x0_mm):
    return A_mm * np.log(x0_mm / np.asarray(distance_mm, dtype=float))


def goodness_of_fit(residual_mm, n_params):
    residual_mm = np.asarray(residual_mm, dtype=float)
    n = residual_mm.size
    sse = float(np.sum(residual_mm**2))
    k = n_params + 1
    if n - k - 1 > 0:
        with np.errstate(divide="ignore"):
            aicc = n * np.log(sse / n) + 2 * k + 2 * k * (k + 1) / (n - k - 1)
    else:
        aicc = np.nan
    return {
        "sse_mm2": sse,
        "rmse_mm": float(np.sqrt(sse / n)) if n else np.nan,
        "max_abs_residual_mm": float(np.max(np.abs(residual_mm))) if n else np.nan,
        "aicc": float(aicc),
    }


def _result(model, params, residual_mm, n_params):
    return {
        "model": model,
        "params": params,
        "n_points": int(np.size(residual_mm)),
        "n_params": n_params,
        "residual_mm": np.asarray(residual_mm, dtype=float),
        **goodness_of_fit(residual_mm, n_params),
    }


def _as_points(distance_mm, deflection_mm, minimum):
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.asarray(deflection_mm, dtype=float)
    if distance_mm.shape != deflection_mm.shape or distance_mm.ndim != 1:
        raise ValueError("distance_mm and deflection_mm must be 1-D arrays of equal length")
    if distance_mm.size < minimum:
        raise ValueError(f"at least {minimum} points are needed, got {distance_mm.size}")
    if not (np.all(np.isfinite(distance_mm)) and np.all(np.isfinite(deflection_mm))):
        raise ValueError("distances and deflections must be finite")
    if np.any(distance_mm <= 0):
        raise ValueError("distances must be > 0 (the load point itself is not fitted)")
    return (distance_mm, deflection_mm)


def profile_interval(sse_of_L, L_best, L_min, L_max, sse_min, n_points, chi2=CHI2_1DOF_95):
    if not np.isfinite(L_best) or n_points < 2:
        return (np.nan, np.nan)
    threshold = max(sse_min, np.finfo(float).tiny) * np.exp(chi2 / n_points)

    def too_far(L):
        return sse_of_L(np.array([L]))[0] > threshold

    def log_ratio(L):
        return np.log(max(sse_of_L(np.array([L]))[0], np.finfo(float).tiny) / threshold)

    ends = []
    for bound, step in ((L_min, 1 / 1.05), (L_max, 1.05)):
        inside, outside = (L_best, L_best)
        while not too_far(outside):
            inside = outside
            if outside == bound:
                outside = None
                break
            outside = min(outside * step, bound) if step > 1 else max(outside * step, bound)
        if outside is None:
            ends.append(bound if step < 1 else np.inf)
            continue
        if inside == outside:
            ends.append(inside)
            continue
        ends.append(_crossing(log_ratio, inside, outside))
    return (float(ends[0]), float(ends[1]))


def _crossing(g, inside, outside, rtol=1e-10):
    a, b = (inside, outside)
    fa, fb = (g(a), g(b))
    last = 0
    for _ in range(100):
        c = (a * fb - b * fa) / (fb - fa)
        fc = g(c)
        if fc > 0:
            b, fb = (c, fc)
            if last == -1:
                fa /= 2.0
            last = -1
        else:
            a, fa = (c, fc)
            if last == 1:
                fb /= 2.0
            last = 1
        if abs(b - a) <= rtol * abs(c) or abs(fc) <= 1e-14:
            break
    return c


def fit_waterbed(distance_mm, deflection_mm, depth_mm):
    x, y = _as_points(distance_mm, deflection_mm, minimum=1)
    a = y - depth_mm
    b = 4.0 * depth_mm * x
    c = -3.0 * depth_mm * x**2
    quartic = np.array(
        [
            np.sum(c * c),
            2.0 * np.sum(b * c),
            np.sum(b * b + 2.0 * a * c),
            2.0 * np.sum(a * b),
            np.sum(a * a),
        ]
    )
    u_max = 1.0 / x.max()
    roots = np.roots(np.polyder(quartic))
    scale = max(1.0, float(np.max(np.abs(roots)))) if roots.size else 1.0
    real = roots[np.abs(roots.imag) <= 1e-09 * scale].real
    candidates = np.concatenate([[0.0, u_max], real[(real > 0) & (real < u_max)]])
    sse = np.polyval(quartic, candidates)
    u_best = float(candidates[np.argmin(sse)])
    L_mm = np.inf if u_best == 0.0 else 1.0 / u_best
    residual = y - waterbed_deflection_mm(x, depth_mm, L_mm)
    low, high = profile_interval(
        lambda L: np.polyval(quartic, 1.0 / np.asarray(L)),
        L_mm,
        x.max(),
        np.inf,
        float(np.sum(residual**2)),
        x.size,
    )
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _result("waterbed", params, residual, n_params=1)


def _arc_sse(x, y, depth_mm, L_mm):
    L_mm = np.atleast_1d(np.asarray(L_mm, dtype=float))
    geometry = arc_geometry(depth_mm, L_mm[:, None])
    dx = x[None, :] - geometry["centre_x_mm"]
    z = geometry["centre_z_mm"] + np.sqrt(np.maximum(geometry["radius_mm"] ** 2 - dx**2, 0.0))
    model = np.where(x[None, :] <= L_mm[:, None], -z, 0.0)
    sse = np.sum((y[None, :] - model) ** 2, axis=1)
    return np.where(geometry["is_graph"][:, 0], sse, np.inf)


def minimise_in_L(sse_of_L, L_min, L_max, n_grid=200, rtol=1e-09):
    grid = np.geomspace(L_min, L_max, n_grid)
    sse = sse_of_L(grid)
    if not np.any(np.isfinite(sse)):
        raise ValueError(f"no admissible L between {L_min:g} and {L_max:g} mm")
    best = int(np.argmin(sse))
    lo, hi = (grid[max(best - 1, 0)], grid[min(best + 1, n_grid - 1)])
    while hi - lo > rtol * hi:
        points = np.linspace(lo, hi, 17)
        k = int(np.argmin(sse_of_L(points)))
        lo, hi = (points[max(k - 1, 0)], points[min(k + 1, 16)])
    candidates = np.array([grid[best], 0.5 * (lo + hi)])
    return float(candidates[np.argmin(sse_of_L(candidates))])


def _fit_L_by_search(model, x, y, sse_of_L, deflection, L_lo):
    L_hi = L_SEARCH_SPAN * x.max()
    try:
        L_mm = minimise_in_L(sse_of_L, L_lo, L_hi)
    except ValueError as error:
        raise ValueError(f"no valid {model} curve: {error}") from None
    residual = y - deflection(x, L_mm)
    low, high = profile_interval(sse_of_L, L_mm, L_lo, L_hi, float(np.sum(residual**2)), x.size)
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high}
    return _result(model, params, residual, n_params=1)


def fit_arc(distance_mm, deflection_mm, depth_mm):
    x, y = _as_points(distance_mm, deflection_mm, minimum=1)
    return _fit_L_by_search(
        "arc",
        x,
        y,
        lambda L: _arc_sse(x, y, depth_mm, L),
        lambda x, L: arc_deflection_mm(x, depth_mm, L),
        x.max(),
    )


def _shifted_sse(x, y, depth_mm, L_mm):
    L_mm = np.atleast_1d(np.asarray(L_mm, dtype=float))
    model = shifted_deflection_mm(x[None, :], depth_mm, L_mm[:, None])
    sse = np.sum((y[None, :] - model) ** 2, axis=1)
    return np.where(np.isfinite(sse), sse, np.inf)


def fit_shifted(distance_mm, deflection_mm, depth_mm):
    x, y = _as_points(distance_mm, deflection_mm, minimum=1)
    fold_mm = abs(float(depth_mm)) / MAX_ONE_TO_ONE_RATIO * (1.0 + 1e-09)
    return _fit_L_by_search(
        "shifted",
        x,
        y,
        lambda L: _shifted_sse(x, y, depth_mm, L),
        lambda x, L: shifted_deflection_mm(x, depth_mm, L),
        max(x.max(), fold_mm),
    )


def fit_waterbed_free_depth(distance_mm, deflection_mm):
    x, y = _as_points(distance_mm, deflection_mm, minimum=2)
    L_lo, L_hi = (x.max(), L_SEARCH_SPAN * x.max())

    def shape_and_depth(L):
        s = x[None, :] / np.atleast_1d(np.asarray(L, dtype=float))[:, None]
        g = 3.0 * s**2 - 4.0 * s + 1.0
        return (g, np.sum(y * g, axis=1) / np.sum(g * g, axis=1))

    def sse_of_L(L):
        g, W0 = shape_and_depth(L)
        return np.sum((y[None, :] - W0[:, None] * g) ** 2, axis=1)

    L_mm = minimise_in_L(sse_of_L, L_lo, L_hi)
    W0_mm = float(shape_and_depth(L_mm)[1][0])
    residual = y - waterbed_deflection_mm(x, W0_mm, L_mm)
    low, high = profile_interval(sse_of_L, L_mm, L_lo, L_hi, float(np.sum(residual**2)), x.size)
    params = {"L_mm": L_mm, "L_ci_low_mm": low, "L_ci_high_mm": high, "W0_mm": W0_mm}
    return _result("waterbed_free_depth", params, residual, n_params=2)


def fit_boussinesq(distance_mm, deflection_mm):
    x, y = _as_points(distance_mm, deflection_mm, minimum=2)
    log_x = np.log(x)
    design = np.column_stack([np.ones_like(log_x), -log_x])
    (intercept, A_mm), *_ = np.linalg.lstsq(design, y, rcond=None)
    residual = y - design @ np.array([intercept, A_mm])
    x0_mm = float(np.exp(intercept / A_mm)) if A_mm > 0 else np.nan
    if A_mm > 0:
        residual = y - boussinesq_deflection_mm(x, A_mm, x0_mm)
    return _result("boussinesq", {"A_mm": float(A_mm), "x0_mm": x0_mm}, residual, n_params=2)


def fit_trial(distance_mm, deflection_mm, depth_mm, window_mm):
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.asarray(deflection_mm, dtype=float)
    keep = (distance_mm > 0) & (distance_mm <= window_mm) & np.isfinite(deflection_mm)
    x, y = (distance_mm[keep], deflection_mm[keep])
    row = {
        "depth_mm": float(depth_mm),
        "fit_window_mm": float(window_mm),
        "n_points": int(x.size),
        "max_distance_mm": float(x.max()) if x.size else np.nan,
    }
    fits = {
        "waterbed": (lambda: fit_waterbed(x, y, depth_mm), ["L_mm", "L_ci_low_mm", "L_ci_high_mm"]),
        "shifted": (lambda: fit_shifted(x, y, depth_mm), ["L_mm", "L_ci_low_mm", "L_ci_high_mm"]),
        "arc": (lambda: fit_arc(x, y, depth_mm), ["L_mm", "L_ci_low_mm", "L_ci_high_mm"]),
        "boussinesq": (lambda: fit_boussinesq(x, y), ["A_mm", "x0_mm"]),
    }
    for model, (fit, names) in fits.items():
        try:
            result = fit()
        except ValueError:
            result = None
        for name in names:
            row[f"{model}_{name}"] = result["params"][name] if result else np.nan
        for measure in ("rmse_mm", "max_abs_residual_mm", "aicc"):
            row[f"{model}_{measure}"] = result[measure] if result else np.nan
    return row


#: The waterbed curves in measured coordinates, by model name (lineload.sensitivity).
CONSISTENT_CURVES = {"shifted": shifted_deflection_mm, "arc": arc_deflection_mm}


def curve_gap_mm(depth_mm, waterbed_L_mm, other_L_mm, max_distance_mm, model, n_points=601):
    values = (depth_mm, waterbed_L_mm, other_L_mm, max_distance_mm)
    if not all(np.isfinite(v) for v in values):
        return np.nan
    x = np.linspace(0.0, max_distance_mm, n_points)
    paper = waterbed_deflection_mm(x, depth_mm, waterbed_L_mm)
    other = CONSISTENT_CURVES[model](x, depth_mm, other_L_mm)
    return float(np.max(np.abs(paper - other)))


def agreement_reach_mm(distance_mm, residual_mm, tolerance_mm):
    order = np.argsort(distance_mm, kind="stable")
    distance_mm = np.asarray(distance_mm, dtype=float)[order]
    outside = np.abs(np.asarray(residual_mm, dtype=float)[order]) > tolerance_mm
    if not outside.any():
        return float(distance_mm[-1]) if distance_mm.size else np.nan
    first = int(np.argmax(outside))
    return float(distance_mm[first - 1]) if first > 0 else 0.0


def trial_checks(distance_mm, deflection_mm, depth_mm, window_mm, reach_fraction):
    distance_mm = np.asarray(distance_mm, dtype=float)
    deflection_mm = np.asarray(deflection_mm, dtype=float)
    usable = (distance_mm > 0) & np.isfinite(deflection_mm)
    x, y = (distance_mm[usable], deflection_mm[usable])
    inside = x <= window_mm
    L_mm = fit_waterbed(x[inside], y[inside], depth_mm)["params"]["L_mm"]
    consistent_L_mm = {
        "shifted": fit_shifted(x[inside], y[inside], depth_mm)["params"]["L_mm"],
        "arc": fit_arc(x[inside], y[inside], depth_mm)["params"]["L_mm"],
    }
    max_distance_mm = float(x[inside].max())
    shift_mm = 8.0 * depth_mm**2 / (9.0 * L_mm)
    residual = y - waterbed_deflection_mm(x, depth_mm, L_mm)
    tolerance_mm = reach_fraction * depth_mm
    beyond = ~inside
    return {
        "depth_mm": float(depth_mm),
        "waterbed_L_mm": L_mm,
        "shifted_L_mm": consistent_L_mm["shifted"],
        "arc_L_mm": consistent_L_mm["arc"],
        **{
            f"gap_{model}_mm": curve_gap_mm(
                depth_mm, L_mm, consistent_L_mm[model], max_distance_mm, model
            )
            for model in CONSISTENT_CURVES
        },
        "shift_at_third_mm": shift_mm,
        "shift_fraction_at_third": shift_mm / (L_mm / 3.0),
        "reach_tolerance_mm": tolerance_mm,
        "reach_mm": agreement_reach_mm(x, residual, tolerance_mm),
        "rmse_within_window_mm": float(np.sqrt(np.mean(residual[inside] ** 2))),
        "rmse_beyond_window_mm": float(np.sqrt(np.mean(residual[beyond] ** 2)))
        if beyond.any()
        else np.nan,
        "n_beyond_window": int(beyond.sum()),
    }
