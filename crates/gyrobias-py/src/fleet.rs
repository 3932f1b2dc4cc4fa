//! Bindings of `gyrocore::fleet`.

use gyrocore::fleet::{self, Spread, SpreadTest};
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;

use crate::array::c_order;
use crate::error::core;

/// Robust z-scores of a fleet's values (`gyrocore::fleet::robust_z`).
#[pyfunction]
#[pyo3(signature = (values, uncertainties))]
#[allow(clippy::needless_pass_by_value)]
fn robust_z<'py>(
    py: Python<'py>,
    values: PyReadonlyArray1<'py, f64>,
    uncertainties: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<f64>>> {
    let x = c_order(&values);
    let u = c_order(&uncertainties);
    let z = core(py.detach(|| fleet::robust_z(&x, &u)))?;
    Ok(z.into_pyarray(py))
}

/// The statistics of one coefficient over a fleet (`gyrocore::fleet::Spread`), built once by
/// [`spread`]; read-only.
#[pyclass(name = "Spread", module = "gyrobias._core.fleet", frozen)]
struct PySpread {
    inner: Spread,
}

#[pymethods]
impl PySpread {
    /// Median of the values.
    #[getter]
    fn median(&self) -> f64 {
        self.inner.median
    }
    /// Scaled MAD.
    #[getter]
    fn spread(&self) -> f64 {
        self.inner.spread
    }
    /// RMS of the finite positive uncertainties (NaN if none).
    #[getter]
    fn mean_uncertainty(&self) -> f64 {
        self.inner.mean_uncertainty
    }
    /// `√max(spread² − mean_uncertainty², 0)`.
    #[getter]
    fn intrinsic_spread(&self) -> f64 {
        self.inner.intrinsic_spread
    }
    /// Homogeneity χ².
    #[getter]
    fn chi2(&self) -> f64 {
        self.inner.chi2
    }
    /// Degrees of freedom (`None` without a test).
    #[getter]
    fn dof(&self) -> Option<usize> {
        self.inner.dof
    }
    /// Birge ratio `√(χ²/dof)`.
    #[getter]
    fn birge_ratio(&self) -> f64 {
        self.inner.birge_ratio
    }
    /// `P(χ²_dof > χ²)`.
    #[getter]
    fn p_value(&self) -> f64 {
        self.inner.p_value
    }
    /// Whether the spread is real (`None` without a test).
    #[getter]
    fn real(&self) -> Option<bool> {
        self.inner.real
    }
}

/// The levels of the homogeneity test (`gyrocore::fleet::SpreadTest`), checked by the core
/// when built; read-only.
#[pyclass(name = "SpreadTest", module = "gyrobias._core.fleet", frozen)]
struct PySpreadTest {
    inner: SpreadTest,
}

#[pymethods]
impl PySpreadTest {
    #[new]
    #[pyo3(signature = (alpha, min_ratio))]
    fn new(alpha: f64, min_ratio: f64) -> PyResult<Self> {
        Ok(Self {
            inner: core(SpreadTest::new(alpha, min_ratio))?,
        })
    }
    /// Significance level, in (0, 1).
    #[getter]
    fn alpha(&self) -> f64 {
        self.inner.alpha()
    }
    /// Smallest Birge ratio of a real spread.
    #[getter]
    fn min_ratio(&self) -> f64 {
        self.inner.min_ratio()
    }
}

/// Median, spread and homogeneity test of one coefficient (`gyrocore::fleet::spread`).
#[pyfunction]
#[pyo3(signature = (values, uncertainties, test))]
#[allow(clippy::needless_pass_by_value)]
fn spread(
    py: Python<'_>,
    values: PyReadonlyArray1<'_, f64>,
    uncertainties: PyReadonlyArray1<'_, f64>,
    test: PyRef<'_, PySpreadTest>,
) -> PyResult<PySpread> {
    let x = c_order(&values);
    let u = c_order(&uncertainties);
    let levels = test.inner;
    let inner = core(py.detach(|| fleet::spread(&x, &u, levels)))?;
    Ok(PySpread { inner })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("MAD_TO_SD", fleet::MAD_TO_SD)?;
    m.add_class::<PySpread>()?;
    m.add_class::<PySpreadTest>()?;
    m.add_function(wrap_pyfunction!(robust_z, m)?)?;
    m.add_function(wrap_pyfunction!(spread, m)?)
}
