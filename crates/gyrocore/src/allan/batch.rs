//! Allan analysis of a batch of units in one call.
//!
//! A fleet of sensors gives one record per unit, all of the same length: a row-major buffer of
//! shape `(units, n, axes)`. [`analyse_batch`] analyses every column of every unit with the same
//! [`Config`], units in parallel. Scratch memory (the N + 1 angle samples of each column being
//! analysed) lives in a small pool of [`Workspace`]s that finished units hand back to the next
//! ones, so the batch faults in about `threads × axes` N-sized buffers in total instead of one
//! per unit and axis (on a fresh 80 MB buffer the page faults cost as much as the kernel).
//!
//! Each column is computed by exactly the code `analyse_column` runs for a single call and
//! nothing in it depends on the workspace's previous contents, on the other units or on the
//! thread that runs it: a batch gives the per-unit results bit for bit.

use std::sync::Mutex;

use rayon::prelude::*;

use super::{AllanAnalysis, Config, Progress, Workspace, analyse_columns, columns_of, locate};
use crate::{Error, Result};

/// Analyses `n_units` records of `data.len() / n_units` rows × `n_axes` columns each (row-major
/// `(units, n, axes)`), returning `[unit][axis]`.
///
/// Errors name the unit (and row and column for non-finite values); when several units fail,
/// the first one in unit order is reported.
pub fn analyse_batch(
    data: &[f64],
    n_units: usize,
    n_axes: usize,
    config: &Config,
    progress: &Progress<'_>,
) -> Result<Vec<Vec<AllanAnalysis>>> {
    config.validate()?;
    if n_units == 0 || n_axes == 0 {
        return Err(Error::ShapeMismatch {
            name: "data",
            reason: format!(
                "a batch needs at least one unit and one axis, got ({n_units} units, {n_axes} axes)"
            ),
        });
    }
    let per_unit = data.len() / n_units;
    if data.len() % n_units != 0 || per_unit % n_axes != 0 {
        return Err(Error::ShapeMismatch {
            name: "data",
            reason: format!(
                "{} values do not form {n_units} units of rows of {n_axes} axes",
                data.len()
            ),
        });
    }
    let n = per_unit / n_axes;
    progress.add_total(n_units as f64 * n_axes as f64 * config.work(n));
    progress.start();
    let pool: Mutex<Vec<Vec<Workspace>>> = Mutex::new(Vec::new());
    let results: Vec<Result<Vec<AllanAnalysis>>> = data
        .par_chunks(per_unit)
        .with_max_len(1)
        .enumerate()
        .map(|(unit, chunk)| {
            progress.check()?;
            let columns = columns_of(chunk, n_axes)?;
            let taken = pool
                .lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .pop();
            let mut workspaces =
                taken.unwrap_or_else(|| (0..n_axes).map(|_| Workspace::new()).collect());
            let out = analyse_columns(&columns, config, &mut workspaces, progress)
                .map_err(|(axis, e)| locate(e, Some(unit), axis, n_axes));
            pool.lock()
                .unwrap_or_else(std::sync::PoisonError::into_inner)
                .push(workspaces);
            out
        })
        .collect();
    let out = results.into_iter().collect::<Result<Vec<_>>>()?;
    progress.finish();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::super::{DataType, Estimator, Gaps, TauSpec, Taus, analyse_column};
    use super::*;

    /// The single-unit path a batch must reproduce (used by the tests).
    fn per_unit(
        data: &[f64],
        n_units: usize,
        n_axes: usize,
        config: &Config,
    ) -> Vec<Vec<AllanAnalysis>> {
        let per = data.len() / n_units;
        data.chunks(per)
            .map(|chunk| {
                columns_of(chunk, n_axes)
                    .unwrap()
                    .into_iter()
                    .map(|c| {
                        analyse_column(c, config, &mut Workspace::new(), &Progress::none()).unwrap()
                    })
                    .collect()
            })
            .collect()
    }

    fn noise(n: usize, seed: u64) -> Vec<f64> {
        // Normal noise from the core's seeded generator (one PRNG for every test).
        crate::random::normal_vec(n, seed)
    }

    fn config(estimator: Estimator, data_type: DataType) -> Config {
        Config {
            t0: 0.01,
            data_type,
            estimator,
            taus: Taus::Spec(TauSpec::Octave),
            confidence: Some(0.683),
            gaps: Gaps::Error,
        }
    }

    #[test]
    fn batch_equals_per_unit_calls_bit_for_bit() {
        // 5 units × 70 001 rows × 3 axes: crosses the integration and fused-kernel blocks.
        let (units, n, axes) = (5, 70_001, 3);
        let data = noise(units * n * axes, 3);
        for estimator in [
            Estimator::Overlapping,
            Estimator::NonOverlapping,
            Estimator::Modified,
            Estimator::Hadamard,
            Estimator::Total,
        ] {
            for data_type in [DataType::Rate, DataType::Angle] {
                let cfg = config(estimator, data_type);
                let batch = analyse_batch(&data, units, axes, &cfg, &Progress::none()).unwrap();
                assert_eq!(batch, per_unit(&data, units, axes, &cfg), "{estimator:?}");
            }
        }
    }

    #[test]
    fn errors_name_the_unit() {
        let (units, n, axes) = (4, 100, 2);
        let mut data = noise(units * n * axes, 5);
        data[2 * n * axes + 7 * axes + 1] = f64::NAN;
        let cfg = config(Estimator::Overlapping, DataType::Rate);
        let err = analyse_batch(&data, units, axes, &cfg, &Progress::none()).unwrap_err();
        assert_eq!(
            err.to_string(),
            "invalid data: non-finite value (NaN or inf) at unit 2, row 7, column 1"
        );
        assert!(analyse_batch(&data[..7], units, axes, &cfg, &Progress::none()).is_err());
    }
}
