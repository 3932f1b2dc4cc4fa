"""The estimator file formats: Kalibr, OpenVINS, VINS-Mono/Fusion, ORB-SLAM3, LIO-SAM, MATLAB
and JSON renderers, :func:`export` and :func:`export_all` (the conventions are tabulated in
:mod:`gyrobias.exports`)."""

from __future__ import annotations

import contextvars
import json
import math
import os
from collections.abc import Mapping, Sequence
from typing import Any

from gyrobias import _core
from gyrobias._files import atomic_write
from gyrobias._validation import checked_path, choice, real, ros_topic, sequence
from gyrobias.exports import _yaml
from gyrobias.exports.discretisation import discrete
from gyrobias.noise._types import NoiseCoefficients

__all__ = ["export", "export_all"]  # FORMATS, DEFAULT_FILENAMES: documented in gyrobias.exports

#: Supported formats.
FORMATS: tuple[str, ...] = ("kalibr", "openvins", "vins", "orbslam3", "liosam", "matlab", "json")

#: File name used for each format by :func:`export_all`.
DEFAULT_FILENAMES: dict[str, str] = {
    "kalibr": "imu.yaml",
    "openvins": "kalibr_imu_chain.yaml",
    "vins": "vins_imu.yaml",
    "orbslam3": "orbslam3_imu.yaml",
    "liosam": "liosam_params.yaml",
    "matlab": "imu_noise.m",
    "json": "noise.json",
}

#: SI units of the exported quantities per sensor kind.
_SI = {
    "gyro": {"N": "rad/s/√Hz", "K": "rad/s²/√Hz", "B": "rad/s", "rate": "rad/s"},
    "accel": {"N": "m/s²/√Hz", "K": "m/s³/√Hz", "B": "m/s²", "rate": "m/s²"},
}

_NAMES = {"N": "white noise N", "K": "random walk K", "B": "bias instability B"}


def _group(name: str, value: Any, kind: str) -> list[NoiseCoefficients]:
    if value is None:
        return []
    items = [value] if isinstance(value, NoiseCoefficients) else sequence(name, value)
    for c in items:
        if not isinstance(c, NoiseCoefficients):
            raise TypeError(
                f"{name} must be NoiseCoefficients or a sequence of them, got {type(c).__name__}"
            )
        if c.data_unit is None or c.sensor is None:
            raise ValueError(
                f"{name}: the data unit is unknown; estimator files need SI units (pass units= to the "
                "Allan analysis, e.g. 'deg/s' or 'm/s^2')"
            )
        if c.sensor != kind:
            raise ValueError(
                f"{name}: coefficients of data in {c.data_unit!r} are {c.sensor} coefficients, not {kind}"
            )
    return items


def _split(gyro: Any, accel: Any) -> tuple[list[NoiseCoefficients], list[NoiseCoefficients]]:
    """Sort the arguments into gyro and accel groups (an accel set passed first is accepted)."""
    if gyro is None:
        first: list[Any] = []
    else:
        first = [gyro] if isinstance(gyro, NoiseCoefficients) else sequence("gyro", gyro)
    if (
        accel is None
        and first
        and all(isinstance(c, NoiseCoefficients) and c.sensor == "accel" for c in first)
    ):
        return [], _group("accel", first, "accel")
    g = _group("gyro", first or None, "gyro")
    a = _group("accel", accel, "accel")
    if not g and not a:
        raise ValueError("gyro and accel: no coefficients given to export")
    return g, a


class _Bounded(float):
    """A value written from an upper bound (a term the log does not show): the float, plus
    the note that marks it in the file."""

    note: str

    def __new__(cls, value: float, note: str) -> _Bounded:
        out = super().__new__(cls, value)
        out.note = note
        return out


#: ``strict=`` of the :func:`export` call being rendered (read by :func:`_value`).
_STRICT: contextvars.ContextVar[bool] = contextvars.ContextVar("_STRICT", default=False)


#: A comment line's text made safe (the YAML writer's escaping; MATLAB comments use it too).
_comment = _yaml.comment_text


def _one_line(text: str) -> str:
    """``text`` on one line (a comment in the file must not end early)."""
    return " ".join(str(text).split())


def _value(group: list[NoiseCoefficients], symbol: str, kind: str, fmt: str | None) -> float | None:
    """Largest value over the axes in SI units; ``None`` when absent and ``fmt`` is None.

    An axis whose term was not identified but is bounded by the data
    (:attr:`gyrobias.noise.Term.upper_bound`) contributes its bound; the result is then a
    :class:`_Bounded` whose note marks it in the file — unless ``strict=True`` was given to
    :func:`export`, which refuses bounds for the terms a format requires.
    """
    label = "gyro" if kind == "gyro" else "accel"
    unit = _SI[kind][symbol]
    values = []
    reasons = []
    bounded = []
    for c in group:
        t = c[symbol]
        if t.value is not None:
            values.append(float(t.to(unit).value or 0.0))
        elif t.upper_bound is not None:
            b = t.to(unit)
            values.append(float(b.upper_bound or 0.0))
            level = "?" if t.bound_confidence is None else f"{100.0 * t.bound_confidence:.4g} %"
            bounded.append((c.axis or "?", level, float(b.upper_bound or 0.0)))
        else:
            reasons.append(f"axis {c.axis or '?'}: {t.missing or 'missing'}")
    if reasons:
        if fmt is None:
            return None
        raise ValueError(
            f"{label} {symbol} ({_NAMES[symbol]}): required by the {fmt} format but not available "
            f"({'; '.join(reasons)}); identify it from a longer log (terms=/tau_range=) or give it "
            f"with gyrobias.noise.from_datasheet"
        )
    if not values:
        return None
    best = max(values)
    if not bounded:
        return best
    ascii_unit = unit.replace("²", "^2").replace("³", "^3").replace("√Hz", "sqrt(Hz)")
    detail = "; ".join(
        f"axis {_one_line(a)}: <= {v:.3e} {ascii_unit} at {lvl}" for a, lvl, v in bounded
    )
    if _STRICT.get():
        need = f"required by the {fmt} format but " if fmt is not None else ""
        raise ValueError(
            f"{label} {symbol} ({_NAMES[symbol]}): {need}only bounded from above by the data "
            f"({detail}; the log does not show the term); strict=True refuses upper bounds: "
            "identify it from a longer log or give it with gyrobias.noise.from_datasheet"
        )
    if max(v for _, _, v in bounded) < best:
        return best  # an identified axis is larger than every bound: the value is an estimate
    note = _one_line(
        f"UPPER BOUND, not an estimate: {label} {symbol} not identified ({detail}; one-sided "
        "confidence, the log does not show the term)"
    )
    return _Bounded(best, note)


def _rate(
    rate: float | None, groups: Sequence[NoiseCoefficients], fmt: str, required: bool
) -> float | None:
    if rate is not None:
        return _core.noise.discrete_rate(real("rate", rate))  # finite and > 0: the core's check
    finite = [c.fs for c in groups if math.isfinite(c.fs) and c.fs > 0.0]
    if finite:
        return max(finite)
    if required:
        raise ValueError(f"rate: the {fmt} format needs the IMU rate in Hz (pass rate=)")
    return None


def _axes_note(group: list[NoiseCoefficients]) -> str:
    if len(group) <= 1:
        return ""
    names = ", ".join(str(c.axis or "?") for c in group)
    return f" (largest over axes {names})"


def _fmt(v: float) -> str:
    return f"{v:.6e}"


def _yaml_pair(key: str, value: float | None, comment: str, missing: str) -> _yaml.Item:
    """The entry ``key: value  # comment``, or the comment line ``# key: missing``."""
    if value is None:
        return _yaml.Comment(f"{key}: {missing}")
    if isinstance(value, _Bounded):
        comment = f"{comment}; {value.note}"
    return _yaml.Pair(key, float(value), _fmt(value), comment)


_NOT_MEASURED = "not written: no accelerometer coefficients given"
_NOT_MEASURED_GYRO = "not written: no gyroscope coefficients given"


def _densities(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], fmt: str
) -> dict[str, float | None]:
    return {
        "gN": _value(g, "N", "gyro", fmt) if g else None,
        "gK": _value(g, "K", "gyro", fmt) if g else None,
        "aN": _value(a, "N", "accel", fmt) if a else None,
        "aK": _value(a, "K", "accel", fmt) if a else None,
    }


def _header(fmt: str, g: list[NoiseCoefficients], a: list[NoiseCoefficients]) -> list[str]:
    """The header's comment lines (without the comment marker)."""
    # one comment line whatever a hand-made NoiseCoefficients' method holds
    sources = sorted({" ".join(str(c.method).split()) for c in g + a})
    lines = [
        f"{fmt} IMU noise model written by gyrobias (from: {', '.join(sources)} coefficients)",
        "N, K: IEEE-952 coefficients (two-sided densities); see the convention table of the gyrobias docs (Estimator parameters).",
    ]
    levels = sorted(
        {
            "?"
            if c[s].bound_confidence is None
            else f"{100.0 * (c[s].bound_confidence or 0.0):.4g} %"
            for c in g + a
            for s in ("N", "K")
            if c[s].bounded
        }
    )
    if levels:
        lines.append(
            f"Values marked UPPER BOUND are terms the log does not show: the largest value "
            f"consistent with it (one-sided confidence {', '.join(levels)}), written in place of "
            "an estimate."
        )
    return lines


def _kalibr_like(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], fmt: str
) -> list[_yaml.Item]:
    v = _densities(g, a, fmt)
    lines: list[_yaml.Item] = []
    miss_a = _NOT_MEASURED if not a else ""
    miss_g = _NOT_MEASURED_GYRO if not g else ""
    lines.append(
        _yaml_pair(
            "accelerometer_noise_density",
            v["aN"],
            f"m/s^2/sqrt(Hz), continuous{_axes_note(a)}",
            miss_a,
        )
    )
    lines.append(
        _yaml_pair(
            "accelerometer_random_walk",
            v["aK"],
            f"m/s^3/sqrt(Hz), continuous{_axes_note(a)}",
            miss_a,
        )
    )
    lines.append(
        _yaml_pair(
            "gyroscope_noise_density",
            v["gN"],
            f"rad/s/sqrt(Hz), continuous{_axes_note(g)}",
            miss_g,
        )
    )
    lines.append(
        _yaml_pair(
            "gyroscope_random_walk",
            v["gK"],
            f"rad/s^2/sqrt(Hz), continuous{_axes_note(g)}",
            miss_g,
        )
    )
    return lines


def _render_kalibr(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], rate: float | None, rostopic: str
) -> str:
    f = _rate(rate, g + a, "kalibr", True)
    assert f is not None
    header = _header("Kalibr", g, a)
    header.append(
        "Kalibr discretises with update_rate: sigma_d = sigma*sqrt(rate), sigma_bd = sigma_b/sqrt(rate)."
    )
    items = _kalibr_like(g, a, "kalibr")
    items.append(_yaml.Pair("rostopic", rostopic))
    items.append(_yaml.Pair("update_rate", f, f"{f:.6g}", "Hz"))
    return _yaml.dump(items, header=header)


def _identity(key: str, n: int, zero: bool = False) -> _yaml.Matrix:
    rows = [["0.0" if zero or i != j else "1.0" for j in range(n)] for i in range(n)]
    return _yaml.Matrix(key, rows)


def _render_openvins(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], rate: float | None, rostopic: str
) -> str:
    f = _rate(rate, g + a, "openvins", True)
    assert f is not None
    header = _header("OpenVINS kalibr_imu_chain.yaml", g, a)
    header.append("Continuous-time densities (OpenVINS discretises them with the IMU period).")
    header.append(
        "Intrinsics below are identity/zero: replace them with a calibration if you have one."
    )
    imu: list[_yaml.Item] = [_identity("T_i_b", 4)]
    imu += _kalibr_like(g, a, "openvins")
    imu.append(_yaml.Pair("rostopic", rostopic))
    imu.append(_yaml.Pair("time_offset", 0.0, "0.0"))
    imu.append(_yaml.Pair("update_rate", f, f"{f:.6g}"))
    imu.append(_yaml.Pair("model", "kalibr", quoted=True))
    for key in ("Tw", "R_IMUtoGYRO", "Ta", "R_IMUtoACC"):
        imu.append(_identity(key, 3))
    imu.append(_identity("Tg", 3, zero=True))
    return _yaml.dump([_yaml.Block("imu0", imu)], header=header, directive="%YAML:1.0")


def _render_vins(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], rate: float | None, rostopic: str
) -> str:
    f = _rate(rate, g + a, "vins", True)
    assert f is not None
    v = _densities(g, a, "vins")

    def white(x: float | None) -> float | None:  # N·√rate: the core's discretisation
        if x is None:
            return None
        v = float(_core.noise.discrete_white(float(x), None, f)[0])
        return _Bounded(v, x.note) if isinstance(x, _Bounded) else v  # keeps the bound's mark

    def walk(x: float | None) -> float | None:  # K/√rate
        if x is None:
            return None
        v = float(_core.noise.discrete_random_walk(float(x), None, f)[0])
        return _Bounded(v, x.note) if isinstance(x, _Bounded) else v

    header = _header("VINS-Mono/VINS-Fusion", g, a)
    header.append(f"Discrete-time values at the IMU rate {f:.6g} Hz (VINS-Mono issue #280):")
    header.append(
        "  *_n = N*sqrt(rate) (per-sample noise std), *_w = K/sqrt(rate) (per-step bias random-walk std)."
    )
    header.append(
        "Merge these keys into your VINS config (g_norm and the extrinsics are not noise parameters)."
    )
    miss_a = _NOT_MEASURED if not a else ""
    miss_g = _NOT_MEASURED_GYRO if not g else ""
    items = [
        _yaml_pair("acc_n", white(v["aN"]), "m/s^2, discrete", miss_a),
        _yaml_pair("gyr_n", white(v["gN"]), "rad/s, discrete", miss_g),
        _yaml_pair("acc_w", walk(v["aK"]), "m/s^2 per step, discrete", miss_a),
        _yaml_pair("gyr_w", walk(v["gK"]), "rad/s per step, discrete", miss_g),
    ]
    return _yaml.dump(items, header=header, directive="%YAML:1.0")


def _render_orbslam3(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], rate: float | None, rostopic: str
) -> str:
    f = _rate(rate, g + a, "orbslam3", True)
    assert f is not None
    v = _densities(g, a, "orbslam3")
    header = _header("ORB-SLAM3", g, a)
    header.append(
        "Continuous-time densities (ORB-SLAM3 discretises them with sqrt(IMU.Frequency))."
    )
    header.append(
        "Merge these keys into your ORB-SLAM3 settings file (IMU.T_b_c1 is not a noise parameter)."
    )
    miss_a = _NOT_MEASURED if not a else ""
    miss_g = _NOT_MEASURED_GYRO if not g else ""
    items = [
        _yaml_pair("IMU.NoiseGyro", v["gN"], "rad/s/sqrt(Hz)", miss_g),
        _yaml_pair("IMU.NoiseAcc", v["aN"], "m/s^2/sqrt(Hz)", miss_a),
        _yaml_pair("IMU.GyroWalk", v["gK"], "rad/s^2/sqrt(Hz)", miss_g),
        _yaml_pair("IMU.AccWalk", v["aK"], "m/s^3/sqrt(Hz)", miss_a),
        _yaml.Pair("IMU.Frequency", f, f"{f:.6g}", "Hz"),
    ]
    return _yaml.dump(items, header=header, directive="%YAML:1.0")


def _render_liosam(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], rate: float | None, rostopic: str
) -> str:
    v = _densities(g, a, "liosam")
    header = _header("LIO-SAM params.yaml", g, a)
    header.append(
        "Continuous-time densities (GTSAM preintegration covariances; bias sigmas scaled by sqrt(dt))."
    )
    header.append(
        "Merge into config/params.yaml (imuGravity, imuRPYWeight and extrinsics are not noise parameters)."
    )
    miss_a = _NOT_MEASURED if not a else ""
    miss_g = _NOT_MEASURED_GYRO if not g else ""
    items = [
        _yaml_pair("imuAccNoise", v["aN"], "m/s^2/sqrt(Hz)", miss_a),
        _yaml_pair("imuGyrNoise", v["gN"], "rad/s/sqrt(Hz)", miss_g),
        _yaml_pair("imuAccBiasN", v["aK"], "m/s^3/sqrt(Hz)", miss_a),
        _yaml_pair("imuGyrBiasN", v["gK"], "rad/s^2/sqrt(Hz)", miss_g),
    ]
    return _yaml.dump([_yaml.Block("lio_sam", items)], header=header)


def _gauss_markov(group: list[NoiseCoefficients]) -> list[Any]:
    """Gauss–Markov terms of the first axis that has them (empty when none)."""
    for c in group:
        terms = c.gauss_markov
        if terms:
            return list(terms)
    return []


def _render_matlab(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], rate: float | None, rostopic: str
) -> str:
    f = _rate(rate, g + a, "matlab", False)
    lines = [f"% {_comment(h)}" for h in _header("MATLAB imuSensor", g, a)]
    lines.append(
        "% NoiseDensity = N, BiasInstability = B, RandomWalk = K (MathWorks' Allan-variance example)."
    )
    args = ["'accel-gyro'"]
    if f is not None:
        args.append(f"'SampleRate', {f:.10g}")
    for kind, group, name, ctor in (
        ("gyro", g, "gyro", "gyroparams"),
        ("accel", a, "accel", "accelparams"),
    ):
        if not group:
            lines.append(f"% {ctor}: no {kind} coefficients given (ideal {kind})")
            continue
        density = _value(group, "N", kind, "matlab") or 0.0
        props = [f"'NoiseDensity', {_fmt(density)}"]
        if isinstance(density, _Bounded):
            lines.append(f"% {kind} NoiseDensity: {_comment(density.note)}")
        gm = _gauss_markov(group)
        # With a Gauss–Markov bias and no identified B, the GM term is imuSensor's bias
        # instability (below), not B's upper bound.
        b_identified = all(c.B.value is not None for c in group)
        for symbol, prop in (("B", "BiasInstability"), ("K", "RandomWalk")):
            value = _value(group, symbol, kind, None)
            if symbol == "B" and gm and f is not None and not b_identified:
                continue
            if value is None:
                lines.append(f"% {kind} {prop}: not identified, left at 0")
            else:
                props.append(f"'{prop}', {_fmt(value)}")
                if isinstance(value, _Bounded):
                    lines.append(f"% {kind} {prop}: {_comment(value.note)}")
        if gm and f is not None and not b_identified:
            # First-order Gauss–Markov bias as imuSensor's bias-instability filter.
            t = gm[0]
            sigma = float(t.sigma.to(_SI[kind]["B"]).value)
            tau_c = float(t.correlation_time.to("s").value)
            (phi, _), (drive, _) = _core.noise.discrete_gauss_markov(sigma, None, tau_c, None, f)
            lines.append(
                f"% Gauss-Markov bias: sigma = {sigma:.6e} {_SI[kind]['B']}, correlation time {tau_c:.6g} s,"
                f" phi = exp(-dt/tau_c) = {phi:.9f}"
            )
            props.append(f"'BiasInstability', {_fmt(drive)}")
            props.append(
                f"'BiasInstabilityCoefficients', struct('Numerator', 1, 'Denominator', [1 {-phi:.12g}])"
            )
        lines.append(f"{name} = {ctor}( ...")
        lines.append("    " + ", ...\n    ".join(props) + ");")
        unit = _SI[kind]["rate"]
        lines.append(
            f"% units: NoiseDensity ({unit})/sqrt(Hz), BiasInstability {unit}, RandomWalk ({unit})*sqrt(Hz)"
        )
        args.append(f"'{'Gyroscope' if kind == 'gyro' else 'Accelerometer'}', {name}")
    lines.append(f"imu = imuSensor({', '.join(args)});")
    return "\n".join(lines) + "\n"


def _clean(value: Any) -> Any:
    """JSON-safe copy: non-finite floats become None."""
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, Mapping):
        return {str(k): _clean(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_clean(v) for v in value]
    return value


def _render_json(
    g: list[NoiseCoefficients], a: list[NoiseCoefficients], rate: float | None, rostopic: str
) -> str:
    f = _rate(rate, g + a, "json", False)
    doc: dict[str, Any] = {
        "generator": "gyrobias",
        "conventions": {
            "model": "sigma^2(tau) = 3Q^2/tau^2 + N^2/tau + (0.664282 B)^2 + K^2 tau/3 + R^2 tau^2/2",
            "psd": "N and K are two-sided (IEEE 952); a one-sided datasheet density is sqrt(2)*N",
            "uncertainty": "standard (1 sigma); null when unknown (datasheet, conservative)",
            "multiple_axes": "estimator values are the largest over the axes",
        },
        "rate_hz": f,
        "gyro": [c.to_dict() for c in g],
        "accel": [c.to_dict() for c in a],
        "estimator_values": {},
    }
    for kind, group in (("gyro", g), ("accel", a)):
        if not group:
            continue
        si = {}
        for symbol in ("N", "B", "K"):
            value = _value(group, symbol, kind, None)
            entry: dict[str, Any] = {
                "value": None if value is None else float(value),
                "unit": _SI[kind][symbol],
                "upper_bound": isinstance(value, _Bounded),
            }
            if isinstance(value, _Bounded):
                entry["note"] = value.note
            si[symbol] = entry
        doc["estimator_values"][kind] = si
        if f is not None:
            doc.setdefault("discrete", {})[kind] = [
                d.to_dict() for d in (discrete(c, f) for c in group)
            ]
        gm = []
        for c in group:
            for t in c.gauss_markov:
                gm.append(
                    {
                        "axis": c.axis,
                        "sigma": t.sigma.to_dict(),
                        "correlation_time": t.correlation_time.to_dict(),
                    }
                )
        if gm:
            doc.setdefault("gauss_markov", {})[kind] = gm
    return json.dumps(_clean(doc), indent=2, allow_nan=False) + "\n"


_RENDER = {
    "kalibr": _render_kalibr,
    "openvins": _render_openvins,
    "vins": _render_vins,
    "orbslam3": _render_orbslam3,
    "liosam": _render_liosam,
    "matlab": _render_matlab,
    "json": _render_json,
}


def export(
    gyro: NoiseCoefficients | Sequence[NoiseCoefficients] | None,
    fmt: str,
    path: str | os.PathLike[str] | None = None,
    *,
    accel: NoiseCoefficients | Sequence[NoiseCoefficients] | None = None,
    rate: float | None = None,
    rostopic: str = "/imu0",
    strict: bool = False,
) -> str:
    """Render (and optionally write) an estimator parameter file.

    Parameters
    ----------
    gyro : NoiseCoefficients or sequence of them, or None
        Gyroscope coefficients (one per axis; each value is the largest over the axes). An
        accelerometer set passed here without ``accel`` is taken as ``accel``.
    fmt : {"kalibr", "openvins", "vins", "orbslam3", "liosam", "matlab", "json"}
        Target format (see the module table for keys, units and time conventions).
    path : path-like, optional
        Output file, written atomically (temporary file beside it, then ``os.replace``).
    accel : NoiseCoefficients or sequence of them, optional
        Accelerometer coefficients. Without them the accelerometer keys are written as
        comments saying so (the estimator then refuses the file instead of using made-up values).
    rate : float, optional
        IMU rate in Hz; default: the coefficients' sample rate. Required by kalibr, openvins,
        vins and orbslam3 when the coefficients have none (datasheet values).
    rostopic : str
        Topic written by kalibr and openvins.
    strict : bool
        Refuse (ValueError) to write any term (N, K; B for matlab and json) that the data only
        bound from above.
        Default: write the bound (:attr:`gyrobias.noise.Term.upper_bound`) in its place, marked
        ``UPPER BOUND, not an estimate`` in a comment on its line (MATLAB: a ``%`` line; JSON:
        ``"upper_bound": true`` and a ``"note"``) and in the file's header.

    Returns
    -------
    str
        The file's text.

    Raises
    ------
    ValueError
        Unknown format, missing rate, coefficients without units or of the wrong sensor, a
        term the format needs (N, K; N for matlab) that was neither identified nor bounded, or
        (``strict=True``) only bounded — the message names the sensor and the term.

    Notes
    -----
    Several axes: each value is the largest over the axes, an axis' upper bound included (the
    value is marked as a bound when a bound is the largest). A term the log does not show is
    written as its upper bound rather than zero or a refusal: the filter then assumes at most
    as much noise as the data allow, which over- rather than under-states it.

    Examples
    --------
    >>> import gyrobias
    >>> ds = gyrobias.noise.from_datasheet(arw="0.3 deg/sqrt(h)", rrw="3 deg/h^1.5",
    ...                                   vrw="0.05 m/s/sqrt(h)", accel_random_walk="1e-4 m/s^2.5")
    >>> text = gyrobias.exports.export(ds.gyro, "orbslam3", accel=ds.accel, rate=200)
    >>> [line.split(":")[0] for line in text.splitlines() if line.startswith("IMU.")]
    ['IMU.NoiseGyro', 'IMU.NoiseAcc', 'IMU.GyroWalk', 'IMU.AccWalk', 'IMU.Frequency']
    """
    fmt = choice("fmt", fmt, FORMATS)
    if path is not None:
        path = checked_path("path", path)
    ros_topic("rostopic", rostopic)  # written verbatim into YAML: a ROS name, nothing else
    if rate is not None:
        # every format's numeric option checked here, once, whether the format writes it or
        # not (LIO-SAM has no rate key and wrote rate=nan without a word): the core's check
        rate = _core.noise.discrete_rate(real("rate", rate))
    if not isinstance(strict, bool):
        raise TypeError(f"strict must be a bool, got {type(strict).__name__}")
    g, a = _split(gyro, accel)
    token = _STRICT.set(strict)
    try:
        text = _RENDER[fmt](g, a, rate, rostopic)
    finally:
        _STRICT.reset(token)
    if path is not None:
        atomic_write(path, text)
    return text


def export_all(
    gyro: NoiseCoefficients | Sequence[NoiseCoefficients] | None,
    directory: str | os.PathLike[str] | None = None,
    *,
    accel: NoiseCoefficients | Sequence[NoiseCoefficients] | None = None,
    rate: float | None = None,
    rostopic: str = "/imu0",
    strict: bool = False,
) -> dict[str, str]:
    """Every format at once: ``{fmt: text}``; files named by :data:`DEFAULT_FILENAMES`.

    All formats are rendered before any file is written, so an error (e.g. a missing random
    walk, or a bounded one with ``strict=True``) leaves ``directory`` unchanged.
    """
    out = None if directory is None else checked_path("directory", directory, "a directory path")
    texts = {
        fmt: export(gyro, fmt, accel=accel, rate=rate, rostopic=rostopic, strict=strict)
        for fmt in FORMATS
    }
    if out is not None:
        out.mkdir(parents=True, exist_ok=True)
        for fmt, text in texts.items():
            atomic_write(out / DEFAULT_FILENAMES[fmt], text)
    return texts
