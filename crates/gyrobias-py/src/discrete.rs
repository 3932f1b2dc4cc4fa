//! Bindings of `gyrocore::noise::discrete` (registered in `gyrobias._core.noise`).

use gyrocore::noise::discrete::{self, BiasReading, Density, Estimate};
use pyo3::prelude::*;

use crate::error::core;

/// A value and its optional uncertainty.
type Pair = (f64, Option<f64>);

fn pair(e: Estimate) -> Pair {
    (e.value, e.uncertainty)
}

/// The filter rate, checked (`gyrocore::noise::discrete::rate`).
#[pyfunction]
#[pyo3(signature = (rate))]
fn discrete_rate(rate: f64) -> PyResult<f64> {
    core(discrete::rate(rate))
}

/// `σ_white = N·√rate` with its uncertainty (`gyrocore::noise::discrete::white`).
#[pyfunction]
#[pyo3(signature = (n, uncertainty, rate))]
fn discrete_white(n: f64, uncertainty: Option<f64>, rate: f64) -> PyResult<Pair> {
    core(discrete::white(n, uncertainty, rate)).map(pair)
}

/// `σ_walk = K/√rate` with its uncertainty (`gyrocore::noise::discrete::random_walk`).
#[pyfunction]
#[pyo3(signature = (k, uncertainty, rate))]
fn discrete_random_walk(k: f64, uncertainty: Option<f64>, rate: f64) -> PyResult<Pair> {
    core(discrete::random_walk(k, uncertainty, rate)).map(pair)
}

/// `(φ, u(φ)), (σ_drive, u(σ_drive))` of a Gauss–Markov term
/// (`gyrocore::noise::discrete::gauss_markov`).
#[pyfunction]
#[pyo3(signature = (sigma, sigma_uncertainty, tau, tau_uncertainty, rate))]
fn discrete_gauss_markov(
    sigma: f64,
    sigma_uncertainty: Option<f64>,
    tau: f64,
    tau_uncertainty: Option<f64>,
    rate: f64,
) -> PyResult<(Pair, Pair)> {
    let g = core(discrete::gauss_markov(
        sigma,
        sigma_uncertainty,
        tau,
        tau_uncertainty,
        rate,
    ))?;
    Ok((pair(g.phi), pair(g.driving_sigma)))
}

/// The IEEE coefficient from a datasheet value and the conversion's name
/// (`gyrocore::noise::discrete::datasheet_coefficient`).
#[pyfunction]
#[pyo3(signature = (value, unit_factor, symbol, per_root_hz, density, bias_instability_is))]
fn datasheet_coefficient(
    value: f64,
    unit_factor: f64,
    symbol: &str,
    per_root_hz: bool,
    density: &str,
    bias_instability_is: &str,
) -> PyResult<(f64, &'static str)> {
    let density = core(Density::parse(density))?;
    let bias = core(BiasReading::parse(bias_instability_is))?;
    let (v, c) = core(discrete::datasheet_coefficient(
        value,
        unit_factor,
        symbol,
        per_root_hz,
        density,
        bias,
    ))?;
    Ok((v, c.name()))
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(discrete_rate, m)?)?;
    m.add_function(wrap_pyfunction!(discrete_white, m)?)?;
    m.add_function(wrap_pyfunction!(discrete_random_walk, m)?)?;
    m.add_function(wrap_pyfunction!(discrete_gauss_markov, m)?)?;
    m.add_function(wrap_pyfunction!(datasheet_coefficient, m)?)
}
